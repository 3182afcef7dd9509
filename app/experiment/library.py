"""How an experiment appears in the app's library: the summary recorded in the store, and its folder's
files (report, statistics, figures, the trials' recordings) found safely for the API and the UI.

Only files inside the recorded folder, of the kinds the experiment writes, are ever handed out: a name
from a URL is a plain file name, and the resolved path (symbolic links followed) must stay inside.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from soccer_lab.app.experiment.figures import FIGURES_FOLDER
from soccer_lab.app.experiment.report import REPORT_HTML, REPORT_MD
from soccer_lab.app.experiment.runner import STATISTICS_FILE, TRIALS_FOLDER

if TYPE_CHECKING:
    from soccer_lab.app.experiment.presets import ExperimentOptions
    from soccer_lab.app.experiment.runner import ExperimentOutcome

FIGURE_SUFFIX = ".png"
RECORDING_SUFFIX = ".rrd"
# A plain file name: no separators, no leading dot (so neither "." nor ".." nor hidden files).
PLAIN_NAME = re.compile(r"[A-Za-z0-9_\-][A-Za-z0-9_.\-]*")


def library_summary(options: "ExperimentOptions", outcome: "ExperimentOutcome") -> dict[str, Any]:
    """What the store keeps about a finished experiment, or replicates of one (the files stay in its
    folder; a replicates folder has the summary report above the replicates' folders)."""
    seeds = getattr(outcome.report, "seeds", None)
    return {
        "presets": [p.name for p in outcome.plan.presets],
        "options": options.model_dump(),
        **({"seeds": seeds} if seeds is not None else {}),
        "trials": outcome.trials,
        "verdicts": outcome.report.verdicts(),
        "statistics": STATISTICS_FILE,
        "report": REPORT_HTML,
        "report_markdown": REPORT_MD,
        "figures": [f.path.as_posix() for f in outcome.report.figures],
        "figure_captions": [f.caption for f in outcome.report.figures],
    }


@dataclass(frozen=True)
class FigureFile:
    name: str  # file name inside figures/
    caption: str
    path: Path


class ExperimentFolder:
    """The files of one recorded experiment; every lookup returns None for anything not safely inside."""

    def __init__(self, path: str | Path, summary: dict[str, Any] | None = None):
        self.path = Path(path)
        self.summary = summary or {}

    @property
    def exists(self) -> bool:
        return self.path.is_dir()

    @property
    def report_html(self) -> Path | None:
        return self._inside(REPORT_HTML)

    @property
    def report_markdown(self) -> Path | None:
        return self._inside(REPORT_MD)

    @property
    def statistics(self) -> Path | None:
        return self._inside(STATISTICS_FILE)

    def figure(self, name: str) -> Path | None:
        return self._inside(FIGURES_FOLDER, name) if name.endswith(FIGURE_SUFFIX) else None

    def recording(self, name: str) -> Path | None:
        return self._inside(TRIALS_FOLDER, name) if name.endswith(RECORDING_SUFFIX) else None

    def figures(self) -> list[FigureFile]:
        """The figures on disk, in the report's order, each with the report's caption."""
        captions = dict(zip(self.summary.get("figures", []), self.summary.get("figure_captions", [])))
        listed = [Path(p).name for p in self.summary.get("figures", []) if isinstance(p, str)]
        on_disk = self._names(FIGURES_FOLDER, FIGURE_SUFFIX)
        ordered = [n for n in listed if n in on_disk] + sorted(on_disk - set(listed))
        found = []
        for name in ordered:
            path = self.figure(name)
            if path is not None:
                caption = captions.get(f"{FIGURES_FOLDER}/{name}") or Path(name).stem.replace("_", " ")
                found.append(FigureFile(name, caption, path))
        return found

    def recordings(self) -> list[str]:
        """File names of the trials' rerun recordings."""
        return sorted(n for n in self._names(TRIALS_FOLDER, RECORDING_SUFFIX) if self.recording(n) is not None)

    def _names(self, folder: str, suffix: str) -> set[str]:
        directory = self.path / folder
        if not directory.is_dir():
            return set()
        return {entry.name for entry in directory.iterdir() if entry.name.endswith(suffix)}

    def _inside(self, *parts: str) -> Path | None:
        if not all(PLAIN_NAME.fullmatch(part) for part in parts):
            return None
        try:
            root = self.path.resolve(strict=True)
            candidate = self.path.joinpath(*parts).resolve(strict=True)
        except (OSError, RuntimeError):  # missing, or a symbolic link loop
            return None
        if not candidate.is_relative_to(root) or not candidate.is_file():
            return None
        return candidate
