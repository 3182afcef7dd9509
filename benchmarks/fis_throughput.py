"""Batched FIS throughput: our numba kernel vs pyfuzzylite and scikit-fuzzy, in one run.

200 random rulebases of 10 rules (seeded), each player its own rulebase, evaluated with
`soccer_lab.fuzzy.batched.infer_batch`. pyfuzzylite evaluates one of the same rulebases, exported to FLL
(MeanOfMaximum), with its own batched evaluation (arrays as input values, one engine.process()).
scikit-fuzzy evaluates the same rulebase with ControlSystemSimulation, one input at a time (slow,
so few evaluations). The script also checks the three agree to within the other tools' sampling
error (a maximum made only of points is invisible to sampling and is not compared: docs/design.md,
"The mean of maximum, exactly").

    python benchmarks/fis_throughput.py [--players 200] [--rows 500] [--fuzzylite-rows 5000] [--skfuzzy-rows 40]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from soccer_lab.fuzzy.batched import compile_rulebases, decide_batch, infer_batch
from soccer_lab.fuzzy.defuzzifier import sampled_error_bound
from soccer_lab.fuzzy.engine import Engine
from soccer_lab.fuzzy.export.fll import to_fll
from soccer_lab.fuzzy.export.layout import (RESOLUTION, VISIBLE_TERM, FisLayout, parameter_output, support_output,
                                            visibility_input)
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py

SEED = 20240601
RULES = 10
VISIBLE_SHARE = 0.8
SKFUZZY_INPUT_STEP = 0.5  # every term vertex lies on this grid, so skfuzzy's interpolation is exact


def draw_inputs(rng, vocabulary, n):
    variables = [vocabulary.variables[kind] for kind in vocabulary.inputs.values()]
    x = np.column_stack([rng.uniform(v.minimum, v.maximum, n) for v in variables])
    return x, rng.random((n, len(vocabulary.object_names))) < VISIBLE_SHARE


def crisp_inputs(vocabulary, row, seen):
    return {name: (float(row[j]) if seen[vocabulary.object_names.index(obj)] else None)
            for j, name in enumerate(vocabulary.input_names)
            for obj in vocabulary.object_names if name in vocabulary.objects[obj].values()}


def timed(function, repeats=3):
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def run_ours(kernel, compiled, x, visible, players):
    kernel(compiled, x[:10], visible[:10], players[:10])  # compile outside the timing
    return len(x) / timed(lambda: kernel(compiled, x, visible, players))


def fuzzylite_engine(rulebase, vocabulary):
    import fuzzylite as fl

    return fl.FllImporter().from_string(to_fll(rulebase, vocabulary))


def run_fuzzylite(engine, vocabulary, x, visible):
    def evaluate():
        for j, name in enumerate(vocabulary.input_names):
            engine.input_variable(name).value = x[:, j]
        for j, obj in enumerate(vocabulary.object_names):
            engine.input_variable(visibility_input(obj)).value = visible[:, j].astype(float)
        engine.process()

    rate = len(x) / timed(evaluate, repeats=1)
    return rate, {v.name: np.broadcast_to(v.value, (len(x),)).copy() for v in engine.output_variables}


def skfuzzy_simulation(rulebase, vocabulary):
    import skfuzzy as fuzz
    from skfuzzy import control as ctrl

    layout = FisLayout(rulebase, vocabulary)
    antecedents = {}
    for variable in layout.inputs:
        if variable.terms[0] is VISIBLE_TERM:
            universe = np.array([0.0, 1.0])
        else:
            universe = np.arange(variable.minimum, variable.maximum + SKFUZZY_INPUT_STEP / 2, SKFUZZY_INPUT_STEP)
        antecedent = ctrl.Antecedent(universe, variable.name)
        for term in variable.terms:
            antecedent[term.name] = fuzz.trapmf(universe, list(term.parameters))
        antecedents[variable.name] = antecedent
    consequents = {}
    for variable in layout.outputs:
        universe = np.linspace(variable.minimum, variable.maximum, RESOLUTION + 1)
        consequent = ctrl.Consequent(universe, variable.name, defuzzify_method="mom")
        for term in variable.terms:
            consequent[term.name] = fuzz.trapmf(universe, list(term.parameters))
        consequents[variable.name] = consequent

    def premise(p):
        seen = antecedents[visibility_input(p.object)][VISIBLE_TERM.name]
        term = antecedents[vocabulary.premise_input(p.object, p.term)][p.term]
        return seen & (~term if p.negated else term)

    rules = []
    for rule in rulebase:
        expression = premise(rule.premises[0])
        for connector, p in zip(rule.connectors, rule.premises[1:]):  # built left to right, as we evaluate
            expression = expression | premise(p) if connector == "OR" else expression & premise(p)
        rules.append(ctrl.Rule(expression, [consequents[name][term] for name, term in layout.conclusions(rule)]))
    return ctrl.ControlSystemSimulation(ctrl.ControlSystem(rules))


def run_skfuzzy(simulation, vocabulary, x, visible):
    outputs = []

    def evaluate():
        outputs.clear()
        for row, seen in zip(x, visible):
            for j, name in enumerate(vocabulary.input_names):
                simulation.input[name] = float(row[j])
            for j, obj in enumerate(vocabulary.object_names):
                simulation.input[visibility_input(obj)] = float(seen[j])
            try:
                simulation.compute()
                outputs.append(dict(simulation.output))
            except (ValueError, AssertionError):  # skfuzzy refuses to defuzzify when no rule fires
                outputs.append({})

    rate = len(x) / timed(evaluate, repeats=1)
    return rate, outputs


def agreement(rulebase, vocabulary, x, visible, value_of):
    """(compared, disagreeing, worst excess) of a tool's outputs against our scalar engine."""
    engine = Engine(rulebase, vocabulary)
    compared = disagreeing = 0
    worst = 0.0
    for i in range(len(x)):
        inference = engine.infer(crisp_inputs(vocabulary, x[i], visible[i]))
        for fired in inference.fired:
            checks = [(support_output(fired.action), fired.support, 1.0 / RESOLUTION)]
            for output, value in fired.parameters.items():
                variable = vocabulary.output_variable(output)
                sets = inference.clipped_sets[fired.action][output]
                step = (variable.maximum - variable.minimum) / RESOLUTION
                bound = sampled_error_bound(engine.maximum_cuts(output, sets), step) if sets else 0.0
                if bound is not None:
                    checks.append((parameter_output(fired.action, output), value, bound))
            for name, expected, bound in checks:
                got = value_of(i, name)
                if got is None:
                    continue
                compared += 1
                excess = abs(got - expected) - bound - 1e-9
                if excess > 0:
                    disagreeing += 1
                    worst = max(worst, excess)
    return compared, disagreeing, worst


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--players", type=int, default=200)
    parser.add_argument("--rows", type=int, default=500, help="evaluations per player for our kernel")
    parser.add_argument("--fuzzylite-rows", type=int, default=5000)
    parser.add_argument("--skfuzzy-rows", type=int, default=40)
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()

    vocabulary = Vocabulary.default()
    rng = np.random.default_rng(SEED)
    rulebases = [random_rulebase(rng, vocabulary, rules=RULES) for _ in range(args.players)]
    compiled = compile_rulebases(rulebases, vocabulary)
    n = args.players * args.rows
    x, visible = draw_inputs(rng, vocabulary, n)
    players = np.repeat(np.arange(args.players, dtype=np.int64), args.rows)
    full = run_ours(infer_batch, compiled, x, visible, players)
    ours = run_ours(decide_batch, compiled, x, visible, players)
    print(f"soccer-lab batched FIS ({args.players} rulebases x {RULES} rules, {n:,} evaluations):\n"
          f"  decide_batch (the decision a player acts on): {ours:,.0f} evaluations/s, {1e6 / ours:.3f} us each\n"
          f"  infer_batch (every fired action's parameters): {full:,.0f} evaluations/s, {1e6 / full:.3f} us each")

    reference = rulebases[0]
    fx, fvisible = draw_inputs(rng, vocabulary, args.fuzzylite_rows)
    fl_rate, fl_out = run_fuzzylite(fuzzylite_engine(reference, vocabulary), vocabulary, fx, fvisible)
    compared, bad, worst = agreement(reference, vocabulary, fx, fvisible, lambda i, name: fl_out[name][i])
    print(f"pyfuzzylite (FLL, MeanOfMaximum, batched): {fl_rate:,.0f} evaluations/s -> decide_batch is {ours / fl_rate:,.0f}x,"
          f" infer_batch {full / fl_rate:,.0f}x (target >= 100x); agreement: {compared - bad}/{compared} outputs within sampling error"
          + (f", worst excess {worst:.3g}" if bad else ""))

    fl_agreement = f"{compared - bad}/{compared} pyfuzzylite outputs within its sampling error"
    sx, svisible = draw_inputs(rng, vocabulary, args.skfuzzy_rows)
    sk_rate, sk_out = run_skfuzzy(skfuzzy_simulation(reference, vocabulary), vocabulary, sx, svisible)
    compared, bad, worst = agreement(reference, vocabulary, sx, svisible, lambda i, name: sk_out[i].get(name))
    print(f"scikit-fuzzy (ControlSystemSimulation): {sk_rate:,.1f} evaluations/s -> decide_batch is {ours / sk_rate:,.0f}x,"
          f" infer_batch {full / sk_rate:,.0f}x (target >= 10,000x); agreement: {compared - bad}/{compared} outputs within sampling error"
          + (f", worst excess {worst:.3g}" if bad else ""))
    if args.record:
        record("fis_throughput", [
            Figure(f"batched FIS, {args.players} rulebases × {RULES} rules, the decision a player acts on",
                   round(ours / 1e6, 2), "M evaluations/s", note=f"{1e6 / ours:.2f} µs each"),
            Figure("the same against pyfuzzylite 8's batched engine", round(ours / fl_rate), "×", target="≥ 100×",
                   note=fl_agreement),
            Figure("the same against scikit-fuzzy's ControlSystemSimulation", round(ours / sk_rate), "×",
                   target="≥ 10,000×", note=f"{compared - bad}/{compared} outputs within its sampling error"),
            Figure("batched FIS, every fired action's parameters", round(full / 1e6, 2), "M evaluations/s"),
        ], command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
