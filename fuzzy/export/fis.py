"""MATLAB's .fis (Fuzzy Logic Toolbox), as fuzzylite and Octave's fuzzy-logic-toolkit also read it.

A .fis rule can say less than ours: it is one AND (or one OR) over the inputs, each input at most once,
and names one defuzzification method for all outputs. So (see fuzzy/export/layout.py for the rest):

- Each rule's antecedent is expanded into an OR of ANDs (strict left-to-right grouping distributes
  exactly under min and max: `(A or B) and C` = `(A and C) or (B and C)`), and each AND becomes one
  .fis rule with the same conclusions; max aggregation of the copies gives what the one rule gave.
- Inside one AND, each premise adds its object's visibility test; repeated tests are kept once.
  When an AND tests one input against several terms (`Ball is Near and Ball is not VeryNear`), the
  second test reads a copy of that input, `ball_distance_2`, which the consumer feeds the same value.
- No rule fired for an output: MATLAB returns the middle of the output's range, fuzzylite its
  `Default` key (NaN without it). Each range is widened where needed so that its middle is our default
  (power: 0..110 for 55; terms keep their own feet, so the mean of maximum is unchanged), and each
  output says `Default=` our default, so both give what soccer-lab gives.
- Inputs are not clamped to their range by the .fis readers: feed values inside it.
"""

from __future__ import annotations

from dataclasses import dataclass

from soccer_lab.fuzzy.export.layout import ENGINE_NAME, ExportedVariable, FisLayout, Literal, number
from soccer_lab.fuzzy.rule import OR, Rule, Rulebase
from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.vocabulary import Vocabulary

AND_CONNECTOR = 1  # the .fis code of a rule whose tests are joined by AND


def conjunctions(layout: FisLayout, rule: Rule) -> list[tuple[Literal, ...]]:
    """The rule's antecedent as an OR of ANDs, read left to right, each AND without repeated tests."""
    groups: list[list[Literal]] = [list(layout.literals(rule.premises[0]))]
    for connector, premise in zip(rule.connectors, rule.premises[1:]):
        tests = list(layout.literals(premise))
        if connector == OR:
            groups.append(tests)
        else:
            groups = [group + tests for group in groups]
    return [tuple(dict.fromkeys(group)) for group in groups]


def copy_name(input_name: str, copy: int) -> str:
    """The name of the copy-th reading of an input in one AND (the first is the input itself)."""
    return input_name if copy == 1 else f"{input_name}_{copy}"


@dataclass(frozen=True)
class FisRule:
    """One .fis rule line: a term index per input column (negative = not, 0 = untested) and per output."""

    antecedent: tuple[int, ...]
    consequent: tuple[int, ...]

    def line(self) -> str:
        return f"{' '.join(map(str, self.antecedent))}, {' '.join(map(str, self.consequent))} (1) : {AND_CONNECTOR}"


class FisTable:
    """The input columns (with the copies the rules need), output columns and rule lines of a rulebase."""

    def __init__(self, layout: FisLayout):
        self.layout = layout
        self.groups = [(rule, conjunctions(layout, rule)) for rule in layout.rulebase]
        copies = {v.name: 1 for v in layout.inputs}
        for _, ands in self.groups:
            for group in ands:
                for name in copies:
                    copies[name] = max(copies[name], sum(t.input == name for t in group))
        base = {v.name: v for v in layout.inputs}
        self.inputs = list(layout.inputs) + [
            ExportedVariable(copy_name(name, k), base[name].minimum, base[name].maximum, base[name].terms)
            for name, count in copies.items() for k in range(2, count + 1)
        ]
        self.outputs = [self._centred(v) for v in layout.outputs]

    @staticmethod
    def _centred(variable: ExportedVariable) -> ExportedVariable:
        """The variable with its range widened on one side so that its middle is its default."""
        low, high, default = variable.minimum, variable.maximum, variable.default
        if default > (low + high) / 2:
            high = 2 * default - low
        else:
            low = 2 * default - high
        return ExportedVariable(variable.name, low, high, variable.terms, default)

    def rules(self) -> list[FisRule]:
        columns = {v.name: i for i, v in enumerate(self.inputs)}
        outputs = {v.name: (i, v) for i, v in enumerate(self.outputs)}
        lines = []
        for rule, ands in self.groups:
            consequent = [0] * len(self.outputs)
            for output, term in self.layout.conclusions(rule):
                index, variable = outputs[output]
                consequent[index] = _term_index(variable, term)
            for group in ands:
                antecedent = [0] * len(self.inputs)
                readings: dict[str, int] = {}
                for test in group:
                    readings[test.input] = readings.get(test.input, 0) + 1
                    column = columns[copy_name(test.input, readings[test.input])]
                    code = _term_index(self.inputs[column], test.term)
                    antecedent[column] = -code if test.negated else code
                lines.append(FisRule(tuple(antecedent), tuple(consequent)))
        return lines


def _term_index(variable: ExportedVariable, term: str) -> int:
    return 1 + [t.name for t in variable.terms].index(term)


def fis_membership(term: Term) -> str:
    """trimf for a triangle with its peak strictly inside its feet, else trapmf (exact for shoulders)."""
    if term.b == term.c and term.a < term.b < term.d:
        return f"'{term.name}':'trimf',[{number(term.a)} {number(term.b)} {number(term.d)}]"
    return f"'{term.name}':'trapmf',[{' '.join(number(p) for p in term.parameters)}]"


def _variable(section: str, variable: ExportedVariable, *, output: bool = False) -> list[str]:
    default = [f"Default={number(variable.default)}"] if output else []  # fuzzylite's key; MATLAB: the range's middle
    return [
        f"[{section}]",
        f"Name='{variable.name}'",
        f"Range=[{number(variable.minimum)} {number(variable.maximum)}]",
        *default,
        f"NumMFs={len(variable.terms)}",
    ] + [f"MF{i}={fis_membership(t)}" for i, t in enumerate(variable.terms, start=1)] + [""]


def to_fis(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    table = FisTable(FisLayout(rulebase, vocabulary))
    rules = table.rules()
    lines = [
        "[System]",
        f"Name='{ENGINE_NAME}'",
        "Type='mamdani'",
        "Version=2.0",
        f"NumInputs={len(table.inputs)}",
        f"NumOutputs={len(table.outputs)}",
        f"NumRules={len(rules)}",
        "AndMethod='min'",
        "OrMethod='max'",
        "ImpMethod='min'",
        "AggMethod='max'",
        "DefuzzMethod='mom'",
        "",
    ]
    for i, variable in enumerate(table.inputs, start=1):
        lines += _variable(f"Input{i}", variable)
    for i, variable in enumerate(table.outputs, start=1):
        lines += _variable(f"Output{i}", variable, output=True)
    lines += ["[Rules]"] + [rule.line() for rule in rules]
    return "\n".join(lines) + "\n"
