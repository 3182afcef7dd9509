"""/api/rules: parse rule text, evaluate a rulebase on crisp inputs, rule usage over games, simplify."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.exceptions import RequestValidationError

from soccer_lab.app.web.api.models import (ErrorBody, EvaluateRequest, EvaluateResponse, FiredAction, ParseRequest,
                                           ParseResponse, RuleEvaluation, RulebaseSource, SimplifyRequest,
                                           SimplifyResponse, UsageRequest, UsageResponse)
from soccer_lab.app.web.api.routes.dependencies import StoreDependency
from soccer_lab.app.web.api.rule_text import VOCABULARY, parse, playable, rule_out
from soccer_lab.app.rule_inspection import (SIMPLIFY_PLAYS, USAGE_PLAYS, checked_cost, rule_usage, simplification,
                                            simplification_document, usage_document)
from soccer_lab.fuzzy.engine import ActionOutput, Engine
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.printer import format_rule, format_rulebase

router = APIRouter(prefix="/rules", tags=["rules"], responses={422: {"model": ErrorBody}})


@router.post("/parse", summary="Parse rule text: the rules, or every error with its line and column")
def parse_text(body: ParseRequest) -> ParseResponse:
    rulebase = parse(body.text)
    return ParseResponse(rules=[rule_out(rule) for rule in rulebase], text=format_rulebase(rulebase, VOCABULARY))


@router.post(
    "/evaluate",
    summary="Evaluate rules on crisp inputs: premise degrees, fired actions, the selected action",
    responses={404: {"model": ErrorBody}},
)
def evaluate(body: EvaluateRequest, store: StoreDependency) -> EvaluateResponse:
    engine = Engine(_rulebase(body, store), VOCABULARY)
    inputs = body.inputs.model_dump()
    inference = engine.infer(inputs)
    return EvaluateResponse(
        visible=sorted(engine.visible_objects(inputs)),
        rules=[
            RuleEvaluation(text=format_rule(rule, VOCABULARY), premise_degrees=degrees, strength=strength)
            for rule, degrees, strength in zip(engine.rulebase, inference.premise_degrees, inference.strengths)
        ],
        fired=[_fired(output) for output in inference.fired],
        selected=_fired(inference.selected) if inference.selected else None,
    )


def _fired(output: ActionOutput) -> FiredAction:
    return FiredAction(action=output.action, support=output.support, parameters=output.parameters)


@router.post(
    "/usage",
    summary="Play games and count, per rule, how often it fired, won (its action was performed) and decided, and "
            "its mean strength; per action how often it was performed; how often the player hunted",
    responses={404: {"model": ErrorBody}},
)
def usage(body: UsageRequest, store: StoreDependency) -> UsageResponse:
    rulebase = _affordable(playable(_rulebase(body, store)), body.games, body.game.max_ticks, USAGE_PLAYS)
    return UsageResponse(**usage_document(rule_usage(rulebase, VOCABULARY, body.games, body.seed, body.game),
                                          VOCABULARY))


@router.post(
    "/simplify",
    summary="A shorter rulebase that plays the same: exact steps (proved on every input), then with games > 0 the "
            "rules that never won in those games, kept only when every game replays identically",
    responses={404: {"model": ErrorBody}},
)
def simplify(body: SimplifyRequest, store: StoreDependency) -> SimplifyResponse:
    rulebase = _affordable(_rulebase(body, store), body.games, body.game.max_ticks, SIMPLIFY_PLAYS)
    if body.games:
        playable(rulebase)
    result = simplification(rulebase, VOCABULARY, body.games, body.seed, body.game, body.drop_unused_fields)
    return SimplifyResponse(**simplification_document(result, VOCABULARY))


def _rulebase(body: RulebaseSource, store) -> Rulebase:
    return parse(body.text if body.text is not None else store.get_rulebase(body.rulebase_id).text)



def _affordable(rulebase: Rulebase, games: int, max_ticks: int, plays: int) -> Rulebase:
    try:
        checked_cost(rulebase, games, max_ticks, plays)
    except ValueError as exc:
        raise RequestValidationError([{"type": "value_error", "loc": ("body", "games"), "input": games,
                                       "msg": str(exc)}]) from None
    return rulebase
