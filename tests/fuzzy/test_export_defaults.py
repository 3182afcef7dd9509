"""Where no rule sets an output, every export's reader gives soccer-lab's default (a .fis once gave NaN in
fuzzylite, where FLL and soccer-lab give 0): Debian's fuzzylite command for .fis, FLL and FCL, pyfuzzylite for FLL."""

from __future__ import annotations

import numpy as np
import pytest

from soccer_lab.app.rulebase_files import load_rulebase
from soccer_lab.fuzzy.export import export_rulebase
from soccer_lab.fuzzy.export.layout import FisLayout
from soccer_lab.fuzzy.vocabulary import Vocabulary
from tests.fuzzy.export_readers import FUZZYLITE, fuzzylite_outputs, fuzzylite_view

VOCABULARY = Vocabulary.default()
DEMO = "soccer/data/examples/demo.rules"


def nothing_in_view(inputs: list[str]) -> np.ndarray:
    """One row of inputs in which no rule of the demo fires: the ball and the goal out of view."""
    return np.array([[0.0 if name.endswith("_visible") else 1.0 for name in inputs]])


def defaults() -> dict[str, float]:
    return {v.name: v.default for v in FisLayout(load_rulebase(DEMO), VOCABULARY).outputs}


@pytest.mark.skipif(FUZZYLITE is None, reason="Debian's fuzzylite command is not installed (scripts/test installs it)")
@pytest.mark.parametrize("fmt", ["fis", "fll", "fcl"])
def test_fuzzylite_gives_our_default_for_an_output_no_rule_sets(fmt, tmp_path):
    text = export_rulebase(load_rulebase(DEMO), fmt, VOCABULARY)
    view = fuzzylite_view(text, fmt, tmp_path)
    [values] = fuzzylite_outputs(text, fmt, view, nothing_in_view(view.inputs), tmp_path)
    assert {name: values[name] for name in defaults()} == defaults()


def test_pyfuzzylite_gives_our_default_for_an_output_no_rule_sets():
    fl = pytest.importorskip("fuzzylite", reason="pyfuzzylite is not installed (scripts/test installs it)")
    engine = fl.FllImporter().from_string(export_rulebase(load_rulebase(DEMO), "fll", VOCABULARY))
    for variable in engine.input_variables:
        variable.value = nothing_in_view([variable.name])[0, 0]
    engine.process()
    assert {name: float(np.ravel(engine.output_variable(name).value)[0]) for name in defaults()} == defaults()
