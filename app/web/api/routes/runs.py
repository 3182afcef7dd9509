"""/api/runs: start, list, read, rename, delete, stop and resume evolutions; their statistics, best and
recording."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from fastapi import APIRouter, Request, Response
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse

from soccer_lab.app.web.api.models import BestOut, ErrorBody, RunOut, RunRename, RunStart
from soccer_lab.app.web.api.routes.dependencies import RecordId, RunsDependency, StoreDependency
from soccer_lab.app.runs.outputs import RunFolder, best_quality_of
from soccer_lab.app.web.served_files import regular_file_inside
from soccer_lab.app.web.access import ScopedStore
from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.store import NotFound, RunRecord, StoreError

router = APIRouter(prefix="/runs", tags=["runs"], responses={404: {"model": ErrorBody}})
CONFLICT = {409: {"model": ErrorBody, "description": "The run's state does not allow this"}}


def _recording(record: RunRecord) -> Path | None:
    """The run's recording, when it is a regular file inside the run's folder (no symbolic link)."""
    folder = RunFolder(Path(record.folder))
    return regular_file_inside(folder.path, folder.recording.name)


def _out(record: RunRecord, store: ScopedStore, request: Request) -> RunOut:
    recording = None
    if _recording(record) is not None:
        recording = str(request.url_for("run_recording", run_id=record.id))
    runs = request.app.state.runs
    return RunOut.of(record, store.statistics(record.id), recording, runs.progress(record.id),
                     runs.queue_place(record.id))


@router.post("", status_code=201, responses=CONFLICT,
             summary="Start a GA or random-search run in the background (without ga.seed: a fresh random seed, "
             "recorded in its config); in classroom mode, when every core is busy, it is queued (status queued)")
def start(body: RunStart, runs: RunsDependency, store: StoreDependency, request: Request) -> RunOut:
    try:  # a thread (a plain def): the opponent's rules are parsed here, not while the body is validated
        record = runs.start(body.name, body.ga, body.game, algorithm=body.algorithm, env=body.env,
                            servers=body.servers, trial=body.trial, start_servers=body.start_servers,
                            opponent=body.opponent, coevolve=body.coevolve)
    except (RunStateError, StoreError):
        raise  # their own answers (409, 403, 422)
    except ValueError as exc:  # the opponent's rules: the 422 the body's validation would have given
        raise RequestValidationError([{"type": "value_error", "loc": ("body",), "msg": str(exc)}]) from None
    return _out(record, store, request)


@router.get("", summary="List runs")
def list_all(store: StoreDependency, request: Request) -> list[RunOut]:
    return [_out(record, store, request) for record in store.list_runs()]


@router.get("/{run_id}", summary="Read a run")
def read(run_id: RecordId, store: StoreDependency, request: Request) -> RunOut:
    return _out(store.get_run(run_id), store, request)


@router.patch("/{run_id}", summary="Rename a run", responses={422: {"model": ErrorBody}})
def rename(run_id: RecordId, body: RunRename, store: StoreDependency, request: Request) -> RunOut:
    return _out(store.rename_run(run_id, body.name), store, request)


@router.delete("/{run_id}", status_code=204, responses=CONFLICT,
               summary="Delete a run that is not running: its statistics, best individuals and its folder's files")
def delete(run_id: RecordId, runs: RunsDependency) -> Response:
    runs.delete(run_id)
    return Response(status_code=204)


@router.get("/{run_id}/statistics", summary="The run's statistics, one object per finished generation")
def statistics(run_id: RecordId, store: StoreDependency) -> list[dict[str, Any]]:
    return store.statistics(run_id)


@router.post("/{run_id}/stop", summary="Stop a run within about a second: the generation in progress is abandoned, "
             "every finished one kept (resume plays on as if never stopped); a queued run leaves the queue",
             responses=CONFLICT)
def stop(run_id: RecordId, runs: RunsDependency, store: StoreDependency, request: Request) -> RunOut:
    return _out(runs.stop(run_id), store, request)


@router.post("/{run_id}/resume", summary="Resume a stopped or interrupted run", responses=CONFLICT)
def resume(run_id: RecordId, runs: RunsDependency, store: StoreDependency, request: Request) -> RunOut:
    return _out(runs.resume(run_id), store, request)


@router.get("/{run_id}/best", summary="The best individual so far: rule text, chromosome, fitness and its true quality")
def best(run_id: RecordId, store: StoreDependency) -> BestOut:
    best = store.best_individual(run_id)
    return BestOut.of(best, best_quality_of(store.get_run(run_id).folder, best.fitness))


@router.get(
    "/{run_id}/recording.rrd",
    name="run_recording",
    summary="The run's rerun recording (open it in the rerun viewer)",
    response_class=FileResponse,
)
def recording(run_id: RecordId, store: StoreDependency) -> FileResponse:
    path = _recording(store.get_run(run_id))
    if path is None:
        raise NotFound("recording of run", run_id)
    return FileResponse(path, media_type="application/octet-stream", filename=f"run-{run_id}.rrd")
