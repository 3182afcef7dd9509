"""/api/rulebases: the library of saved rulebases (only text that parses is saved)."""

from __future__ import annotations

from fastapi import APIRouter, Response

from app.api.models import ErrorBody, RulebaseCreate, RulebaseOut, RulebaseUpdate
from app.api.routes.dependencies import RecordId, StoreDependency
from app.api.rule_text import parse

router = APIRouter(prefix="/rulebases", tags=["rulebases"], responses={404: {"model": ErrorBody}})


@router.post("", status_code=201, summary="Save a rulebase", responses={422: {"model": ErrorBody}})
def create(body: RulebaseCreate, store: StoreDependency) -> RulebaseOut:
    parse(body.text)
    return RulebaseOut.of(store.create_rulebase(body.name, body.text))


@router.get("", summary="List saved rulebases")
def list_all(store: StoreDependency) -> list[RulebaseOut]:
    return [RulebaseOut.of(record) for record in store.list_rulebases()]


@router.get("/{rulebase_id}", summary="Read a rulebase")
def read(rulebase_id: RecordId, store: StoreDependency) -> RulebaseOut:
    return RulebaseOut.of(store.get_rulebase(rulebase_id))


@router.put("/{rulebase_id}", summary="Rename a rulebase and/or replace its text", responses={422: {"model": ErrorBody}})
def update(rulebase_id: RecordId, body: RulebaseUpdate, store: StoreDependency) -> RulebaseOut:
    if body.text is not None:
        parse(body.text)
    return RulebaseOut.of(store.update_rulebase(rulebase_id, name=body.name, text=body.text))


@router.delete("/{rulebase_id}", status_code=204, summary="Delete a rulebase")
def delete(rulebase_id: RecordId, store: StoreDependency) -> Response:
    store.delete_rulebase(rulebase_id)
    return Response(status_code=204)
