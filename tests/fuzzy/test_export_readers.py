"""Every export format, loaded by the real readers, decides what our engine decides.

Readers: Debian's `fuzzylite` command (fuzzylite 6) for FCL, FLL and .fis, and pyfuzzylite 8 for FLL,
each over the same random rulebases with random inputs (objects unseen one time in five). Two checks:

- Exactness: every output value the reader gives equals our engine's exact clipped sets as that
  reader samples them (tests/fuzzy/export_readers.py), so the export loses nothing.
- Decision: the reader's supports are within its sampling error of ours, its largest support is our
  selected action (or ties with it within that error), and the parameters of our selected action are
  within its sampling error of ours. Two cases have no bounded sampling error and are counted, not
  compared: a maximum made of points (a triangle's peak at strength 1), which sampling cannot see,
  in fuzzylite 6, a maximum in several pieces, where its mean of maximum takes the first piece; and
  two rules whose strengths differ by rounding only (see ROUNDING).
"""

from __future__ import annotations

import functools
import math
from collections import Counter

import numpy as np
import pytest

from soccer_lab.fuzzy.defuzzifier import merge_intervals, sampled_error_bound
from soccer_lab.fuzzy.engine import Engine
from soccer_lab.fuzzy.export import export_rulebase
from soccer_lab.fuzzy.export.layout import FIRED_TERM, FisLayout, parameter_output, support_output, visibility_input
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from tests.fuzzy.export_readers import (FUZZYLITE, INDETERMINATE, EngineView, fuzzylite_outputs, fuzzylite_view,
                                        pyfuzzylite_outputs, pyfuzzylite_view, reader_value)

VOCABULARY = Vocabulary.default()
SEED = 20240614
RULEBASES = 60
INPUTS_PER_RULEBASE = 40
MAX_RULES = 12
VISIBLE_SHARE = 0.8
OUTSIDE = 10.0  # inputs are drawn this far beyond their universe, to check clamping (not for .fis)
VALUE_TOLERANCE = 1e-6
# Strengths this close are one value computed two ways (1 - Near is Slightly Near's rising side): our
# engine's maximum takes only the larger, a reader comparing within a tolerance takes both.
ROUNDING = 1e-9
MAX_INDETERMINATE_SHARE = 0.01
# What the seeded cases give (docs/inspecting/index.md, "Exports"): ties broken by a later rule, point maxima and, in
# fuzzylite 6, maxima in pieces make up the rest.
MIN_AGREEING_DECISIONS = 0.9
MIN_AGREEING_PARAMETERS = 0.9

needs_fuzzylite = pytest.mark.skipif(
    FUZZYLITE is None, reason="Debian's fuzzylite command is not installed (scripts/test installs it with apt-get)")


def cases(fmt: str) -> list:
    """The same seeded rulebases for every reader: (rulebase, engine, crisp inputs, visibility, our inferences)."""
    return _cases(0.0 if fmt == "fis" else OUTSIDE)  # .fis readers do not clamp inputs to their range


@functools.cache
def _cases(outside: float) -> list:
    rng = np.random.default_rng(SEED)
    variables = [VOCABULARY.variables[kind] for kind in VOCABULARY.inputs.values()]
    drawn = []
    for _ in range(RULEBASES):
        rulebase = random_rulebase(rng, VOCABULARY, rules=int(rng.integers(1, MAX_RULES + 1)))
        crisp = np.column_stack([rng.uniform(v.minimum - outside, v.maximum + outside, INPUTS_PER_RULEBASE)
                                 for v in variables])
        visible = rng.random((INPUTS_PER_RULEBASE, len(VOCABULARY.object_names))) < VISIBLE_SHARE
        engine = Engine(rulebase, VOCABULARY)
        inferences = [engine.infer(ours_inputs(crisp[i], visible[i])) for i in range(INPUTS_PER_RULEBASE)]
        drawn.append((rulebase, engine, crisp, visible, inferences))
    return drawn


def ours_inputs(crisp_row, visible_row) -> dict[str, float | None]:
    seen = dict(zip(VOCABULARY.object_names, visible_row))
    owner = {name: obj for obj, kinds in VOCABULARY.objects.items() for name in kinds.values()}
    return {name: (float(crisp_row[j]) if seen[owner[name]] else None) for j, name in enumerate(VOCABULARY.input_names)}


def reader_rows(view: EngineView, crisp: np.ndarray, visible: np.ndarray) -> np.ndarray:
    """Input values in the reader's column order; a .fis copy (`ball_distance_2`) gets its input's value."""
    columns = []
    for name in view.inputs:
        base = name if name in VOCABULARY.inputs else name.rsplit("_", 1)[0]
        if base in VOCABULARY.inputs:
            columns.append(crisp[:, VOCABULARY.input_names.index(base)])
        else:
            objects = [visibility_input(o) for o in VOCABULARY.object_names]
            columns.append(visible[:, objects.index(name)].astype(float))
    return np.column_stack(columns)


class Comparison:
    """Tallies one reader's agreement with our engine over many evaluations."""

    def __init__(self, label: str):
        self.label = label
        self.count: Counter[str] = Counter()
        self.failures: list[str] = []

    def fail(self, message: str) -> None:
        self.count["failed"] += 1
        if len(self.failures) < 20:
            self.failures.append(message)

    def exact(self, name: str, sets, sampling, got: float, where: str) -> None:
        expected = reader_value(sets, sampling)
        self.count["values"] += 1
        if expected is INDETERMINATE:
            self.count["indeterminate"] += 1
        elif not (math.isnan(expected) and math.isnan(got)) and not abs(got - expected) <= VALUE_TOLERANCE:
            self.fail(f"{where}: {name} = {got}, our sets sampled as the reader does give {expected}")

    def evaluation(self, layout: FisLayout, engine: Engine, inference, view: EngineView, values: dict, where: str):
        fired = {a.action: a for a in inference.fired}
        for name in set(view.outputs) ^ {v.name for v in layout.outputs}:
            self.fail(f"{where}: output {name} is not in both the export and the reader")
        supports = {}
        for action in layout.actions:
            name = support_output(action)
            sets = [(FIRED_TERM, fired[action].support)] if action in fired else []
            self.exact(name, sets, view.outputs[name], values[name], where)
            for output in VOCABULARY.actions[action]:
                param = parameter_output(action, output)
                clipped = inference.clipped_sets[action][output] if action in fired else []
                terms = [(VOCABULARY.output_variable(output).term(t), s) for t, s in clipped]
                self.exact(param, terms, view.outputs[param], values[param], where)
            sampling = view.outputs[name]
            tolerance = (sampling.maximum - sampling.minimum) / sampling.resolution / 2 + VALUE_TOLERANCE
            got = 0.0 if math.isnan(values[name]) else values[name]
            ours = fired[action].support if action in fired else 0.0
            if abs(got - ours) > tolerance:
                self.fail(f"{where}: {name} = {got}, ours {ours} (sampling error up to {tolerance:.3g})")
            supports[action] = (got, tolerance)
        self.count["evaluations"] += 1
        self.decision(engine, inference, view, values, supports, where)

    def decision(self, engine: Engine, inference, view: EngineView, values: dict, supports: dict, where: str):
        selected = inference.selected
        if selected is None:
            if any(got > tolerance for got, tolerance in supports.values()):
                self.fail(f"{where}: no rule fires in our engine, the reader gives supports {supports}")
            self.count["agree"] += 1
            return
        best = max(got for got, _ in supports.values())
        tied = [a for a, (got, tolerance) in supports.items() if got >= best - 2 * tolerance]
        if selected.action not in tied:
            self.fail(f"{where}: the reader's largest supports are {tied}, our engine selects {selected.action}")
            return
        if tied[0] == selected.action:  # the consumer takes the first declared of the largest
            outcome = "agree"
        elif sum(a.support == selected.support for a in inference.fired) > 1:
            outcome = "rule-order tie"  # ours: the action whose first rule reaching the support comes first
        else:
            outcome = "sampling tie"
        for output, ours in selected.parameters.items():
            name = parameter_output(selected.action, output)
            if not self.parameter(engine, inference.clipped_sets[selected.action][output], output, ours,
                                  view.outputs[name], values[name], f"{where}: {name}"):
                outcome = "unresolved" if outcome == "agree" else outcome
        self.count[outcome] += 1

    def parameter(self, engine: Engine, sets, output: str, ours: float, sampling, got: float, where: str) -> bool:
        """Compare one parameter of the selected action; False when sampling cannot resolve it."""
        if not sets:
            if not (got == ours or (math.isnan(got) and math.isnan(sampling.unfired))):
                self.fail(f"{where} = {got}, ours the default {ours}")
            return True
        self.count["parameters"] += 1
        cuts = engine.maximum_cuts(output, sets)
        pieces = merge_intervals(cuts)
        step = (sampling.maximum - sampling.minimum) / sampling.resolution
        level = max(strength for _, strength in sets)
        if any(0.0 < level - strength < ROUNDING for _, strength in sets):
            self.count["rounding ties"] += 1
            return False
        if sampling.first_plateau and len(pieces) > 1:
            self.count["maxima in pieces"] += 1
            return False
        bound = sampled_error_bound(cuts, step)
        if bound is None and len(pieces) == 1:
            # a point (or nearly): the samples next to it are highest unless another set comes close
            if abs(got - ours) <= step + (pieces[0][1] - pieces[0][0]) / 2 + VALUE_TOLERANCE:
                self.count["parameters agree"] += 1
                return True
            self.count["point maxima missed"] += 1
            return False
        if bound is None:
            self.count["point maxima missed"] += 1
            return False
        if abs(got - ours) <= bound + VALUE_TOLERANCE:
            self.count["parameters agree"] += 1
            return True
        self.fail(f"{where} = {got}, ours {ours} (sampling error up to {bound:.3g})")
        return True

    def summary(self) -> str:
        c = self.count
        return (f"{self.label}: {RULEBASES} rulebases x {INPUTS_PER_RULEBASE} inputs = {c['evaluations']} decisions: "
                f"{c['agree']} agree, {c['rule-order tie']} ties our engine breaks by a later rule, "
                f"{c['sampling tie']} tie within sampling error, {c['unresolved']} unresolved by sampling; "
                f"{c['parameters agree']}/{c['parameters']} selected parameters agree within sampling error "
                f"({c['point maxima missed']} point maxima missed, {c['maxima in pieces']} maxima in pieces, "
                f"{c['rounding ties']} strengths tied up to rounding); "
                f"{c['values']} output values equal our sets as the reader samples them, "
                f"{c['indeterminate']} indeterminate; {c['failed']} failed")

    def check(self) -> None:
        print(self.summary())
        assert not self.failures, self.summary() + "\n" + "\n".join(self.failures)
        assert self.count["evaluations"] == RULEBASES * INPUTS_PER_RULEBASE
        assert self.count["indeterminate"] <= MAX_INDETERMINATE_SHARE * self.count["values"]
        assert self.count["agree"] >= MIN_AGREEING_DECISIONS * self.count["evaluations"]
        assert self.count["parameters agree"] >= MIN_AGREEING_PARAMETERS * self.count["parameters"]


@needs_fuzzylite
@pytest.mark.parametrize("fmt", ["fcl", "fll", "fis"])
def test_fuzzylite_command_decides_what_our_engine_decides(fmt, tmp_path):
    comparison = Comparison(f"fuzzylite 6, {fmt}")
    for k, (rulebase, engine, crisp, visible, inferences) in enumerate(cases(fmt)):
        text = export_rulebase(rulebase, fmt, VOCABULARY)
        view = fuzzylite_view(text, fmt, tmp_path)
        outputs = fuzzylite_outputs(text, fmt, view, reader_rows(view, crisp, visible), tmp_path)
        layout = FisLayout(rulebase, VOCABULARY)
        for i, (inference, values) in enumerate(zip(inferences, outputs)):
            comparison.evaluation(layout, engine, inference, view, values, f"rulebase {k}, input {i}")
    comparison.check()


def test_pyfuzzylite_decides_what_our_engine_decides():
    fl = pytest.importorskip("fuzzylite", reason="pyfuzzylite is not installed: "
                                                  "pip install --no-deps pyfuzzylite==8.0.6 (scripts/test does)")
    comparison = Comparison("pyfuzzylite 8, fll")
    for k, (rulebase, engine, crisp, visible, inferences) in enumerate(cases("fll")):
        reader = fl.FllImporter().from_string(export_rulebase(rulebase, "fll", VOCABULARY))
        view = pyfuzzylite_view(reader)
        outputs = pyfuzzylite_outputs(reader, view, reader_rows(view, crisp, visible))
        layout = FisLayout(rulebase, VOCABULARY)
        for i, (inference, values) in enumerate(zip(inferences, outputs)):
            comparison.evaluation(layout, engine, inference, view, values, f"rulebase {k}, input {i}")
    comparison.check()
