"""/api/rulebases: the library of saved rulebases (only text that parses is saved)."""

from __future__ import annotations

from enum import Enum

from fastapi import APIRouter, Query, Response
from fastapi.exceptions import RequestValidationError

from soccer_lab.app.runs.outputs import best_of_run

from soccer_lab.app.web.api.models import ErrorBody, RulebaseCreate, RulebaseOut, RulebaseUpdate
from soccer_lab.app.web.api.routes.dependencies import RecordId, StoreDependency
from soccer_lab.app.web.api.rule_text import VOCABULARY, parse, playable
from soccer_lab.fuzzy.export import EXPORT_FORMATS, FORMATS
from soccer_lab.fuzzy.rule import Rulebase

router = APIRouter(prefix="/rulebases", tags=["rulebases"], responses={404: {"model": ErrorBody}})
ExportFormatName = Enum("ExportFormatName", {name: name for name in FORMATS}, type=str)


@router.post("", status_code=201, summary="Save a rulebase (a run's best with its figures: give `run_id`)",
             responses={422: {"model": ErrorBody}})
def create(body: RulebaseCreate, store: StoreDependency) -> RulebaseOut:
    rulebase = playable(parse(body.text))
    best_of = None if body.run_id is None else _best_of(store, body.run_id, rulebase)
    return RulebaseOut.of(store.create_rulebase(body.name, body.text, best_of=best_of))


def _best_of(store: StoreDependency, run_id: int, rulebase: Rulebase) -> dict:
    """The run's best's figures, if `rulebase` is that best (a 404 for an unknown run, a 422 for other rules)."""
    if parse(store.best_individual(run_id).rules) != rulebase:
        raise RequestValidationError([{"type": "value_error", "loc": ("body", "text"), "input": "",
                                       "msg": f"these rules are not run {run_id}'s best so far"}])
    return best_of_run(store, run_id)


@router.get("", summary="List saved rulebases")
def list_all(store: StoreDependency) -> list[RulebaseOut]:
    return [RulebaseOut.of(record) for record in store.list_rulebases()]


@router.get("/{rulebase_id}", summary="Read a rulebase")
def read(rulebase_id: RecordId, store: StoreDependency) -> RulebaseOut:
    return RulebaseOut.of(store.get_rulebase(rulebase_id))


@router.put("/{rulebase_id}", summary="Rename a rulebase and/or replace its text", responses={422: {"model": ErrorBody}})
def update(rulebase_id: RecordId, body: RulebaseUpdate, store: StoreDependency) -> RulebaseOut:
    if body.text is not None:
        playable(parse(body.text))
    return RulebaseOut.of(store.update_rulebase(rulebase_id, name=body.name, text=body.text))


@router.delete("/{rulebase_id}", status_code=204, summary="Delete a rulebase")
def delete(rulebase_id: RecordId, store: StoreDependency) -> Response:
    store.delete_rulebase(rulebase_id)
    return Response(status_code=204)


@router.get(
    "/{rulebase_id}/export",
    summary="Download a rulebase as our JSON, FCL (IEC 61131-7), fuzzylite's FLL or MATLAB's .fis",
    response_class=Response,
    responses={200: {"content": {f.media_type: {} for f in EXPORT_FORMATS.values()}}, 422: {"model": ErrorBody}},
)
def export(rulebase_id: RecordId, store: StoreDependency,
           format: ExportFormatName = Query(description="json, fcl, fll or fis")) -> Response:
    record = store.get_rulebase(rulebase_id)
    chosen = EXPORT_FORMATS[format.value]
    return Response(chosen.write(parse(record.text), VOCABULARY), media_type=chosen.media_type,
                    headers={"Content-Disposition": f'attachment; filename="{chosen.filename(record.name)}"'})
