"""fuzzylite's FLL (see fuzzy/export/layout.py for how our FIS maps onto a plain Mamdani engine)."""

from __future__ import annotations

from soccer_lab.fuzzy.export.layout import ENGINE_NAME, RESOLUTION, ExportedVariable, FisLayout, Keywords, number
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.vocabulary import Vocabulary

WORDS = Keywords(is_="is", not_="not", and_="and", or_="or")


def fll_term(term: Term) -> str:
    """Triangle when it has a single peak strictly inside its feet, else Trapezoid (exact for shoulders)."""
    if term.b == term.c and term.a < term.b < term.d:
        shape = f"Triangle {number(term.a)} {number(term.b)} {number(term.d)}"
    else:
        shape = "Trapezoid " + " ".join(number(p) for p in term.parameters)
    return f"  term: {term.name} {shape}"


def _input(variable: ExportedVariable) -> list[str]:
    return [
        f"InputVariable: {variable.name}",
        "  enabled: true",
        f"  range: {number(variable.minimum)} {number(variable.maximum)}",
        "  lock-range: true",
    ] + [fll_term(t) for t in variable.terms]


def _output(variable: ExportedVariable) -> list[str]:
    return [
        f"OutputVariable: {variable.name}",
        "  enabled: true",
        f"  range: {number(variable.minimum)} {number(variable.maximum)}",
        "  lock-range: false",
        "  aggregation: Maximum",
        f"  defuzzifier: MeanOfMaximum {RESOLUTION}",
        f"  default: {number(variable.default)}",
        "  lock-previous: false",
    ] + [fll_term(t) for t in variable.terms]


def to_fll(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    layout = FisLayout(rulebase, vocabulary)
    lines = [
        f"Engine: {ENGINE_NAME}",
        "  description: exported by soccer-lab; feed *_visible 1 (seen) or 0 (unseen); "
        "the player performs the action with the largest *_support (on a tie, the one declared first)",
    ]
    for variable in layout.inputs:
        lines += _input(variable)
    for variable in layout.outputs:
        lines += _output(variable)
    lines += [
        "RuleBlock: rules",
        "  enabled: true",
        "  conjunction: Minimum",
        "  disjunction: Maximum",
        "  implication: Minimum",
        "  activation: General",
    ]
    for rule in rulebase:
        then = f" {WORDS.and_} ".join(f"{out} {WORDS.is_} {term}" for out, term in layout.conclusions(rule))
        lines.append(f"  rule: if {layout.antecedent(rule, WORDS)} then {then}")
    return "\n".join(lines) + "\n"
