"""A shorter rulebase that decides exactly as the original does, on every input.

Each step below is a small function over the rules (each tagged with its number in the original),
composed top to bottom by `simplify_exactly`. Every step is proved to change no decision (the
selected action, its support and its parameters, bit for bit, on both engines):

- duplicate-rules: a rule equal to an earlier one (same premises and connectors, same action, same
  terms in the parameters the action uses). The earlier rule reaches the same strength first, so it
  already sets the action's support and first rule, and its output set is the same cut at the same
  level: the union in the mean of maximum is unchanged.
- repeated-premises: a premise repeated within a run of the same connector (`a and b and a`): the
  run is one min (or max) of its operands, and min(x, x) = x.
- subsumed-premises: a premise whose removal leaves the rule's strength the same float on every input,
  proved by fuzzy/strength_form.py (absorption, `x and y = x` where x <= y is proved, ...).
- never-firing-rules: a rule whose strength is provably always 0 (`Ball is At and Ball is Far`): a
  rule of strength 0 takes part in nothing.
- subsumed-rules: a rule never stronger than an earlier rule of the same action that has the same term
  in every parameter where this one has one: the earlier rule reaches any strength this one reaches,
  first, with the same cut, so support, first rule and every mean of maximum stay (the mean of
  maximum gathers every rule of the action at the top level, so a weaker rule with another term
  could change a parameter, and is kept).
- dominated-actions: the rules of an action that can never be performed, because each of its rules
  has an earlier rule of another action that is never weaker (on a tie the action whose strongest
  rule comes first wins). An action never performed decides nothing.
- unused-fields (only on request; listed otherwise): consequent fields the action does not use.

Dropping a rule keeps the others in order, so ties between the remaining actions break as before.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable, Iterator

from soccer_lab.fuzzy.premise_relations import PremiseRelations
from soccer_lab.fuzzy.printer import format_premise, format_rule
from soccer_lab.fuzzy.rule import Consequent, Rule, Rulebase
from soccer_lab.fuzzy.strength_form import StrengthForm
from soccer_lab.fuzzy.vocabulary import Vocabulary

EXACT, CHECKED = "exact", "checked"


@dataclass(frozen=True)
class Change:
    rule: int  # the rule's number in the original rulebase, from 1
    before: str
    after: str | None  # None: the rule is dropped
    reason: str


@dataclass(frozen=True)
class Step:
    name: str
    kind: str  # EXACT (proved) or CHECKED (replayed on games)
    summary: str  # why it changes no decision, or how it was checked
    changes: tuple[Change, ...]
    applied: bool = True  # False: the changes are only listed (not asked for, or a replay differed)
    games: int = 0  # CHECKED: the games replayed


@dataclass(frozen=True)
class Entry:
    origin: int  # index in the original rulebase
    rule: Rule


@dataclass(frozen=True)
class Simplification:
    original: Rulebase
    rulebase: Rulebase
    origins: tuple[int, ...]  # per rule of `rulebase`, its index in `original`
    steps: tuple[Step, ...]


class Context:
    def __init__(self, vocabulary: Vocabulary):
        self.vocabulary = vocabulary
        self.relations = PremiseRelations(vocabulary)
        self._forms: dict[Rule, StrengthForm] = {}

    def form(self, rule: Rule) -> StrengthForm:
        if rule not in self._forms:
            self._forms[rule] = StrengthForm.of(rule, self.relations)
        return self._forms[rule]

    def text(self, rule: Rule) -> str:
        return format_rule(rule, self.vocabulary)

    def used(self, consequent: Consequent) -> tuple[str, ...]:
        return self.vocabulary.actions[consequent.action]


StepFunction = Callable[[list[Entry], Context], tuple[list[Entry], list[Change]]]


# ---- the steps ------------------------------------------------------------------------------------


def duplicate_rules(entries: list[Entry], context: Context) -> tuple[list[Entry], list[Change]]:
    kept: list[Entry] = []
    changes = []
    for entry in entries:
        twin = next((k for k in kept if _same_rule(k.rule, entry.rule, context)), None)
        if twin is None:
            kept.append(entry)
        else:
            changes.append(_dropped(entry, context, f"the same as rule {twin.origin + 1}"))
    return kept, changes


def repeated_premises(entries: list[Entry], context: Context) -> tuple[list[Entry], list[Change]]:
    return _rewrite_each(entries, context, _without_repeats, "a premise repeated in a run of the same connector")


def subsumed_premises(entries: list[Entry], context: Context) -> tuple[list[Entry], list[Change]]:
    return _rewrite_each(entries, context, lambda rule: _fewest_premises(rule, context),
                         "the same strength on every input without it")


def never_firing_rules(entries: list[Entry], context: Context) -> tuple[list[Entry], list[Change]]:
    kept, changes = [], []
    for entry in entries:
        if context.form(entry.rule).never_fires:
            changes.append(_dropped(entry, context, "its premises exclude each other: its strength is always 0"))
        else:
            kept.append(entry)
    return kept, changes


def subsumed_rules(entries: list[Entry], context: Context) -> tuple[list[Entry], list[Change]]:
    kept: list[Entry] = []
    changes = []
    for entry in entries:
        cover = next((k for k in kept if _covers(k.rule, entry.rule, context)), None)
        if cover is None:
            kept.append(entry)
        else:
            changes.append(_dropped(entry, context, f"never stronger than rule {cover.origin + 1}, which has the "
                                                    "same action and terms and comes first"))
    return kept, changes


def dominated_actions(entries: list[Entry], context: Context) -> tuple[list[Entry], list[Change]]:
    changes: list[Change] = []
    while True:  # one action at a time: each drop is proved on the rules that remain
        action = next((a for a in dict.fromkeys(e.rule.consequent.action for e in entries)
                       if _never_performed(a, entries, context)), None)
        if action is None:
            return entries, changes
        name = context.vocabulary.display(action)
        for entry in entries:
            if entry.rule.consequent.action == action:
                changes.append(_dropped(entry, context, f"{name} is never performed: each of its rules has an "
                                                        "earlier rule of another action that is never weaker"))
        entries = [e for e in entries if e.rule.consequent.action != action]


def unused_fields(entries: list[Entry], context: Context) -> tuple[list[Entry], list[Change]]:
    def trimmed(rule: Rule) -> Rule:
        used = context.used(rule.consequent)
        fields = {o: getattr(rule.consequent, o) if o in used else None for o in context.vocabulary.output_names}
        return replace(rule, consequent=Consequent(rule.consequent.action, **fields))

    return _rewrite_each(entries, context, trimmed, "not used by the action")


EXACT_STEPS: tuple[tuple[str, StepFunction], ...] = (
    ("duplicate-rules", duplicate_rules),
    ("repeated-premises", repeated_premises),
    ("subsumed-premises", subsumed_premises),
    ("never-firing-rules", never_firing_rules),
    ("subsumed-rules", subsumed_rules),
    ("dominated-actions", dominated_actions),
)
UNUSED_FIELDS = "unused-fields"
SUMMARIES = {
    "duplicate-rules": "a rule equal to an earlier one decides nothing the earlier one does not",
    "repeated-premises": "min(x, x) = x and max(x, x) = x within a run of the same connector",
    "subsumed-premises": "the rule's strength, as a max of mins of its premises, is provably the same float",
    "never-firing-rules": "a rule whose strength is always 0 takes part in nothing",
    "subsumed-rules": "an earlier rule of the same action with the same terms is never weaker",
    "dominated-actions": "an action whose every rule is beaten (or tied, earlier) by another action's rule is "
                         "never performed",
    UNUSED_FIELDS: "a parameter the action does not use is never read",
}


def simplify_exactly(rulebase: Rulebase, vocabulary: Vocabulary, drop_unused_fields: bool = False) -> Simplification:
    """Every exact step in turn; the unused fields are dropped only when asked, else listed."""
    context = Context(vocabulary)
    entries = [Entry(i, rule) for i, rule in enumerate(rulebase)]
    steps = []
    for name, step in EXACT_STEPS:
        entries, changes = step(entries, context)
        steps.append(Step(name, EXACT, SUMMARIES[name], tuple(changes)))
    trimmed, changes = unused_fields(entries, context)
    if drop_unused_fields:
        entries = trimmed
    steps.append(Step(UNUSED_FIELDS, EXACT, SUMMARIES[UNUSED_FIELDS], tuple(changes), applied=drop_unused_fields))
    return Simplification(rulebase, Rulebase(tuple(e.rule for e in entries)), tuple(e.origin for e in entries),
                          tuple(steps))


def premise_count(rulebase: Rulebase) -> int:
    return sum(len(rule.premises) for rule in rulebase)


# ---- helpers ----------------------------------------------------------------------------------------


def _same_rule(a: Rule, b: Rule, context: Context) -> bool:
    return (a.premises == b.premises and a.connectors == b.connectors and a.consequent.action == b.consequent.action
            and all(getattr(a.consequent, o) == getattr(b.consequent, o) for o in context.used(a.consequent)))


def _covers(earlier: Rule, later: Rule, context: Context) -> bool:
    """`earlier` makes `later` redundant within their action (see subsumed-rules above)."""
    if earlier.consequent.action != later.consequent.action:
        return False
    for output in context.used(later.consequent):
        term = getattr(later.consequent, output)
        if term is not None and term != getattr(earlier.consequent, output):
            return False
    return context.form(later).at_most(context.form(earlier))


def _never_performed(action: str, entries: list[Entry], context: Context) -> bool:
    for i, entry in enumerate(entries):
        if entry.rule.consequent.action != action:
            continue
        form = context.form(entry.rule)
        if not any(e.rule.consequent.action != action and form.at_most(context.form(e.rule))
                   for e in entries[:i]):
            return False
    return True


def _dropped(entry: Entry, context: Context, reason: str) -> Change:
    return Change(entry.origin + 1, context.text(entry.rule), None, reason)


def _rewrite_each(entries: list[Entry], context: Context, rewrite: Callable[[Rule], Rule],
                  reason: str) -> tuple[list[Entry], list[Change]]:
    result, changes = [], []
    for entry in entries:
        rule = rewrite(entry.rule)
        if rule != entry.rule:
            removed = _removed_words(entry.rule, rule, context)
            changes.append(Change(entry.origin + 1, context.text(entry.rule), context.text(rule),
                                  f"{removed}: {reason}" if removed else reason))
        result.append(Entry(entry.origin, rule))
    return result, changes


def _removed_words(before: Rule, after: Rule, context: Context) -> str:
    """The premises (or fields) `after` lacks, as text."""
    left = list(after.premises)
    gone = []
    for premise in before.premises:
        if premise in left:
            left.remove(premise)
        else:
            gone.append(format_premise(premise, context.vocabulary))
    for output in context.vocabulary.output_names:
        term = getattr(before.consequent, output)
        if term is not None and getattr(after.consequent, output) is None:
            gone.append(f"{output} {context.vocabulary.display(term)}")
    return ", ".join(gone)


def _without_repeats(rule: Rule) -> Rule:
    premises, connectors = [rule.premises[0]], []
    run, run_connector = {rule.premises[0]}, None  # the first run also holds the first premise
    for connector, premise in zip(rule.connectors, rule.premises[1:]):
        if connector != run_connector:
            if run_connector is not None:
                run = set()
            run_connector = connector
        if premise in run:
            continue
        run.add(premise)
        premises.append(premise)
        connectors.append(connector)
    return Rule(tuple(premises), tuple(connectors), rule.consequent)


def _fewest_premises(rule: Rule, context: Context) -> Rule:
    """Drop premises one at a time (the last first) while the strength is provably unchanged."""
    form = context.form(rule)
    while True:
        shorter = next((c for c in _one_premise_less(rule) if context.form(c).equals(form)), None)
        if shorter is None:
            return rule
        rule = shorter


def _one_premise_less(rule: Rule) -> Iterator[Rule]:
    """`rule` without one premise and one of the connectors beside it, last premise first."""
    premises, connectors = rule.premises, rule.connectors
    for i in reversed(range(1, len(premises))):
        without = premises[:i] + premises[i + 1:]
        yield Rule(without, connectors[:i - 1] + connectors[i:], rule.consequent)
        if i < len(connectors):
            yield Rule(without, connectors[:i] + connectors[i + 1:], rule.consequent)
    if len(premises) > 1:
        yield Rule(premises[1:], connectors[1:], rule.consequent)
