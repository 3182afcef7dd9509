"""Rule text in and out of the API: parsing (errors become 422 with line/column) and rule bodies."""

from __future__ import annotations

from fastapi.exceptions import RequestValidationError

from soccer_lab.app.web.api.models import ConsequentOut, PremiseOut, RuleOut
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.fuzzy.rule import Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

VOCABULARY = Vocabulary.default()  # the API's rules are written in the soccer vocabulary it publishes


def parse(text: str) -> Rulebase:
    """The rulebase; RuleSyntaxError (every error of the text) is answered 422 by the error handlers."""
    return parse_rulebase(text, VOCABULARY)


NO_RULE = "the rulebase holds no rule: write at least one (a player without rules only hunts)"


def playable(rulebase: Rulebase, where: tuple[str, ...] = ("body", "text")) -> Rulebase:
    """The rulebase, if it has a rule to play or save (the UI refuses the same); else a 422 at `where`."""
    if not len(rulebase):
        raise RequestValidationError([{"type": "value_error", "loc": where, "input": "", "msg": NO_RULE}])
    return rulebase


def rule_out(rule: Rule) -> RuleOut:
    return RuleOut(
        text=format_rule(rule, VOCABULARY),
        premises=[PremiseOut(object=p.object, term=p.term, negated=p.negated) for p in rule.premises],
        connectors=list(rule.connectors),
        consequent=ConsequentOut(**vars(rule.consequent)),
    )
