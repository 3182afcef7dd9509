"""How our FIS maps onto a plain Mamdani FIS that other tools load (shared by the FCL, FLL and .fis writers).

- Inputs: the vocabulary's crisp inputs, plus one visibility input per object, `ball_visible` in
  [0, 1] with the term YES (a ramp from 0 to 1): feed 1 when the object is seen, 0 when not. Each
  premise becomes `(ball_visible is YES and ball_distance is [not] NEAR)`, so a premise about an
  unseen object has degree 0, negated or not, as in our engine. (NaN inputs would not do: tools
  disagree on min/max with NaN.)
- Outputs: our FIS has one output per (action, parameter) pair in effect. For every action the
  rulebase uses: `kick_support`, whose value is the largest strength among the action's rules, and
  `kick_direction`, `kick_power` for the parameters the action uses (the variable's terms, max
  aggregation, our default when no rule gives a term).
- Every output is defuzzified by mean of maximum, the only method all three formats share (a .fis
  file names one method for all its outputs). The support's term FIRED rises from 0 at -1 to 1 at 1:
  clipped at strength s its maximum is [2s - 1, 1], whose mean is s.
- The consumer selects the action with the largest support; on a tie, the one declared first. The
  actions are declared in the order of their first rule, so that is our engine's choice unless an
  action's earlier rules fired weaker (ours takes the first rule that reaches the tied support).
- Premises combine strictly left to right, written with explicit parentheses.
"""

from __future__ import annotations

from dataclasses import dataclass

from soccer_lab.fuzzy.rule import Premise, Rule, Rulebase
from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.vocabulary import Vocabulary

ENGINE_NAME = "soccer_lab"
VISIBLE_TERM = Term("YES", 0.0, 1.0, 1.0, 1.0)
FIRED_TERM = Term("FIRED", -1.0, 1.0, 1.0, 1.0)
SUPPORT_RANGE = (-1.0, 1.0)
SUPPORT_DEFAULT = 0.0
RESOLUTION = 1000  # samples of the defuzzifiers where the format can say so (FLL)


def visibility_input(obj: str) -> str:
    return f"{obj.lower()}_visible"


def support_output(action: str) -> str:
    return f"{action.lower()}_support"


def parameter_output(action: str, output: str) -> str:
    return f"{action.lower()}_{output}"


@dataclass(frozen=True)
class ExportedVariable:
    name: str
    minimum: float
    maximum: float
    terms: tuple[Term, ...]
    default: float = 0.0


@dataclass(frozen=True)
class Keywords:
    """The rule words of a target language."""

    is_: str
    not_: str
    and_: str
    or_: str


@dataclass(frozen=True)
class Literal:
    """`input is [not] term`: one premise's membership test, or an object's visibility test."""

    input: str
    term: str
    negated: bool = False


class FisLayout:
    """The exported inputs, outputs and rule texts of one rulebase."""

    def __init__(self, rulebase: Rulebase, vocabulary: Vocabulary):
        self.rulebase = rulebase
        self.vocabulary = vocabulary
        self.actions = list(dict.fromkeys(rule.consequent.action for rule in rulebase))  # by first rule

    @property
    def inputs(self) -> list[ExportedVariable]:
        crisp = [
            ExportedVariable(name, v.minimum, v.maximum, v.terms)
            for name, v in ((n, self.vocabulary.variables[k]) for n, k in self.vocabulary.inputs.items())
        ]
        visible = [ExportedVariable(visibility_input(o), 0.0, 1.0, (VISIBLE_TERM,)) for o in self.vocabulary.object_names]
        return crisp + visible

    @property
    def outputs(self) -> list[ExportedVariable]:
        outputs = []
        for action in self.actions:
            outputs.append(ExportedVariable(support_output(action), *SUPPORT_RANGE, (FIRED_TERM,), SUPPORT_DEFAULT))
            for output in self.vocabulary.actions[action]:
                variable = self.vocabulary.output_variable(output)
                outputs.append(ExportedVariable(parameter_output(action, output), variable.minimum, variable.maximum,
                                                variable.terms, self.vocabulary.output_default(output)))
        return outputs

    def literals(self, premise: Premise) -> tuple[Literal, Literal]:
        """The premise as (object is visible) and (input is [not] term)."""
        return (Literal(visibility_input(premise.object), VISIBLE_TERM.name),
                Literal(self.vocabulary.premise_input(premise.object, premise.term), premise.term, premise.negated))

    def premise(self, premise: Premise, words: Keywords) -> str:
        visible, test = self.literals(premise)
        negation = f"{words.not_} " if test.negated else ""
        return (f"({visible.input} {words.is_} {visible.term} {words.and_} "
                f"{test.input} {words.is_} {negation}{test.term})")

    def antecedent(self, rule: Rule, words: Keywords) -> str:
        text = self.premise(rule.premises[0], words)
        for index, (connector, premise) in enumerate(zip(rule.connectors, rule.premises[1:])):
            if index > 0:
                text = f"({text})"
            joiner = words.or_ if connector == "OR" else words.and_
            text = f"{text} {joiner} {self.premise(premise, words)}"
        return text

    def conclusions(self, rule: Rule) -> list[tuple[str, str]]:
        """(output variable, term) pairs the rule sets: the support, then each used, non-Null parameter."""
        action = rule.consequent.action
        pairs = [(support_output(action), FIRED_TERM.name)]
        for output in self.vocabulary.actions[action]:
            term = getattr(rule.consequent, output)
            if term is not None:
                pairs.append((parameter_output(action, output), term))
        return pairs


def number(x: float) -> str:
    """Shortest exact decimal text of a float (`130.0` -> `130`)."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text
