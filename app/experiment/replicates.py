"""Replicates: the same experiment at several experiment seeds, so that a reader can tell a verdict that
holds from a lucky one.

The folder holds one whole experiment per seed (seed-<S>/: its trials, statistics, figures and report,
resumable as any experiment folder) and, above them, report.md and report.html with each finding's
verdict per replicate, how many replicates it agrees in, and its robust verdict: the verdict every
replicate gives, or "varies with the seed". The answers beyond the chapter are summarised the same way.
verdicts.csv holds the table; figures/replicates-verdicts.png draws it. All replicates' trials go to
one executor, replicate after replicate (an interrupted run leaves whole replicates), each's longest first.
"""

from __future__ import annotations

import csv
import html
import io
import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure as MatplotlibFigure
from matplotlib.patches import Patch

from soccer_lab.app.experiment.figures import DPI, FIGURES_FOLDER, Figure
from soccer_lab.app.experiment.presets import ROBOCUP, ExperimentOptions
from soccer_lab.app.experiment.report import REPORT_HTML, REPORT_MD, STYLE, Report, _cell, run_size
from soccer_lab.app.experiment.runner import (ExperimentError, ExperimentOutcome, Plan, Progress, RunClock,
                                              _write_atomically, assemble, assemble_bests, plan, prepare_folder,
                                              run_trials_in)
from soccer_lab.app.experiment.verdicts import AGREES, DISAGREES, INCONCLUSIVE, NOT_RUN, TOO_SMALL, VERDICTS

VARIES = "varies with the seed"
VERDICTS_FILE = "verdicts.csv"
VERDICTS_FIGURE = "replicates-verdicts.png"
MAX_REPLICATES = 100
LABEL_CLAIM_CHARACTERS = 48  # of a claim in the verdict grid's row labels
LABEL_INCHES_PER_CHARACTER = 0.055  # a row label's width per character at its 7 pt
LEGEND_INCHES = 1.6  # the verdict grid's legend, beside it
COLOURS = {AGREES: "#1a7f37", DISAGREES: "#c62828", INCONCLUSIVE: "#d4a72c", TOO_SMALL: "#9e9e9e",
           NOT_RUN: "#ffffff"}


def replicate_seeds(seed: int, replicates: int | None, seeds: list[int] | None) -> list[int]:
    """--seeds as given, else --replicates seeds counting up from --seed."""
    if seeds:
        if len(set(seeds)) != len(seeds):
            raise ExperimentError("--seeds: each seed once")
        if replicates is not None and replicates != len(seeds):
            raise ExperimentError(f"--replicates {replicates} but {len(seeds)} --seeds: give one or make them agree")
        return list(seeds)
    count = 1 if replicates is None else replicates
    if not 1 <= count <= MAX_REPLICATES:
        raise ExperimentError(f"--replicates: between 1 and {MAX_REPLICATES}")
    return [seed + i for i in range(count)]


def replicate_folder(folder: Path, seed: int) -> Path:
    return folder / f"seed-{seed}"


@dataclass(frozen=True)
class Row:
    """One finding (or question) across the replicates."""

    preset: str
    where: str
    claim: str
    verdicts: list[str]  # per replicate, as shown
    summary: str  # "agrees in k of N" or "same answer in k of N"
    robust: str  # the verdict all replicates give, or VARIES


@dataclass(frozen=True)
class ReplicatesReport:
    seeds: list[int]
    findings: list[Row]
    answers: list[Row]
    figures: list[Figure]

    def verdicts(self) -> dict[str, int]:
        """Robust verdicts (every replicate's), and how many vary with the seed."""
        counts = {f"robust: {v}": 0 for v in VERDICTS} | {VARIES: 0}
        for row in self.findings:
            counts[row.robust if row.robust == VARIES else f"robust: {row.robust}"] += 1
        return counts


@dataclass(frozen=True)
class ReplicatesOutcome:
    folder: Path
    replicates: list[ExperimentOutcome]
    report: ReplicatesReport
    ran: int
    skipped: int
    seconds: float

    @property
    def plan(self) -> Plan:
        """The first replicate's plan: the presets run (every replicate runs the same)."""
        return self.replicates[0].plan

    @property
    def trials(self) -> int:
        return sum(outcome.trials for outcome in self.replicates)


def run_replicates(preset_name: str, options: ExperimentOptions, seeds: list[int], folder: Path, executor: Any, *,
                   progress: Progress | None = None) -> ReplicatesOutcome:
    """Each seed's experiment in its own folder, all trials on one executor; then each replicate's report
    and the summary above them."""
    from soccer_lab.app.experiment.report import write_report

    clock = RunClock()
    on_servers = preset_name == ROBOCUP
    prepare_folder(folder, {k: v for k, v in options.identity(on_servers).items() if k != "seed"})
    experiments = []
    for seed in seeds:
        replicate = options.model_copy(update={"seed": seed})
        prepare_folder(replicate_folder(folder, seed), replicate.identity(on_servers))
        experiments.append((plan(preset_name, replicate), replicate_folder(folder, seed)))
    with executor:
        ran, skipped = run_trials_in(experiments, executor, progress)
    outcomes, headers = [], []
    for experiment, where in experiments:
        table, bests = assemble(experiment, where), assemble_bests(experiment, where)
        report = write_report(table, experiment.presets, where, bests)
        outcomes.append(ExperimentOutcome(where, experiment, table, report, 0, 0, 0.0))
        headers.append(run_size(table, bests, [p for p in experiment.presets if p.name in table.presets()]))
    header = headers[0]  # the replicates differ only in their seeds
    summary = write_replicates_report(folder, seeds, [o.report for o in outcomes], header)
    seconds = clock.log(folder, preset_name, options, seeds, ran, skipped)
    return ReplicatesOutcome(folder, outcomes, summary, ran, skipped, seconds)


def summarise(seeds: list[int], reports: list[Report]) -> tuple[list[Row], list[Row]]:
    """Findings and answers across the replicates (the reports are in the order of `seeds`)."""
    n = len(seeds)
    findings = []
    for i, (finding, _) in enumerate(reports[0].findings):
        verdicts = [report.findings[i][1].verdict for report in reports]
        agreeing = sum(v == AGREES for v in verdicts)
        findings.append(Row(finding.preset, finding.where, finding.claim, verdicts, f"agrees in {agreeing} of {n}",
                            verdicts[0] if len(set(verdicts)) == 1 else VARIES))
    answers = []
    for i, (question, _) in enumerate(reports[0].answers):
        given = [report.answers[i][1].verdict for report in reports]
        most = max(set(given), key=given.count)
        answers.append(Row(question.preset, question.where, question.question, given,
                           f"'{most}' in {given.count(most)} of {n}", most if given.count(most) == n else VARIES))
    return findings, answers


def write_replicates_report(folder: Path, seeds: list[int], reports: list[Report], header: str) -> ReplicatesReport:
    findings, answers = summarise(seeds, reports)
    findings = [row for row in findings if row.robust != NOT_RUN]  # their preset was not part of the experiment
    figures = [_verdict_figure(folder, seeds, findings)] if findings else []
    report = ReplicatesReport(seeds, findings, answers, figures)
    _write_atomically(folder / VERDICTS_FILE, _verdicts_csv(seeds, findings + answers))
    (folder / REPORT_MD).write_text(_markdown(report, header))
    (folder / REPORT_HTML).write_text(_html(report, header, folder))
    return report


def _columns(seeds: list[int]) -> list[str]:
    return [f"seed {seed}" for seed in seeds]


def _verdicts_csv(seeds: list[int], rows: list[Row]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["preset", "chapter", "claim", *_columns(seeds), "summary", "robust"])
    writer.writerows([row.preset, row.where, row.claim, *row.verdicts, row.summary, row.robust] for row in rows)
    return buffer.getvalue()


def _intro(report: ReplicatesReport, header: str) -> list[str]:
    counts = ", ".join(f"{n} {v}" for v, n in report.verdicts().items() if n)
    links = ", ".join(f"seed-{seed}/{REPORT_MD}" for seed in report.seeds)
    return [header,
            f"{len(report.seeds)} replicates, experiment seeds {', '.join(map(str, report.seeds))}. A verdict is "
            f"robust only when every replicate gives it; otherwise it {VARIES}."
            + (f" Findings: {counts}." if counts else ""),
            f"Each replicate's own report (figures, settings, measured values and tests): {links}."]


def _tables(report: ReplicatesReport) -> list[tuple[str, list[str], list[list[str]]]]:
    columns = _columns(report.seeds)
    tables = []
    if report.findings:
        tables.append(("Findings of the chapter", ["preset", "chapter", "claim", *columns, "summary", "robust verdict"],
                       [[r.preset, r.where, r.claim, *r.verdicts, r.summary, r.robust] for r in report.findings]))
    if report.answers:
        tables.append(("Beyond the chapter", ["preset", "chapter", "question", *columns, "summary", "robust answer"],
                       [[r.preset, r.where, r.claim, *r.verdicts, r.summary, r.robust] for r in report.answers]))
    return tables


def _markdown(report: ReplicatesReport, header: str) -> str:
    lines = [f"# soccer-lab: the experiments at {len(report.seeds)} seeds", ""]
    for paragraph in _intro(report, header):
        lines += [paragraph, ""]
    for title, columns, rows in _tables(report):
        lines += [f"## {title}", "", "| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
        lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
        lines.append("")
    lines += [f"![{f.caption}]({f.path.as_posix()})" for f in report.figures]
    return "\n".join(lines) + "\n"


def _html(report: ReplicatesReport, header: str, folder: Path) -> str:
    import base64

    parts = ["<!doctype html><html><head><meta charset='utf-8'><title>soccer-lab replicates</title>",
             f"<style>{STYLE}</style></head><body>",
             f"<h1>soccer-lab: the experiments at {len(report.seeds)} seeds</h1>"]
    parts += [f"<p>{html.escape(paragraph)}</p>" for paragraph in _intro(report, header)]
    for title, columns, rows in _tables(report):
        parts.append(f"<h2>{html.escape(title)}</h2><table><tr>"
                     + "".join(f"<th>{html.escape(c)}</th>" for c in columns) + "</tr>")
        parts += ["<tr>" + "".join(f"<td class='{html.escape(c)}'>{html.escape(c)}</td>" for c in row) + "</tr>"
                  for row in rows]
        parts.append("</table>")
    for figure in report.figures:
        data = base64.b64encode((folder / figure.path).read_bytes()).decode()
        parts.append(f"<figure><img alt='{html.escape(figure.caption)}' src='data:image/png;base64,{data}'>"
                     f"<figcaption>{html.escape(figure.caption)}</figcaption></figure>")
    return "\n".join(parts + ["</body></html>"])


def row_labels(rows: list[Row]) -> list[str]:
    """One label a row, never two alike (a section's figure often holds several findings): the preset, the
    chapter's place, the claim shortened, the summary."""
    labels = [f"{r.preset} {r.where}: {textwrap.shorten(r.claim, LABEL_CLAIM_CHARACTERS, placeholder='...')} "
              f"({r.summary})" for r in rows]
    seen: dict[str, int] = {}
    for i, label in enumerate(labels):
        seen[label] = seen.get(label, 0) + 1
        if seen[label] > 1:
            labels[i] = f"{label} [{seen[label]}]"
    return labels


def _verdict_figure(folder: Path, seeds: list[int], rows: list[Row]) -> Figure:
    """A grid: one row per finding, one column per replicate, coloured by verdict."""
    order = list(COLOURS)
    grid = np.array([[order.index(v) for v in row.verdicts] for row in rows])
    labels = row_labels(rows)
    # As wide as the longest label needs beside the grid and its legend: a fixed width cut the labels off.
    width = LABEL_INCHES_PER_CHARACTER * max(map(len, labels)) + max(2.0, 0.6 * len(seeds)) + LEGEND_INCHES
    figure = MatplotlibFigure(figsize=(width, 1.0 + 0.24 * len(rows)), dpi=DPI, layout="constrained")
    axes = figure.subplots()
    axes.imshow(grid, cmap=ListedColormap(list(COLOURS.values())), vmin=0, vmax=len(order) - 1, aspect="auto")
    axes.set_xticks(range(len(seeds)), [f"seed {s}" for s in seeds], fontsize=8)
    axes.set_yticks(range(len(rows)), labels, fontsize=7)
    axes.set_xticks(np.arange(len(seeds)) - 0.5, minor=True)
    axes.set_yticks(np.arange(len(rows)) - 0.5, minor=True)
    axes.grid(which="minor", color="white", linewidth=1.5)
    axes.tick_params(which="minor", length=0)
    axes.legend(handles=[Patch(facecolor=COLOURS[v], edgecolor="0.6", label=v) for v in order], fontsize=7,
                loc="upper left", bbox_to_anchor=(1.01, 1.0))
    caption = "Each finding's verdict per replicate"
    axes.set_title(caption, fontsize=9)
    relative = Path(FIGURES_FOLDER) / VERDICTS_FIGURE
    (folder / FIGURES_FOLDER).mkdir(parents=True, exist_ok=True)
    figure.savefig(folder / relative, metadata={"Software": None})
    return Figure(relative, caption)
