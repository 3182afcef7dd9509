"""/api/experiments: experiments recorded by `soccer-lab experiment`, their report, statistics, figures
and the trials' recordings, served only from inside each experiment's recorded folder."""

from __future__ import annotations

from pathlib import Path

from fastapi import APIRouter, Request
from fastapi.responses import FileResponse

from soccer_lab.app.web.api.models import ErrorBody, ExperimentOut, FigureOut, TrialRecordingOut
from soccer_lab.app.web.api.routes.dependencies import RecordId, StoreDependency
from soccer_lab.app.experiment.library import ExperimentFolder
from soccer_lab.app.web.access import ScopedStore
from soccer_lab.app.store import ExperimentRecord, NotFound

router = APIRouter(prefix="/experiments", tags=["experiments"], responses={404: {"model": ErrorBody}})
# The report is our own self-contained HTML (figures inline as data: URLs): let it do nothing else.
REPORT_POLICY = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"


def _folder(record: ExperimentRecord) -> ExperimentFolder:
    return ExperimentFolder(record.folder, record.summary)


def _out(record: ExperimentRecord, request: Request) -> ExperimentOut:
    folder = _folder(record)
    summary = record.summary

    def url(route: str, present: Path | None, **names: str) -> str | None:
        return str(request.url_for(route, experiment_id=record.id, **names)) if present is not None else None

    trials = summary.get("trials")
    return ExperimentOut(
        id=record.id,
        preset=record.preset,
        created=record.created,
        folder=Path(record.folder).name,  # where it lies is the server's business: no path leaves the API
        available=folder.exists,
        presets=[str(p) for p in summary.get("presets", [record.preset])],
        trials=trials if isinstance(trials, int) else None,
        options=summary.get("options") or {},
        verdicts={str(k): v for k, v in (summary.get("verdicts") or {}).items() if isinstance(v, int)},
        report=url("experiment_report", folder.report_html),
        report_markdown=url("experiment_report_markdown", folder.report_markdown),
        statistics=url("experiment_statistics", folder.statistics),
        figures=[FigureOut(name=f.name, caption=f.caption, url=url("experiment_figure", f.path, name=f.name))
                 for f in folder.figures()],
        recordings=[TrialRecordingOut(trial=Path(name).stem, url=url("experiment_recording", Path(name), name=name))
                    for name in folder.recordings()],
    )


def _file(store: ScopedStore, experiment_id: int, what: str, find) -> Path:
    path = find(_folder(store.get_experiment(experiment_id)))
    if path is None:
        raise NotFound(f"{what} of experiment", experiment_id)
    return path


@router.get("", summary="List recorded experiments")
def list_all(store: StoreDependency, request: Request) -> list[ExperimentOut]:
    return [_out(record, request) for record in store.list_experiments()]


@router.get("/{experiment_id}", summary="Read an experiment: summary, verdicts, links to its report and figures")
def read(experiment_id: RecordId, store: StoreDependency, request: Request) -> ExperimentOut:
    return _out(store.get_experiment(experiment_id), request)


@router.get("/{experiment_id}/report.html", name="experiment_report", response_class=FileResponse,
            summary="The experiment's report (HTML, figures inline)")
def report(experiment_id: RecordId, store: StoreDependency) -> FileResponse:
    path = _file(store, experiment_id, "report", lambda f: f.report_html)
    return FileResponse(path, media_type="text/html; charset=utf-8",
                        headers={"Content-Security-Policy": REPORT_POLICY})


@router.get("/{experiment_id}/report.md", name="experiment_report_markdown", response_class=FileResponse,
            summary="The experiment's report (Markdown; figures are relative links into figures/)")
def report_markdown(experiment_id: RecordId, store: StoreDependency) -> FileResponse:
    path = _file(store, experiment_id, "Markdown report", lambda f: f.report_markdown)
    return FileResponse(path, media_type="text/markdown; charset=utf-8")


@router.get("/{experiment_id}/statistics.csv", name="experiment_statistics", response_class=FileResponse,
            summary="Every statistic per generation per trial (CSV)")
def statistics(experiment_id: RecordId, store: StoreDependency) -> FileResponse:
    path = _file(store, experiment_id, "statistics", lambda f: f.statistics)
    return FileResponse(path, media_type="text/csv; charset=utf-8", filename=f"experiment-{experiment_id}.csv")


@router.get("/{experiment_id}/figures/{name}", name="experiment_figure", response_class=FileResponse,
            summary="One figure (PNG)")
def figure(experiment_id: RecordId, name: str, store: StoreDependency) -> FileResponse:
    return FileResponse(_file(store, experiment_id, f"figure {name!r}", lambda f: f.figure(name)),
                        media_type="image/png")


@router.get("/{experiment_id}/trials/{name}", name="experiment_recording", response_class=FileResponse,
            summary="One trial's rerun recording (.rrd; open it in the rerun viewer)")
def recording(experiment_id: RecordId, name: str, store: StoreDependency) -> FileResponse:
    path = _file(store, experiment_id, f"recording {name!r}", lambda f: f.recording(name))
    return FileResponse(path, media_type="application/octet-stream", filename=name)
