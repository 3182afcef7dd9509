"""IEC 61131-7 Fuzzy Control Language that standard readers (jFuzzyLogic) and fuzzylite 6 both load.

fuzzylite's FCL reader is line based and differs from the standard in three places; the text is
written so that each reader sees what it expects (see fuzzy/export/layout.py for the FIS itself):

- Comments: the standard has only `(* ... *)`; fuzzylite rejects a line that starts with one. Ours
  follow a keyword whose line fuzzylite reads no further (`VAR_INPUT`, `VAR_OUTPUT`, the head of a
  DEFUZZIFY or RULEBLOCK).
- ACCU: the standard puts the accumulation in RULEBLOCK, fuzzylite in each DEFUZZIFY and refuses it in
  RULEBLOCK. The RULEBLOCK head line carries the standard's `AND : MIN; ACT : MIN; ACCU : MAX;`
  (fuzzylite reads only the head's first and last word) and opens a comment; inside it, lines
  that fuzzylite reads up to its own `//` comment give it AND, OR and ACT. Each DEFUZZIFY head opens a
  comment whose line `ACCU : MAX; // ... *)` only fuzzylite reads.
- Rules: fuzzylite wants lower-case rule words and one conclusion per rule, which the standard allows
  (its keywords are case-insensitive): a rule setting the support and two parameters becomes three
  rules with the same condition, which max aggregation makes equivalent.

Mean of maximum is not among the standard's methods (CoG, CoGS, CoA, LM, RM); we write `MM`, the name
jFuzzyLogic and fuzzylite use. fuzzylite reads FCL with 100 samples per output (FCL cannot say more).
"""

from __future__ import annotations

from soccer_lab.fuzzy.export.layout import ENGINE_NAME, ExportedVariable, FisLayout, Keywords, number, visibility_input
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.vocabulary import Vocabulary

WORDS = Keywords(is_="is", not_="not", and_="and", or_="or")
INDENT = "    "
RULEBLOCK_NAME = "rules"


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


def _declarations(kind: str, variables: list[ExportedVariable], comment: str) -> list[str]:
    if not variables:
        return []
    return [f"{kind} (* {comment} *)"] + [f"{INDENT}{v.name} : REAL;" for v in variables] + ["END_VAR", ""]


def _fuzzify(variable: ExportedVariable) -> list[str]:
    # No RANGE (not in the standard's FUZZIFY): FCL holds a term's end values flat beyond its first and
    # last points, which for our shoulders is the same as clamping the input to its universe.
    return [f"FUZZIFY {variable.name}"] + _terms(variable) + ["END_FUZZIFY", ""]


def _defuzzify(variable: ExportedVariable) -> list[str]:
    return [
        f"DEFUZZIFY {variable.name} (*",
        f"{INDENT}ACCU : MAX; // fuzzylite reads ACCU here, the standard in RULEBLOCK *)",
        *_terms(variable),
        f"{INDENT}METHOD : MM;",
        f"{INDENT}DEFAULT := {number(variable.default)};",
        f"{INDENT}RANGE := ({number(variable.minimum)} .. {number(variable.maximum)});",
        "END_DEFUZZIFY",
        "",
    ]


def _ruleblock(layout: FisLayout) -> list[str]:
    lines = [
        f"RULEBLOCK {RULEBLOCK_NAME} AND : MIN; ACT : MIN; ACCU : MAX; "
        f"(* fuzzylite reads only the first and the last word of this line: {RULEBLOCK_NAME}",
        f"{INDENT}AND : MIN; //",
        f"{INDENT}OR : MAX; //",
        f"{INDENT}ACT : MIN; // it takes its operators from these lines, which the standard reads as a comment *)",
    ]
    number_ = 0
    for rule in layout.rulebase:
        condition = layout.antecedent(rule, WORDS)
        for output, term in layout.conclusions(rule):
            number_ += 1
            lines.append(f"{INDENT}RULE {number_} : if {condition} then {output} {WORDS.is_} {term};")
    return lines + ["END_RULEBLOCK", ""]


def to_fcl(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    layout = FisLayout(rulebase, vocabulary)
    seen = " and ".join(visibility_input(o) for o in vocabulary.object_names)
    lines = [f"FUNCTION_BLOCK {ENGINE_NAME}", ""]
    lines += _declarations("VAR_INPUT", layout.inputs,
                           f"exported by soccer-lab; feed {seen} 1 when the object is seen, 0 when not")
    lines += _declarations("VAR_OUTPUT", layout.outputs,
                           "the player performs the action whose *_support is the largest; "
                           "on a tie, the one declared first")
    for variable in layout.inputs:
        lines += _fuzzify(variable)
    for variable in layout.outputs:
        lines += _defuzzify(variable)
    lines += _ruleblock(layout)
    lines.append("END_FUNCTION_BLOCK")
    return "\n".join(lines) + "\n"
