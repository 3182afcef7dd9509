"""The batched numba kernels equal the scalar reference engine bit for bit (docs/reference/rules.md)."""

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from soccer_lab.fuzzy.batched import NO_ACTION, Scratch, compile_rulebases, decide, decide_batch, infer_batch
from soccer_lab.fuzzy.engine import Engine
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

VOCABULARY = Vocabulary.default()
INPUT_VARIABLES = [VOCABULARY.variables[kind] for kind in VOCABULARY.inputs.values()]
OBJECT_OF_INPUT = [next(o for o, kinds in VOCABULARY.objects.items() if name in kinds.values())
                   for name in VOCABULARY.input_names]


def draw_input(rng, variable):
    """Mostly uniform (a little outside the universe), sometimes exactly on a term vertex."""
    if rng.random() < 0.3:
        term = variable.terms[rng.integers(len(variable.terms))]
        return float(term.parameters[rng.integers(4)])
    span = variable.maximum - variable.minimum
    return float(rng.uniform(variable.minimum - 0.05 * span, variable.maximum + 0.05 * span))


def scenario(seed):
    rng = np.random.default_rng(seed)
    players = int(rng.integers(1, 7))
    rulebases = [random_rulebase(rng, VOCABULARY, rules=int(rng.integers(1, 12))) for _ in range(players)]
    rows = int(rng.integers(1, 40))
    inputs = np.array([[draw_input(rng, v) for v in INPUT_VARIABLES] for _ in range(rows)])
    visible = rng.random((rows, len(VOCABULARY.object_names))) < 0.8
    owner = rng.integers(0, players, rows)
    return rulebases, inputs, visible, owner


def scalar_inputs(row, seen):
    return {name: (float(row[j]) if seen[VOCABULARY.object_names.index(OBJECT_OF_INPUT[j])] else None)
            for j, name in enumerate(VOCABULARY.input_names)}


@given(st.integers(0, 2**32 - 1))
def test_infer_batch_equals_scalar_exactly(seed):
    rulebases, inputs, visible, owner = scenario(seed)
    batch = infer_batch(compile_rulebases(rulebases, VOCABULARY), inputs, visible, owner)
    actions = VOCABULARY.action_names
    for i in range(len(inputs)):
        rulebase = rulebases[owner[i]]
        expected = Engine(rulebase, VOCABULARY).infer(scalar_inputs(inputs[i], visible[i]))
        assert batch.strengths[i, : len(rulebase)].tolist() == expected.strengths
        fired = {a.action: a for a in expected.fired}
        assert {actions[a] for a in np.flatnonzero(batch.supports[i] > 0)} == set(fired)
        for name, out in fired.items():
            a = actions.index(name)
            assert batch.supports[i, a] == out.support
            assert batch.first_rules[i, a] == out.first_rule
            for k, output in enumerate(VOCABULARY.output_names):
                if output in out.parameters:
                    assert batch.values[i, a, k] == out.parameters[output]
        selected = NO_ACTION if expected.selected is None else actions.index(expected.selected.action)
        assert batch.selected[i] == selected


@given(st.integers(0, 2**32 - 1))
def test_decide_kernel_equals_scalar_exactly(seed):
    rulebases, inputs, visible, owner = scenario(seed)
    compiled = compile_rulebases(rulebases, VOCABULARY)
    scratch = Scratch.for_rulebases(compiled)
    strengths = np.empty(max(compiled.max_rules, 1))
    outputs = np.empty(compiled.tables.outputs)
    for i in range(len(inputs)):
        action, value = decide(owner[i], inputs[i], visible[i], compiled, scratch, strengths, outputs)
        assert strengths[: len(rulebases[owner[i]])].tolist() == Engine(rulebases[owner[i]], VOCABULARY).infer(
            scalar_inputs(inputs[i], visible[i])).strengths
        expected = Engine(rulebases[owner[i]], VOCABULARY).infer(scalar_inputs(inputs[i], visible[i])).selected
        if expected is None:
            assert (action, value) == (NO_ACTION, 0.0)
            assert outputs.tolist() == [VOCABULARY.output_default(o) for o in VOCABULARY.output_names]
        else:
            assert (VOCABULARY.action_names[action], value) == (expected.action, expected.support)
            for k, output in enumerate(VOCABULARY.output_names):
                assert outputs[k] == expected.parameters.get(output, VOCABULARY.output_default(output))


def test_many_players_in_one_batch_each_use_their_own_rulebase():
    rulebases = [random_rulebase(np.random.default_rng(seed), VOCABULARY) for seed in range(50)]
    rng = np.random.default_rng(7)
    inputs = np.array([[draw_input(rng, v) for v in INPUT_VARIABLES] for _ in range(50)])
    visible = np.ones((50, 2), dtype=bool)
    batch = infer_batch(compile_rulebases(rulebases, VOCABULARY), inputs, visible)
    for i, rulebase in enumerate(rulebases):
        expected = Engine(rulebase, VOCABULARY).infer(scalar_inputs(inputs[i], visible[i]))
        assert batch.strengths[i, : len(rulebase)].tolist() == expected.strengths


@given(st.integers(0, 2**32 - 1))
def test_decide_batch_equals_decide_row_by_row(seed):
    rulebases, inputs, visible, owner = scenario(seed)
    compiled = compile_rulebases(rulebases, VOCABULARY)
    actions, supports, outputs = decide_batch(compiled, inputs, visible, owner)
    batch = infer_batch(compiled, inputs, visible, owner)
    assert actions.tolist() == batch.selected.tolist()
    for i, a in enumerate(actions):
        if a == NO_ACTION:
            assert supports[i] == 0.0
            continue
        assert supports[i] == batch.supports[i, a]
        used = compiled.tables.action_uses[a]
        assert outputs[i, used].tolist() == batch.values[i, a, used].tolist()
        assert outputs[i, ~used].tolist() == compiled.tables.output_default[~used].tolist()
