"""Experiment folders from Python: what `soccer-lab experiment PRESET --out FOLDER` wrote, read back with its
statistics and each finding's verdict, judged from statistics.csv as the report judges it."""

from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
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
    """An experiment folder read back: its `options` (soccer_lab.app.experiment.presets.ExperimentOptions), the
    presets it ran, `statistics` (one dict per preset, setting, trial and generation: statistics.csv),
    `bests` (each trial's best player, as the GA saw it and re-played: bests.csv) and its `findings`.
    Replicates (`--replicates`, `--seeds`): `replicates` holds each seed's experiment, `findings` each
    finding's robust verdict (the one every replicate gives, else "varies with the seed"), `statistics`
    and `bests` every replicate's rows."""

    folder: Path
    options: Any = field(repr=False)
    presets: list[str]
    statistics: list[dict[str, Any]] = field(repr=False)
    bests: list[dict[str, Any]] = field(repr=False)
    findings: list[Finding] = field(repr=False)
    replicates: list["Experiment"] = field(default_factory=list, repr=False)

    def verdicts(self) -> dict[str, int]:
        """How many of the chapter's findings got each verdict, as `soccer-lab experiment` sums them up
        (for replicates: each robust verdict, and how many vary with the seed)."""
        from soccer_lab.app.experiment.replicates import VARIES
        from soccer_lab.app.experiment.verdicts import VERDICTS

        counts = {self._shown(verdict): 0 for verdict in VERDICTS} | ({VARIES: 0} if self.replicates else {})
        for finding in self.findings:
            if not finding.beyond:
                counts[self._shown(finding.verdict)] += 1
        return counts

    def _shown(self, verdict: str) -> str:
        """The verdict as the command's summary names it: the replicates' is robust unless it varies."""
        from soccer_lab.app.experiment.replicates import VARIES

        return f"robust: {verdict}" if self.replicates and verdict != VARIES else verdict

    @property
    def report(self) -> Path:
        """report.md, the written report (figures beside it, report.html for a browser)."""
        from soccer_lab.app.experiment.report import REPORT_MD

        return self.folder / REPORT_MD


def open_experiment(folder: str | PathLike) -> Experiment:
    """The experiment a folder holds, or its replicates (the folder of `--replicates` or `--seeds`).
    ValueError with one line for a folder holding no finished experiment.

    >>> import soccer_lab as sl
    >>> found = sl.open_experiment(experiment_folder)  # made by `soccer-lab experiment selection --out ...`
    >>> found.presets
    ['selection']
    >>> [f.verdict for f in found.findings if f.preset == "selection"]
    ['too small to judge', 'too small to judge', 'too small to judge']
    """
    from soccer_lab.app.experiment.beyond import assess_questions
    from soccer_lab.app.experiment.presets import ExperimentOptions, preset
    from soccer_lab.app.experiment.report import assess_findings
    from soccer_lab.app.experiment.runner import BESTS_FILE, MANIFEST, STATISTICS_FILE
    from soccer_lab.app.experiment.table import BestsTable, StatisticsTable

    path = Path(folder)
    statistics, manifest = path / STATISTICS_FILE, path / MANIFEST
    if not statistics.is_file() and _replicate_folders(path):
        return _replicates(path, [open_experiment(each) for each in _replicate_folders(path)])
    if not statistics.is_file() or not manifest.is_file():
        raise ValueError(f"{path} holds no finished experiment (no {STATISTICS_FILE} and {MANIFEST})")
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


def _replicate_folders(folder: Path) -> list[Path]:
    """The seed-S folders of the replicates in `folder`, by seed (as runs.jsonl lists the seeds run)."""
    from soccer_lab.app.experiment.replicates import replicate_folder
    from soccer_lab.app.experiment.runner import STATISTICS_FILE, read_runs

    seeds = sorted({seed for entry in read_runs(folder) for seed in entry.get("seeds", ())})
    return [replicate_folder(folder, seed) for seed in seeds
            if (replicate_folder(folder, seed) / STATISTICS_FILE).is_file()] if len(seeds) > 1 else []


def _replicates(folder: Path, replicates: list[Experiment]) -> Experiment:
    """Replicates as one experiment: each finding with the verdict all replicates give, else VARIES (the
    findings of presets not run left out, as the replicates' report leaves them)."""
    from soccer_lab.app.experiment.replicates import VARIES
    from soccer_lab.app.experiment.verdicts import NOT_RUN

    findings = []
    for i, finding in enumerate(replicates[0].findings):
        verdicts = {replicate.findings[i].verdict for replicate in replicates}
        if verdicts == {NOT_RUN}:
            continue
        findings.append(replace(finding, verdict=verdicts.pop() if len(verdicts) == 1 else VARIES,
                                measured="; ".join(r.findings[i].measured for r in replicates)))
    return Experiment(folder, replicates[0].options, replicates[0].presets,
                      [row for r in replicates for row in r.statistics], [row for r in replicates for row in r.bests],
                      findings, replicates)
