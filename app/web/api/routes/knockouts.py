"""/api/class/knockouts (classroom mode): the class knockout (app/web/classroom/knockout.py). The teacher starts
one; everyone in the class reads the bracket as it fills in, and its matches as CSV."""

from __future__ import annotations

from fastapi import APIRouter, Request, Response

from soccer_lab.app.store import KnockoutRecord
from soccer_lab.app.web.api.class_models import KnockoutOut, KnockoutStart
from soccer_lab.app.web.api.models import ErrorBody
from soccer_lab.app.web.api.routes.dependencies import RecordId, VisitorDependency
from soccer_lab.app.web.classroom.knockout import Knockout, knockout_csv
from soccer_lab.app.web.classroom.tournament import Tournament

router = APIRouter(prefix="/class/knockouts", tags=["classroom"], responses={403: {"model": ErrorBody}})


def _tournament(request: Request) -> Tournament:
    return request.app.state.tournament


def _knockout(request: Request) -> Knockout:
    return _tournament(request).knockout


@router.post("", status_code=202, summary="Start a knockout of every entry (the teacher's): a seeded draw, each "
             "tie the best of N matches; its ties are stored as they finish",
             responses={409: {"model": ErrorBody}, 422: {"model": ErrorBody}})
def start(body: KnockoutStart, request: Request, visitor: VisitorDependency) -> KnockoutOut:
    record = _knockout(request).start(visitor, _tournament(request).entries(), best_of=body.best_of, seed=body.seed,
                                      max_ticks=body.max_ticks)
    return _out(record, request)


@router.get("", summary="Every knockout, newest first, with its bracket so far")
def knockouts(request: Request) -> list[KnockoutOut]:
    return [_out(record, request) for record in _knockout(request).knockouts()]


@router.get("/{knockout_id}", summary="A knockout's draw and bracket: every tie played so far, match by match")
def knockout(knockout_id: RecordId, request: Request) -> KnockoutOut:
    return _out(_knockout(request).get(knockout_id), request)


@router.get("/{knockout_id}/matches.csv", name="knockout_csv", summary="A knockout's matches as CSV: one row per "
            "match (round, tie, players, goals, winner, seed)", response_class=Response,
            responses={200: {"content": {"text/csv": {}}}})
def matches_csv(knockout_id: RecordId, request: Request) -> Response:
    record = _knockout(request).get(knockout_id)
    return Response(knockout_csv(record), media_type="text/csv; charset=utf-8",
                    headers={"Content-Disposition": f'attachment; filename="knockout-{record.id}.csv"'})


def _out(record: KnockoutRecord, request: Request) -> KnockoutOut:
    return KnockoutOut.of(record, str(request.url_for("knockout_csv", knockout_id=record.id)))
