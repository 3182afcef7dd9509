"""/api/rules: parse rule text, evaluate a rulebase on crisp inputs."""

from __future__ import annotations

from fastapi import APIRouter

from app.api.models import (
    ErrorBody,
    EvaluateRequest,
    EvaluateResponse,
    FiredAction,
    ParseRequest,
    ParseResponse,
    RuleEvaluation,
)
from app.api.routes.dependencies import StoreDependency
from app.api.rule_text import VOCABULARY, parse, rule_out
from fuzzy.engine import ActionOutput, Engine
from fuzzy.printer import format_rule, format_rulebase

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
    text = body.text if body.text is not None else store.get_rulebase(body.rulebase_id).text
    engine = Engine(parse(text), VOCABULARY)
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
