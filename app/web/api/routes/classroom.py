"""/api/class (classroom mode, `soccer-lab serve --class`): join the class, the tournament's entries and
rounds, the class's settings and students. Teacher actions answer 403 to students; joining is the one
route RequestGuard lets through without the join code (app/web/api/guard.py)."""

from __future__ import annotations

from fastapi import APIRouter, Request, Response
from fastapi.responses import JSONResponse

from soccer_lab.app.runs.outputs import best_of_run, best_of_text
from soccer_lab.app.web.access import Visitor
from soccer_lab.app.web.api.class_models import (ClassOut, EntryOut, EntrySubmit, JoinRequest, RoundOut, RoundStart,
                                                 RoundStarted, SettingsChange, StudentOut, TeacherRequest, VisitorOut)
from soccer_lab.app.web.api.errors import error_response
from soccer_lab.app.web.api.guard import RATE_KEY_STATE
from soccer_lab.app.web.api.models import ErrorBody
from soccer_lab.app.web.api.routes.dependencies import RecordId, RunsDependency, StoreDependency, VisitorDependency
from soccer_lab.app.web.classroom.admission import (WRONG_GUESS_COST, Classroom, JoinRefused, WrongSecret,
                                                set_cookie_headers)
from soccer_lab.app.web.classroom.qr import qr_svg
from soccer_lab.app.web.classroom.settings import ClassSettings
from soccer_lab.app.web.classroom.tournament import Tournament, round_csv
from soccer_lab.fuzzy.printer import format_rulebase

router = APIRouter(prefix="/class", tags=["classroom"], responses={403: {"model": ErrorBody}})
JOIN_PATH = "/api/class/join"
TEACHER_PATH = "/api/class/teacher"


def _classroom(request: Request) -> Classroom:
    return request.app.state.classroom


def _tournament(request: Request) -> Tournament:
    return request.app.state.tournament


def _admitted(cookies: dict[str, str], body: dict) -> JSONResponse:
    response = JSONResponse(body)
    for value in set_cookie_headers(cookies):
        response.headers.append("set-cookie", value)
    return response


@router.post("/join", summary="Join the class: the join code and a display name; sets the class's cookies",
             responses={400: {"model": ErrorBody}})
def join(body: JoinRequest, request: Request) -> JSONResponse:
    try:
        student, cookies = _classroom(request).join(body.code, body.name, request.headers.get("cookie"))
    except WrongSecret as exc:
        return _guessed(request, exc)
    except JoinRefused as exc:
        return error_response(400, str(exc))
    return _admitted(cookies, {"name": student.name, "teacher": False})


@router.post("/teacher", summary="The teacher's sign-in: the token `serve --class` printed",
             responses={400: {"model": ErrorBody}})
def teacher(body: TeacherRequest, request: Request) -> JSONResponse:
    try:
        cookies = _classroom(request).teacher_login(body.token)
    except WrongSecret as exc:
        return _guessed(request, exc)
    return _admitted(cookies, {"name": "teacher", "teacher": True})


def _guessed(request: Request, refused: WrongSecret) -> JSONResponse:
    """A wrong code or token: its guess charged to the visitor's rate (the guard took one request of it)."""
    if (key := getattr(request.state, RATE_KEY_STATE, None)) is not None:
        _classroom(request).rate.charge(key, WRONG_GUESS_COST - 1)
    return error_response(400, str(refused))


@router.get("", summary="The class: its address, join code, who you are, its settings, the tournament's state")
def read(request: Request, visitor: VisitorDependency) -> ClassOut:
    classroom, tournament = _classroom(request), _tournament(request)
    return ClassOut(address=classroom.address, join_code=classroom.join_code,
                    you=VisitorOut(name=visitor.name, teacher=visitor.teacher),
                    settings=classroom.settings.model_dump(), playing=tournament.playing,
                    entries=len(tournament.entries()), rounds=len(tournament.rounds()))


@router.get("/qr.svg", summary="A QR code of the class's address", response_class=Response,
            responses={200: {"content": {"image/svg+xml": {}}}})
def qr(request: Request) -> Response:
    return Response(qr_svg(_classroom(request).address), media_type="image/svg+xml",
                    headers={"Cache-Control": "no-cache"})


# ---- the tournament's entries ----
@router.get("/entries", summary="The tournament's entries (their rules: your own, or all for the teacher)")
def entries(request: Request, visitor: VisitorDependency) -> list[EntryOut]:
    return [_entry_out(entry, visitor) for entry in _tournament(request).entries()]


@router.post("/entries", status_code=201, summary="Enter a rulebase: a student's under their name (replacing "
             "their earlier entry), the teacher's under the name given", responses={422: {"model": ErrorBody}})
def submit(body: EntrySubmit, request: Request, visitor: VisitorDependency, store: StoreDependency,
           runs: RunsDependency) -> EntryOut:
    if body.text is not None:
        text, source = body.text, "rules"
    elif body.rulebase_id is not None:
        record = store.get_rulebase(body.rulebase_id)
        figures = best_of_text(record.best_of)  # saved from a run's best: both its figures
        text, source = record.text, f"library: {record.name}" + (f", {figures}" if figures else "")
    else:
        text = format_rulebase(runs.best_rulebase(body.run_id), _tournament(request).vocabulary)
        source = best_of_text(best_of_run(store, body.run_id))
    entry = _tournament(request).submit(visitor, text, name=body.name, source=source)
    return _entry_out(entry, visitor)


@router.delete("/entries/{entry_id}", status_code=204, summary="Remove an entry (the teacher's)")
def remove(entry_id: RecordId, request: Request, visitor: VisitorDependency) -> Response:
    _tournament(request).remove(visitor, entry_id)
    return Response(status_code=204)


def _entry_out(entry, visitor: Visitor) -> EntryOut:
    mine = visitor.is_student and entry.student_id == visitor.student_id
    return EntryOut.of(entry, mine=mine, readable=mine or visitor.teacher)


# ---- rounds ----
@router.post("/rounds", status_code=202, summary="Start a round (the teacher's): every entry plays the same "
             "starts; its table is stored when complete", responses={409: {"model": ErrorBody}})
def start_round(body: RoundStart, request: Request, visitor: VisitorDependency) -> RoundStarted:
    return RoundStarted(**_tournament(request).start_round(visitor, starts=body.starts, seed=body.seed))


@router.get("/rounds", summary="Every round played, newest first, with its ranked table")
def rounds(request: Request) -> list[RoundOut]:
    return [_round_out(record, request) for record in _tournament(request).rounds()]


@router.get("/rounds/{round_id}", summary="A round's ranked table: goals, the chapter's fitness, kicks")
def round_table(round_id: RecordId, request: Request) -> RoundOut:
    return _round_out(_tournament(request).get_round(round_id), request)


@router.get("/rounds/{round_id}/table.csv", name="round_csv", summary="A round's table as CSV",
            response_class=Response, responses={200: {"content": {"text/csv": {}}}})
def round_table_csv(round_id: RecordId, request: Request) -> Response:
    record = _tournament(request).get_round(round_id)
    return Response(round_csv(record), media_type="text/csv; charset=utf-8",
                    headers={"Content-Disposition": f'attachment; filename="round-{record.id}.csv"'})


def _round_out(record, request: Request) -> RoundOut:
    return RoundOut.of(record, str(request.url_for("round_csv", round_id=record.id)))


# ---- the teacher's: settings and students ----
@router.get("/settings", summary="The class's settings")
def settings(request: Request) -> ClassSettings:
    return _classroom(request).settings


@router.put("/settings", summary="Change the class's settings (the teacher's)", responses={422: {"model": ErrorBody}})
def change_settings(body: SettingsChange, request: Request, visitor: VisitorDependency) -> ClassSettings:
    visitor.require_teacher("change the class's settings")
    _classroom(request).settings = body.settings()
    return _classroom(request).settings


@router.get("/students", summary="The students who joined (the teacher's)")
def students(request: Request, visitor: VisitorDependency) -> list[StudentOut]:
    visitor.require_teacher("list the students")
    return [StudentOut(id=s.id, name=s.name, created=s.created) for s in _classroom(request).store.list_students()]


@router.delete("/students/{student_id}", status_code=204, summary="Remove a student (the teacher's): their browser "
               "must join again, their entry goes")
def remove_student(student_id: RecordId, request: Request, visitor: VisitorDependency) -> Response:
    _tournament(request).remove_student(visitor, student_id)
    return Response(status_code=204)
