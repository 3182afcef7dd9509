"""Copy the experiment figures the research guide shows into docs/images/research/, record what a
replicates folder holds into docs/results/research/study.json, and print its verdict tables as Markdown,
so the guide's figures, tables and run sizes come from a run, not by hand.

    python scripts/research_figures.py EXPERIMENT_FOLDER [--seed S] [--figure NAME ...] [--tables]
                                       [--record --command "soccer-lab experiment ..."]

EXPERIMENT_FOLDER is what `soccer-lab experiment PRESET --replicates N --out EXPERIMENT_FOLDER` wrote. The
figures come from its figures/ (the verdict grid) and from seed-S/figures/ (one replicate's, default the
first seed); each is copied as <name> under docs/images/research/. --tables prints verdicts.csv as the
Markdown tables the guide's pages hold. --record writes study.json: the command and the size run, each
replicate's finished trials against the plan (so an unfinished run says how far it got), each
invocation's wall time and load average (the folder's runs.jsonl), and, once finished, the verdicts
(verdicts.csv) and each replicate's answers beyond the chapter with their measured figures and tests.
docs/hooks/research_results.py shows it in the pages.
"""

from __future__ import annotations

import argparse
import csv
import json
import shutil
import sys
from datetime import datetime, timezone
from pathlib import Path

DOCS_IMAGES = Path(__file__).resolve().parent.parent / "docs" / "images" / "research"
DOCS_RESULTS = Path(__file__).resolve().parent.parent / "docs" / "results" / "research"
STUDY_FILE = "study.json"
SUMMARY_FIGURE = "replicates-verdicts.png"
# The figures docs/research/replicates.md and open-questions.md show (a replicate's figures/ names).
GUIDE_FIGURES = ("uniform-crossover-best_fitness.png", "uniform-crossover-true_quality.png",
                 "rule-pressure-rules_and_bound.png", "rule-pressure-premises_per_rule.png",
                 "games-per-evaluation-best_fitness.png", "games-per-evaluation-true_quality.png",
                 "restarts-best_so_far.png", "restarts-true_quality.png", "initial-true_quality.png")


def copy_figures(folder: Path, seed: int | None, names: tuple[str, ...], target: Path = DOCS_IMAGES) -> list[Path]:
    seeds = sorted(int(p.name.removeprefix("seed-")) for p in folder.glob("seed-*") if p.is_dir())
    replicate = folder / f"seed-{seeds[0] if seed is None else seed}" / "figures"
    target.mkdir(parents=True, exist_ok=True)
    copied = []
    for name in names:
        source = folder / "figures" / name if name == SUMMARY_FIGURE else replicate / name
        if not source.is_file():
            print(f"missing: {source}", file=sys.stderr)
            continue
        shutil.copyfile(source, target / name)
        copied.append(target / name)
    return copied


def markdown_tables(folder: Path) -> str:
    """verdicts.csv as Markdown: the chapter's findings, then the answers beyond it."""
    with (folder / "verdicts.csv").open(newline="") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], rows[1:]
    beyond = {"uniform-crossover", "rule-pressure", "games-per-evaluation", "restarts"}
    lines = []
    for title, chosen in (("Findings of the chapter", [r for r in body if r[0] not in beyond]),
                          ("Beyond the chapter", [r for r in body if r[0] in beyond])):
        if chosen:
            lines += [f"**{title}**", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            lines += ["| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |" for row in chosen]
            lines.append("")
    return "\n".join(lines)


def _seeds(folder: Path) -> list[int]:
    return sorted(int(p.name.removeprefix("seed-")) for p in folder.glob("seed-*") if p.is_dir())


def study_record(folder: Path, command: str) -> dict:
    """What the folder holds: its size, each replicate's progress against the plan of the experiments run
    (runs.jsonl's presets; `all` and `all-plus` for a folder from before it was kept), each invocation, and
    the verdicts and answers once finished."""
    from soccer_lab.app.experiment.beyond import assess_questions
    from soccer_lab.app.experiment.presets import ALL, ALL_PLUS, ExperimentOptions, presets
    from soccer_lab.app.experiment.replicates import VERDICTS_FILE, replicate_folder
    from soccer_lab.app.experiment.runner import MANIFEST, TrialFolder, assemble, assemble_bests, plan, read_runs

    size = json.loads((folder / MANIFEST).read_text())
    seeds, runs = _seeds(folder), read_runs(folder)
    trials = {run["preset"]: run.get("trials") for run in runs}  # per experiment, its latest; None: the chapter's
    names = list(trials) or [ALL, ALL_PLUS]
    progress, answers = [], []
    for name in names:
        for seed in seeds:
            options = ExperimentOptions(**size, seed=seed, trials=trials.get(name))
            experiment, where = plan(name, options), replicate_folder(folder, seed)
            finished = [spec for spec in experiment.specs if TrialFolder(where).finished(spec)]
            progress.append({"experiment": name, "seed": seed, "trials": len(experiment.specs),
                             "finished": len(finished),
                             "games": sum(spec.setting.games for spec in experiment.specs),
                             "games_finished": sum(spec.setting.games for spec in finished)})
            if name == names[-1] and len(finished) == len(experiment.specs):
                chosen = presets(name, options)
                for question, assessment in assess_questions(assemble(experiment, where),
                                                             assemble_bests(experiment, where), chosen):
                    answers.append({"preset": question.preset, "where": question.where, "seed": seed,
                                    "question": question.question, "answer": assessment.shown,
                                    "measured": assessment.measured, "test": assessment.test})
    complete = all(row["finished"] == row["trials"] for row in progress if row["experiment"] == names[-1])
    verdicts = []
    if complete and (folder / VERDICTS_FILE).is_file():
        with (folder / VERDICTS_FILE).open(newline="") as handle:
            verdicts = list(csv.DictReader(handle))
    return {"folder": folder.name, "command": command, "recorded": datetime.now(timezone.utc).isoformat(
        timespec="seconds"), "size": size, "seeds": seeds, "complete": complete, "progress": progress,
        "runs": runs, "verdicts": verdicts, "answers": answers}


def record_study(folder: Path, command: str, target: Path = DOCS_RESULTS) -> Path:
    target.mkdir(parents=True, exist_ok=True)
    path = target / STUDY_FILE
    path.write_text(json.dumps(study_record(folder, command), indent=1) + "\n")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=Path)
    parser.add_argument("--seed", type=int, help="the replicate whose figures are copied (default: the first)")
    parser.add_argument("--figure", nargs="+", default=[SUMMARY_FIGURE, *GUIDE_FIGURES], metavar="NAME")
    parser.add_argument("--tables", action="store_true", help="print verdicts.csv as Markdown tables")
    parser.add_argument("--record", action="store_true", help=f"write docs/results/research/{STUDY_FILE}")
    parser.add_argument("--command", default="", help="the command that ran the folder, for the record")
    arguments = parser.parse_args()
    if arguments.record:
        print(f"recorded {record_study(arguments.folder, arguments.command)}", file=sys.stderr)
    for path in copy_figures(arguments.folder, arguments.seed, tuple(arguments.figure)):
        print(f"copied {path}", file=sys.stderr)
    if arguments.tables:
        print(markdown_tables(arguments.folder))


if __name__ == "__main__":
    main()
