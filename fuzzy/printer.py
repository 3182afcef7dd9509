"""Rulebase -> rule text: the exact inverse of fuzzy/parser.py.

Display names come from the vocabulary (CamelCase). The strict left-to-right grouping is made
explicit: the running group is parenthesised wherever the connector changes, e.g.
`if (Ball is Near or Ball is not Far) and Goal is Near then RunTowardBall Low`.
"""

from __future__ import annotations

from soccer_lab.fuzzy.parser import IF, IS, NOT, THEN
from soccer_lab.fuzzy.rule import Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary


def format_premise(premise: Premise, vocabulary: Vocabulary) -> str:
    words = [vocabulary.display(premise.object), IS] + ([NOT] if premise.negated else [])
    return " ".join(words + [vocabulary.display(premise.term)])


def format_antecedent(rule: Rule, vocabulary: Vocabulary) -> str:
    """Premises joined left to right; a group is closed in parentheses before a different connector."""
    text = format_premise(rule.premises[0], vocabulary)
    previous = None
    for connector, premise in zip(rule.connectors, rule.premises[1:]):
        if previous is not None and connector != previous:
            text = f"({text})"
        text = f"{text} {connector.lower()} {format_premise(premise, vocabulary)}"
        previous = connector
    return text


def format_consequent(consequent: Consequent, vocabulary: Vocabulary) -> str:
    """`Kick SlightlyRight High`; Null parameters are left out; unused ones go in brackets: `Turn Left [power High]`."""
    uses = vocabulary.actions[consequent.action]
    words = [vocabulary.display(consequent.action)]
    unused = []
    for output in vocabulary.output_names:
        term = getattr(consequent, output)
        if term is None:
            continue
        if output in uses:
            words.append(vocabulary.display(term))
        else:
            unused.append(f"{output} {vocabulary.display(term)}")
    if unused:
        words.append(f"[{', '.join(unused)}]")
    return " ".join(words)


def format_rule(rule: Rule, vocabulary: Vocabulary) -> str:
    return f"{IF} {format_antecedent(rule, vocabulary)} {THEN} {format_consequent(rule.consequent, vocabulary)}"


def format_rulebase(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    """One rule a line (no trailing newline)."""
    return "\n".join(format_rule(rule, vocabulary) for rule in rulebase)
