"""Record what a `soccer-lab experiment matches` folder holds into docs/results/research/matches.json and copy its
figures into docs/images/research/, so docs/research/matches.md shows the study's run and answers from a run,
not by hand (docs/hooks/matches_results.py reads the file).

    python scripts/matches_results.py EXPERIMENT_FOLDER --record --command "soccer-lab experiment matches ..."

The record holds the command and size, each setting's finished trials against the plan (an unfinished run
says how far it got), each invocation's wall time and load average (runs.jsonl), the crowd share by
generation of the co-evolved trials finished so far (median over them), and, once every trial has finished,
each question's answer, measured figures and test, as the report gives them.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

DOCS_IMAGES = Path(__file__).resolve().parent.parent / "docs" / "images" / "research"
DOCS_RESULTS = Path(__file__).resolve().parent.parent / "docs" / "results" / "research"
RESULTS_FILE = "matches.json"
FIGURES = ("matches-crowd_share.png", "matches-head_to_head.png")  # the ones docs/hooks/matches_results.py shows


def matches_record(folder: Path, command: str) -> dict:
    from soccer_lab.app.experiment.beyond import assess_questions
    from soccer_lab.app.experiment.matches import matches_questions
    from soccer_lab.app.experiment.presets import MATCHES, ExperimentOptions
    from soccer_lab.app.experiment.runner import MANIFEST, TrialFolder, assemble, assemble_bests, plan, read_runs

    options = ExperimentOptions.from_identity(json.loads((folder / MANIFEST).read_text()))
    runs = read_runs(folder)  # the manifest leaves the trials out (more only add files): the last invocation's
    options = options.model_copy(update={"trials": next((r["trials"] for r in reversed(runs) if r.get("trials")), None)})
    experiment = plan(MATCHES, options)
    trials = TrialFolder(folder)
    progress = []
    for setting in experiment.presets[0].settings:
        specs = [m.spec for m in experiment.memberships if m.setting == setting.label]
        progress.append({"setting": setting.label, "trials": len(specs),
                         "finished": sum(trials.finished(spec) for spec in specs)})
    complete = all(p["finished"] == p["trials"] for p in progress)
    crowd = {}
    for setting in experiment.presets[0].settings:
        shares = [json.loads(trials.best(m.spec).read_text())["crowd_share"] for m in experiment.memberships
                  if m.setting == setting.label and setting.coevolve is not None and trials.best(m.spec).is_file()]
        if shares:
            crowd[setting.label] = {"trials": len(shares),
                                    "median_by_generation": [float(np.nanmedian(g)) for g in zip(*shares)]}
    answers = []
    if complete:
        table, bests = assemble(experiment, folder), assemble_bests(experiment, folder)
        preset = experiment.presets[0]
        questions, _ = matches_questions(folder, preset, bests)
        answers = [{"where": q.where, "question": q.question, "answer": a.shown + (f": {a.reason}" if a.reason else ""),
                    "measured": a.measured, "test": a.test}
                   for q, a in assess_questions(table, bests, [preset], questions)]
    return {"command": command, "folder": folder.name, "recorded": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M"),
            "size": {"population": options.population, "generations": options.generations,
                     "max_ticks": options.max_ticks, "replays": options.replays, "seed": options.seed},
            "progress": progress, "complete": complete, "runs": runs, "crowd_share": crowd,
            "answers": answers}


def replicates_record(folder: Path, command: str) -> dict:
    """The answers of a `--seeds`/`--replicates` run of the preset (its verdicts.csv): per seed, and robust."""
    import csv

    rows = list(csv.DictReader((folder / "verdicts.csv").open(encoding="utf-8")))
    seeds = [int(column.removeprefix("seed ")) for column in rows[0] if column.startswith("seed ")] if rows else []
    return {"command": command, "folder": folder.name, "seeds": seeds,
            "answers": [{"where": row["chapter"], "question": row["claim"],
                         "by_seed": [row[f"seed {seed}"] for seed in seeds], "robust": row["robust"]}
                        for row in rows if row["preset"] == "matches"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path)
    parser.add_argument("--record", action="store_true", help=f"write docs/results/research/{RESULTS_FILE}")
    parser.add_argument("--command", default="", help="the command that ran the study, as the page shows it")
    parser.add_argument("--replicates", type=Path, metavar="FOLDER",
                        help="also record the answers at more seeds: the folder of `experiment matches --seeds ...`")
    parser.add_argument("--replicates-command", default="", help="the command that ran the replicates")
    args = parser.parse_args()
    record = matches_record(args.folder, args.command)
    if args.replicates is not None:
        record["replicates"] = replicates_record(args.replicates, args.replicates_command)
    done = sum(p["finished"] for p in record["progress"])
    print(f"{done} of {sum(p['trials'] for p in record['progress'])} trials finished; "
          + ("complete" if record["complete"] else "not finished"))
    for answer in record["answers"]:
        print(f"{answer['where']}: {answer['answer']} ({answer['measured']})")
    if args.record:
        DOCS_RESULTS.mkdir(parents=True, exist_ok=True)
        (DOCS_RESULTS / RESULTS_FILE).write_text(json.dumps(record, indent=1) + "\n")
        DOCS_IMAGES.mkdir(parents=True, exist_ok=True)
        for name in FIGURES if record["complete"] else ():
            source = args.folder / "figures" / name
            if source.is_file():
                shutil.copyfile(source, DOCS_IMAGES / name)
            else:
                print(f"missing: {source}", file=sys.stderr)
        print(f"wrote {DOCS_RESULTS / RESULTS_FILE}")


if __name__ == "__main__":
    main()
