"""Put a RoboCup study's results into the docs: what ran, at what size, for how long, its findings and figures.

    .venv/bin/python scripts/robocup_results.py EXPERIMENT_FOLDER

The folder is one `soccer-lab experiment robocup` wrote (and, if it was also run there, `soccer-lab experiment
transfer`). It may still be running or be stopped part-way: the results are those of its finished GA trials
(trials/*.csv), assessed and drawn as the experiment's own report does (app/experiment/report.py, figures.py).
Writes docs/results/robocup/study.json (and transfer.json when the transfer study finished there) and the
figures into docs/images/robocup/; the RoboCup guide's pages show these files (docs/hooks/robocup_pages.py),
never copied numbers or hand-drawn figures. Prints what it wrote; exit status 2 with one line when the folder
holds no finished robocup trial.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any

from soccer_lab.app.experiment.figures import write_figures
from soccer_lab.app.experiment.presets import ROBOCUP, ExperimentOptions
from soccer_lab.app.experiment.report import assess_findings
from soccer_lab.app.experiment.runner import MANIFEST, TrialFolder, plan, read_runs
from soccer_lab.app.experiment.table import PRESET, SETTING, TRIAL, SEED, ALGORITHM, StatisticsTable

DOCS = Path(__file__).resolve().parent.parent / "docs"
RESULTS = DOCS / "results" / "robocup"
IMAGES = DOCS / "images" / "robocup"


class NoStudy(Exception):
    pass


def options_of(folder: Path) -> ExperimentOptions:
    """The folder's options as the command line gave them (its manifest read back)."""
    try:
        return ExperimentOptions.from_identity(json.loads((folder / MANIFEST).read_text()))
    except (OSError, ValueError) as exc:
        raise NoStudy(f"{folder} holds no experiment ({MANIFEST}: {exc})") from None


def finished_table(folder: Path, options: ExperimentOptions) -> tuple[StatisticsTable, int]:
    """The finished robocup trials as the experiment's statistics table, and how many trials the study plans."""
    experiment = plan(ROBOCUP, options)
    trials = TrialFolder(folder) if (folder / "trials").is_dir() else None
    rows = []
    for membership in experiment.memberships:
        spec = membership.spec
        if trials is None or not trials.finished(spec):
            continue
        keys = {PRESET: membership.preset, SETTING: membership.setting, TRIAL: spec.trial, SEED: spec.seed,
                ALGORITHM: spec.setting.algorithm}
        rows.extend({**keys, **row} for row in trials.read(spec))
    if not rows:
        raise NoStudy(f"no finished robocup trial in {folder / 'trials'}")
    with tempfile.TemporaryDirectory() as scratch:  # typed as the experiment's own statistics.csv is read
        path = Path(scratch) / "statistics.csv"
        path.write_text(StatisticsTable(rows).to_csv())
        return StatisticsTable.read(path), len(experiment.memberships)


def study_record(folder: Path, images: Path = IMAGES, command: str | None = None) -> dict[str, Any]:
    """The robocup study in `folder` as the docs show it; its figures drawn into `images`."""
    options = options_of(folder)
    table, planned = finished_table(folder, options)
    experiment = plan(ROBOCUP, options)
    (preset,) = experiment.presets
    (setting,) = preset.settings
    trials = table.trials(ROBOCUP, setting.label)
    wall_times = [float(t) for t in table.final(ROBOCUP, setting.label, "wall_time")]
    with tempfile.TemporaryDirectory() as scratch:
        drawn = write_figures(table, preset, Path(scratch))
        images.mkdir(parents=True, exist_ok=True)
        for figure in drawn:
            shutil.copyfile(Path(scratch) / figure.path, images / figure.path.name)
    return {
        "study": ROBOCUP,
        "folder": folder.name,  # the study's name, not this machine's path
        "command": command or f"soccer-lab experiment robocup --out {folder.name}",
        "recorded": datetime.date.today().isoformat(),
        "load_average": [round(x, 2) for x in os.getloadavg()],
        "trials_finished": len(trials),
        "trials_planned": planned,
        "population": setting.ga.population_size,
        "generations": setting.ga.max_generations,
        "max_cycles": setting.trial.max_ticks,
        "server_noise": setting.trial.noise,
        "skills": setting.trial.skills,
        "evaluations": int(sum(table.final(ROBOCUP, setting.label, "evaluations"))),
        "wall_time_seconds": round(sum(wall_times), 1),
        "trial_wall_time_seconds": [round(t, 1) for t in wall_times],
        "findings": [{"where": f.where, "claim": f.claim, "measured": a.measured, "verdict": a.verdict,
                      "test": a.test} for f, a in assess_findings(table, experiment.presets)
                     if f.preset == ROBOCUP],
        "figures": [{"file": f"images/robocup/{figure.path.name}", "caption": figure.caption} for figure in drawn],
    }


def transfer_record(folder: Path, images: Path = IMAGES, command: str | None = None) -> dict[str, Any] | None:
    """The transfer study in `folder` (None unless it finished there: its report exists)."""
    from soccer_lab.app.experiment import transfer

    if not (folder / transfer.REPORT_MD).is_file():
        return None
    options = options_of(folder)
    experiment = transfer.transfer_plan(options)
    table = StatisticsTable.read(folder / transfer.STATISTICS_FILE)
    with (folder / transfer.FOLDER / transfer.PLAYERS_FILE).open(newline="") as handle:
        players = list(csv.DictReader(handle))
    figures = sorted((folder / "figures").glob("transfer-*.png"))
    images.mkdir(parents=True, exist_ok=True)
    for figure in figures:
        shutil.copyfile(figure, images / figure.name)
    runs = [run for run in read_runs(folder) if run["preset"] == transfer.TRANSFER]
    return {
        "study": transfer.TRANSFER,
        "folder": folder.name,  # the study's name, not this machine's path
        "command": command or f"soccer-lab experiment transfer --out {folder.name}",
        "recorded": datetime.date.today().isoformat(),
        # the load the study ran under, as its invocations logged it (else the load now)
        "load_average_before": runs[0]["load_average_before"] if runs else None,
        "load_average": runs[-1]["load_average_after"] if runs else [round(x, 2) for x in os.getloadavg()],
        "sources": len({row["source"] for row in players}),  # as played: the manifest does not keep --trials
        "starts": transfer.STARTS,
        "size": {"population": options.population, "generations": options.generations},
        "wall_time_seconds": sum(run["seconds"] for run in runs) or None,
        "findings": [dict(zip(("question", "measured", "verdict", "test"), row))
                     for row in transfer.assess(experiment, table, players)],
        "figures": [f"images/robocup/{figure.name}" for figure in figures],
    }


def write(record: dict[str, Any], name: str, results: Path = RESULTS) -> Path:
    results.mkdir(parents=True, exist_ok=True)
    path = results / f"{name}.json"
    path.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the experiment folder `experiment robocup --out` wrote")
    parser.add_argument("--command", help="the command that ran the robocup study, as the docs should show it "
                                          "(default: `soccer-lab experiment robocup --out FOLDER`)")
    parser.add_argument("--transfer-command", help="the same for the transfer study")
    parser.add_argument("--transfer-only", action="store_true",
                        help="write transfer.json only: the folder's robocup trials are not the study to record "
                             "(a transfer study run apart from it, e.g. smaller)")
    args = parser.parse_args()
    if args.transfer_only:
        transferred = transfer_record(args.folder.resolve(), command=args.transfer_command)
        if transferred is None:
            print(f"error: {args.folder} holds no finished transfer study (no transfer report)", file=sys.stderr)
            raise SystemExit(2)
        print(f"wrote {write(transferred, 'transfer')}")
        return
    try:
        study = study_record(args.folder.resolve(), command=args.command)
    except NoStudy as exc:
        print(f"error: {exc}", file=sys.stderr)
        raise SystemExit(2) from None
    written = [write(study, "study")]
    transferred = transfer_record(args.folder.resolve(), command=args.transfer_command)
    if transferred is not None:
        written.append(write(transferred, "transfer"))
    for path in written:
        print(f"wrote {path}")
    print(f"figures in {IMAGES}")


if __name__ == "__main__":
    main()
