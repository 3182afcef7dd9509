"""IEC 61131-7 Fuzzy Control Language (see fuzzy/export/layout.py for how our FIS maps onto a plain
Mamdani function block). Mean of maximum is not among the standard's methods (CoG, CoGS, CoA, LM,
RM); we write `MM`, the name jFuzzyLogic and fuzzylite use, and `LM` (left-most maximum) for supports.
"""

from __future__ import annotations

from fuzzy.export.layout import ENGINE_NAME, ExportedVariable, FisLayout, Keywords, number
from fuzzy.rule import Rulebase
from fuzzy.term import Term
from fuzzy.vocabulary import Vocabulary

WORDS = Keywords(is_="IS", not_="NOT", and_="AND", or_="OR")
INDENT = "    "


def fcl_points(term: Term) -> str:
    """The term's corner points; FCL holds the end values flat beyond the first and last point."""
    points = [(term.a, 0.0), (term.b, 1.0), (term.c, 1.0), (term.d, 0.0)]
    if term.a == term.b:
        points.pop(0)
    if term.c == term.d:
        points.pop()
    unique = [p for i, p in enumerate(points) if i == 0 or p != points[i - 1]]
    return " ".join(f"({number(x)}, {number(y)})" for x, y in unique)


def _terms(variable: ExportedVariable) -> list[str]:
    return [f"{INDENT}TERM {t.name} := {fcl_points(t)};" for t in variable.terms]


def _range(variable: ExportedVariable) -> str:
    return f"{INDENT}RANGE := ({number(variable.minimum)} .. {number(variable.maximum)});"


def to_fcl(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    layout = FisLayout(rulebase, vocabulary)
    lines = [
        "(* exported by soccer-lab: feed *_visible 1 (seen) or 0 (unseen); *)",
        "(* the player performs the action with the largest *_support output *)",
        f"FUNCTION_BLOCK {ENGINE_NAME}",
        "",
        "VAR_INPUT",
    ]
    lines += [f"{INDENT}{v.name} : REAL;" for v in layout.inputs]
    lines += ["END_VAR", "", "VAR_OUTPUT"]
    lines += [f"{INDENT}{v.name} : REAL;" for v in layout.outputs]
    lines += ["END_VAR", ""]
    for variable in layout.inputs:
        # No RANGE here (not in the standard): FCL holds a term's end values flat beyond its first and
        # last points, which for our shoulders is the same as clamping the input to its universe.
        lines += [f"FUZZIFY {variable.name}"] + _terms(variable) + ["END_FUZZIFY", ""]
    for variable in layout.outputs:
        method = "LM" if variable.smallest_of_maximum else "MM"
        lines += [f"DEFUZZIFY {variable.name}"] + _terms(variable) + [
            f"{INDENT}METHOD : {method};",
            f"{INDENT}DEFAULT := {number(variable.default)};",
            _range(variable),
            "END_DEFUZZIFY",
            "",
        ]
    lines += ["RULEBLOCK rules", f"{INDENT}AND : MIN;", f"{INDENT}ACT : MIN;", f"{INDENT}ACCU : MAX;"]
    for index, rule in enumerate(rulebase, start=1):
        then = ", ".join(f"{out} {WORDS.is_} {term}" for out, term in layout.conclusions(rule))
        lines.append(f"{INDENT}RULE {index} : IF {layout.antecedent(rule, WORDS)} THEN {then};")
    lines += ["END_RULEBLOCK", "", "END_FUNCTION_BLOCK"]
    return "\n".join(lines) + "\n"
