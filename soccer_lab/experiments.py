"""Experiment folders from Python: what `soccer-lab experiment PRESET --out FOLDER` wrote, read back with its
statistics and each finding's verdict, judged from statistics.csv as the report judges it."""

from __future__ import annotations

import json
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class Finding:
    """One claim of the chapter (or, `beyond` True, a question it leaves open) and the experiment's verdict:
    "agrees", "disagrees", "inconclusive", "too small to judge" or "not run"; `measured` and `test` say why."""

    preset: str
    where: str  # the chapter's section and figure
    claim: str
    verdict: str
    measured: str
    test: str
    beyond: bool = False


@dataclass(frozen=True)
class Experiment:
    """An experiment folder read back: its `options` (app.experiment.presets.ExperimentOptions), the
    presets it ran, `statistics` (one dict per preset, setting, trial and generation: statistics.csv),
    `bests` (each trial's best player, as the GA saw it and re-played: bests.csv) and its `findings`."""

    folder: Path
    options: Any
    presets: list[str]
    statistics: list[dict[str, Any]]
    bests: list[dict[str, Any]]
    findings: list[Finding]

    def verdicts(self) -> dict[str, int]:
        """How many of the chapter's findings got each verdict, as `soccer-lab experiment` sums them up."""
        from app.experiment.report import VERDICTS

        counts = {verdict: 0 for verdict in VERDICTS}
        for finding in self.findings:
            if not finding.beyond:
                counts[finding.verdict] += 1
        return counts

    @property
    def report(self) -> Path:
        """report.md, the written report (figures beside it, report.html for a browser)."""
        from app.experiment.report import REPORT_MD

        return self.folder / REPORT_MD


def open_experiment(folder: str | PathLike) -> Experiment:
    """The experiment a folder holds (one experiment seed; for replicates, open each seed-S folder).
    ValueError with one line for a folder holding no finished experiment.

    >>> import soccer_lab as sl
    >>> found = sl.open_experiment(experiment_folder)  # made by `soccer-lab experiment selection --out ...`
    >>> found.presets
    ['selection']
    >>> [f.verdict for f in found.findings if f.preset == "selection"]
    ['too small to judge', 'too small to judge', 'too small to judge']
    """
    from app.experiment.beyond import assess_questions
    from app.experiment.presets import ExperimentOptions, preset
    from app.experiment.report import assess_findings
    from app.experiment.runner import BESTS_FILE, MANIFEST, STATISTICS_FILE
    from app.experiment.table import BestsTable, StatisticsTable

    path = Path(folder)
    statistics, manifest = path / STATISTICS_FILE, path / MANIFEST
    if not statistics.is_file() or not manifest.is_file():
        raise ValueError(f"{path} holds no finished experiment (no {STATISTICS_FILE} and {MANIFEST}; replicates "
                         "are in its seed-S folders)")
    try:
        options = ExperimentOptions.from_identity(json.loads(manifest.read_text()))
        table = StatisticsTable.read(statistics)
        bests = BestsTable.read(path / BESTS_FILE) if (path / BESTS_FILE).is_file() else BestsTable([])
    except (OSError, ValueError, TypeError) as exc:  # pydantic's and the tables' errors are ValueErrors
        raise ValueError(f"{path}: cannot read the experiment: {exc}") from None
    run = [preset(name, options) for name in table.presets()]
    findings = [Finding(f.preset, f.where, f.claim, a.verdict, a.measured, a.test)
                for f, a in assess_findings(table, run)]
    findings += [Finding(q.preset, q.where, q.question, a.verdict, a.measured, a.test, beyond=True)
                 for q, a in assess_questions(table, bests, run)]
    return Experiment(path, options, table.presets(), table.rows, bests.rows, findings)
