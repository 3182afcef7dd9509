"""Every exact simplification step decides exactly as the original rulebase: the same selected action,
support and parameters, bit for bit, on the scalar engine and on the batched kernels, on random
inputs that favour term vertices, their float neighbours and unseen objects."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from soccer_lab.fuzzy.batched import compile_rulebases, decide_batch, infer_batch
from soccer_lab.fuzzy.engine import Engine
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.random_rulebase import random_rule, random_rulebase
from soccer_lab.fuzzy.rule import AND, OR, Rule, Rulebase
from soccer_lab.fuzzy.simplify import EXACT_STEPS, Context, Entry, premise_count, simplify_exactly, unused_fields
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.genes import GeneSpace
from soccer_lab.ga.initialisation import random_chromosome

VOCABULARY = Vocabulary.default()
INPUT_VARIABLES = [VOCABULARY.variables[kind] for kind in VOCABULARY.inputs.values()]
OBJECT_OF_INPUT = [VOCABULARY.object_names.index(next(o for o, kinds in VOCABULARY.objects.items()
                                                     if name in kinds.values())) for name in VOCABULARY.input_names]
ROWS = 200
SCALAR_ROWS = 50  # the scalar engine is slow; it sees the first rows, the kernels all of them
SEEDS = st.integers(0, 2**32 - 1)
EXAMPLES = settings(max_examples=60)  # x ROWS inputs x every step


# ---- inputs and rulebases -------------------------------------------------------------------------


def draw_input(rng, variable):
    """A term vertex, a float next to one, a crossing point of two terms, or uniform (a little outside)."""
    kind = rng.random()
    vertex = float(variable.terms[rng.integers(len(variable.terms))].parameters[rng.integers(4)])
    if kind < 0.25:
        return vertex
    if kind < 0.45:
        return float(np.nextafter(vertex, np.inf if rng.random() < 0.5 else -np.inf))
    if kind < 0.6:
        other = float(variable.terms[rng.integers(len(variable.terms))].parameters[rng.integers(4)])
        return (vertex + other) / 2
    span = variable.maximum - variable.minimum
    return float(rng.uniform(variable.minimum - 0.05 * span, variable.maximum + 0.05 * span))


def draw_inputs(rng, rows=ROWS):
    inputs = np.array([[draw_input(rng, v) for v in INPUT_VARIABLES] for _ in range(rows)])
    visible = rng.random((rows, len(VOCABULARY.object_names))) < 0.8
    return inputs, visible


def redundant_rulebase(rng):
    """A random rulebase with redundancy planted in it: copies, repeated and related premises,
    absorbed groups, weaker copies with the same or another action, contradictions."""
    rules = list(random_rulebase(rng, VOCABULARY, rules=int(rng.integers(1, 7))))
    for _ in range(int(rng.integers(1, 9))):
        source = rules[int(rng.integers(len(rules)))]
        planted = _plant(rng, source)
        rules.insert(int(rng.integers(len(rules) + 1)), planted)
    return Rulebase(tuple(rules))


def _plant(rng, rule):
    kind = int(rng.integers(7))
    premises, connectors, consequent = list(rule.premises), list(rule.connectors), rule.consequent
    connector = (AND, OR)[int(rng.integers(2))]
    other = random_rule(rng, VOCABULARY).consequent
    if kind == 0:  # a copy, perhaps with other unused fields
        fields = {o: (getattr(other, o) if o not in VOCABULARY.actions[consequent.action] else getattr(consequent, o))
                  for o in VOCABULARY.output_names}
        return Rule(rule.premises, rule.connectors, type(consequent)(consequent.action, **fields))
    if kind == 1:  # a premise repeated
        i = int(rng.integers(len(premises)))
        return Rule(tuple(premises + [premises[i]]), tuple(connectors + [connector]), consequent)
    if kind == 2:  # a premise about the same object and variable as one already there
        base = premises[int(rng.integers(len(premises)))]
        variable = VOCABULARY.variables[VOCABULARY.premise_variable(base.term)]
        related = type(base)(base.object, variable.term_names[int(rng.integers(len(variable.terms)))],
                             bool(rng.random() < 0.5))
        return Rule(tuple(premises + [related]), tuple(connectors + [connector]), consequent)
    if kind == 3:  # absorption: the rule's own first premise again, under the other connector
        return Rule(tuple(premises + [premises[0]]), tuple(connectors + [connector]), consequent)
    if kind == 4:  # weaker copy with another action (may be dominated)
        extra = random_rule(rng, VOCABULARY).premises[0]
        return Rule(tuple(premises + [extra]), tuple(connectors + [AND]), other)
    if kind == 5:  # weaker copy with the same action, perhaps other terms
        extra = random_rule(rng, VOCABULARY).premises[0]
        return Rule(tuple(premises + [extra]), tuple(connectors + [AND]),
                    consequent if rng.random() < 0.5 else type(consequent)(consequent.action, other.direction,
                                                                            other.power))
    obj = VOCABULARY.object_names[int(rng.integers(len(VOCABULARY.object_names)))]  # a contradiction
    return Rule((type(premises[0])(obj, "AT"), type(premises[0])(obj, "FAR")) + tuple(premises),
                (AND, connector) + tuple(connectors), consequent)


def decoded_chromosome(seed):
    """What the GA starts from: a random messy chromosome of up to 64 genes, decoded."""
    rng = np.random.default_rng(seed)
    codec = ChromosomeCodec(VOCABULARY)
    return codec.decode(random_chromosome(GeneSpace.from_vocabulary(VOCABULARY), 64, 0.25, rng))


# ---- the check ------------------------------------------------------------------------------------


def scalar_inputs(row, seen):
    return {name: (float(row[j]) if seen[OBJECT_OF_INPUT[j]] else None) for j, name in enumerate(VOCABULARY.input_names)}


def scalar_decisions(rulebase, inputs, visible):
    engine = Engine(rulebase, VOCABULARY)
    decisions = []
    for row, seen in zip(inputs, visible):
        selected = engine.infer(scalar_inputs(row, seen)).selected
        decisions.append(None if selected is None else (selected.action, selected.support, selected.parameters))
    return decisions


def batched_decisions(rulebase, inputs, visible):
    compiled = compile_rulebases([rulebase], VOCABULARY)
    players = np.zeros(len(inputs), dtype=np.int64)
    actions, supports, outputs = decide_batch(compiled, inputs, visible, players)
    full = infer_batch(compiled, inputs, visible, players)
    chosen = [full.values[i, a].tolist() if a >= 0 else None for i, a in enumerate(full.selected)]
    return actions.tolist(), supports.tolist(), outputs.tolist(), full.selected.tolist(), chosen


def decisions(rulebase, inputs, visible):
    # lists of floats compare with ==, i.e. bit for bit for the values the engines produce (no -0.0);
    # infer_batch's values are NaN for outputs the action does not use: those compare as "unused"
    *rest, chosen = batched_decisions(rulebase, inputs, visible)
    chosen = [None if c is None else ["unused" if v != v else v for v in c] for c in chosen]
    return scalar_decisions(rulebase, inputs[:SCALAR_ROWS], visible[:SCALAR_ROWS]), (*rest, chosen)


def each_step_alone(rulebase):
    """The rulebase after each exact step applied on its own to the original, then after all of them."""
    context = Context(VOCABULARY)
    entries = [Entry(i, r) for i, r in enumerate(rulebase)]
    for name, step in EXACT_STEPS + (("unused-fields", unused_fields),):
        kept, _ = step(entries, context)
        yield name, Rulebase(tuple(e.rule for e in kept))
    yield "all", simplify_exactly(rulebase, VOCABULARY, drop_unused_fields=True).rulebase


def check_every_step(rulebase, seed):
    inputs, visible = draw_inputs(np.random.default_rng(seed))
    original = decisions(rulebase, inputs, visible)
    for name, simplified in each_step_alone(rulebase):
        if simplified != rulebase:
            scalar, batched = decisions(simplified, inputs, visible)
            assert scalar == original[0], name
            assert batched == original[1], name


# ---- property tests ---------------------------------------------------------------------------------


@EXAMPLES
@given(SEEDS)
def test_every_exact_step_decides_as_the_original_on_redundant_random_rulebases(seed):
    check_every_step(redundant_rulebase(np.random.default_rng(seed)), seed)


@EXAMPLES
@given(SEEDS)
def test_every_exact_step_decides_as_the_original_on_decoded_random_chromosomes(seed):
    rulebase = decoded_chromosome(seed)
    if len(rulebase):
        check_every_step(rulebase, seed)


@EXAMPLES
@given(st.integers(0, 15), SEEDS)
def test_every_exact_step_decides_as_the_original_on_evolved_rulebases(evolved_rulebases, index, seed):
    check_every_step(evolved_rulebases[index % len(evolved_rulebases)], seed)


def test_the_planted_redundancy_is_found():
    """Not a vacuous pass: over many redundant rulebases every step has work to do somewhere."""
    removed = dict.fromkeys([name for name, _ in EXACT_STEPS], 0)
    for seed in range(60):
        for step in simplify_exactly(redundant_rulebase(np.random.default_rng(seed)), VOCABULARY).steps:
            if step.name in removed:
                removed[step.name] += len(step.changes)
    assert all(count > 0 for count in removed.values()), removed


def test_evolved_rulebases_get_shorter(evolved_rulebases):
    before = sum(premise_count(r) for r in evolved_rulebases)
    after = sum(premise_count(simplify_exactly(r, VOCABULARY).rulebase) for r in evolved_rulebases)
    assert after < before


# ---- each step on worked cases -------------------------------------------------------------------


def simplified(text, drop_unused_fields=False):
    result = simplify_exactly(parse_rulebase(text, VOCABULARY), VOCABULARY, drop_unused_fields)
    return format_rulebase(result.rulebase, VOCABULARY), result


def changed_by(result):
    return {step.name: [c.rule for c in step.changes] for step in result.steps if step.changes}


@pytest.mark.parametrize("text, expected, step", [
    ("if Ball is Near then Dash High\nif Ball is Near then Dash High [direction Left]",
     "if Ball is Near then Dash High", "duplicate-rules"),
    ("if Ball is Near and Goal is Far and Ball is Near then Dash",
     "if Ball is Near and Goal is Far then Dash", "repeated-premises"),
    ("if Ball is Near or Goal is Far or Ball is Near then Dash", "if Ball is Near or Goal is Far then Dash",
     "repeated-premises"),
    # Near is 0 wherever Far is above 0, so Near <= not Far, and min(Near, not Far) = Near
    ("if Ball is Near and Ball is not Far then Dash", "if Ball is Near then Dash", "subsumed-premises"),
    ("if Ball is Near or Ball is not Far then Dash", "if Ball is not Far then Dash", "subsumed-premises"),
    # absorption: (x and y) or x = x
    ("if Ball is Near and Goal is Far or Ball is Near then Dash", "if Ball is Near then Dash", "subsumed-premises"),
    ("if Ball is At and Ball is Far then Dash\nif Goal is Near then Turn", "if Goal is Near then Turn",
     "never-firing-rules"),
    ("if Ball is Near then Dash High\nif Ball is Near and Goal is Far then Dash High",
     "if Ball is Near then Dash High", "subsumed-rules"),
    ("if Ball is Near then Dash High\nif Ball is Near and Goal is Far then Kick Left High",
     "if Ball is Near then Dash High", "dominated-actions"),
])
def test_each_step_on_a_worked_case(text, expected, step):
    output, result = simplified(text)
    assert output == expected
    assert step in changed_by(result)


def test_unused_fields_are_listed_and_dropped_only_on_request():
    text = "if Ball is Near then Turn Left [power High]"
    kept, listed = simplified(text)
    assert kept == text
    unused = next(s for s in listed.steps if s.name == "unused-fields")
    assert not unused.applied and [c.after for c in unused.changes] == ["if Ball is Near then Turn Left"]
    assert simplified(text, drop_unused_fields=True)[0] == "if Ball is Near then Turn Left"


# ---- what must not be simplified ------------------------------------------------------------------


@pytest.mark.parametrize("text", [
    # an unseen ball makes both 0: p or not p is not always 1, p and not p is not always 0
    "if Ball is Near or Ball is not Near then Dash",
    "if Ball is Near and Ball is not Near then Dash",
    # different objects, different variables of one object: independent inputs
    "if Ball is Near and Goal is not Far then Dash",
    "if Ball is Near and Ball is not Left then Dash",
    # two ramps crossing: neither is below the other everywhere
    "if Ball is Near and Ball is VeryNear then Dash",
    # the weaker rule of the same action has another term: at a tie it moves the mean of maximum
    "if Ball is Near then Dash High\nif Ball is Near and Goal is Far then Dash Low",
    # the stronger rule of another action comes later: on a tie the weaker, earlier action wins
    "if Ball is Near and Goal is Far then Kick Left High\nif Ball is Near then Dash High",
])
def test_what_cannot_be_proved_is_kept(text):
    assert simplified(text)[0] == format_rulebase(parse_rulebase(text, VOCABULARY), VOCABULARY)


def test_the_kept_cases_matter_on_some_input():
    """Removing what the last two cases keep would change a decision: ties decide there."""
    at_tie = dict(ball_distance=4.0, ball_direction=0.0, goal_distance=40.0, goal_direction=0.0)  # Near = Far = 1
    same_action = Engine(parse_rulebase("if Ball is Near then Dash High\nif Ball is Near and Goal is Far then Dash Low",
                                        VOCABULARY), VOCABULARY).infer(at_tie).selected
    assert same_action.parameters["power"] != Engine(parse_rulebase("if Ball is Near then Dash High", VOCABULARY),
                                                     VOCABULARY).infer(at_tie).selected.parameters["power"]
    later = Engine(parse_rulebase("if Ball is Near and Goal is Far then Kick Left High\nif Ball is Near then Dash High",
                                  VOCABULARY), VOCABULARY).infer(at_tie).selected
    assert later.action == "KICK"
