"""Copy the experiment figures the research guide shows into docs/images/research/, record what a
replicates folder holds into docs/results/research/study.json, and print its verdict tables as Markdown,
so the guide's figures, tables and run sizes come from a run, not by hand.

    python scripts/research_figures.py EXPERIMENT_FOLDER [--seed S] [--figure NAME ...] [--tables]
                                       [--record --command "soccer-lab experiment ..." [--merge-with STUDY]]

EXPERIMENT_FOLDER is what `soccer-lab experiment PRESET --replicates N --out EXPERIMENT_FOLDER` wrote. The
figures come from its figures/ (the verdict grid) and from seed-S/figures/ (one replicate's, default the
first seed); each is copied as <name> under docs/images/research/. --tables prints verdicts.csv as the
Markdown tables the guide's pages hold. --record writes study.json: the command and the size run, each
replicate's finished trials against the plan (so an unfinished run says how far it got), each
invocation's wall time and load average (the folder's runs.jsonl), and, once finished, the verdicts
(verdicts.csv) and each replicate's answers beyond the chapter with their measured figures and tests.
--merge-with STUDY keeps what an earlier record holds and the folder does not (other seeds' verdicts, the
experiments it did not run, every invocation): seeds judged again are re-run into a folder of their own and
merged with the seeds whose verdicts are current; the verdict grid is then drawn from the merged table.
docs/hooks/research_results.py shows it in the pages.
"""

from __future__ import annotations

import argparse
import csv
import json
import shutil
import sys
import tempfile
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


def merged_record(new: dict, earlier: dict) -> dict:
    """`new` (a folder's record) with what `earlier` holds beyond it: the seeds `new` lacks (their verdicts as
    recorded, each finding's summary and robust verdict counted again over all seeds), the experiments and
    seeds it did not run (their progress and answers), and every invocation of both."""
    from soccer_lab.app.experiment.replicates import VARIES
    from soccer_lab.app.experiment.verdicts import AGREES, NOT_RUN

    seeds = sorted(set(earlier["seeds"]) | set(new["seeds"]))
    judged = {(row["preset"], row["claim"]): row for row in new["verdicts"]}
    verdicts = []
    for row in earlier["verdicts"] + [r for k, r in judged.items()
                                      if k not in {(e["preset"], e["claim"]) for e in earlier["verdicts"]}]:
        again = judged.get((row["preset"], row["claim"]))
        if again is None and row in earlier["verdicts"]:
            verdicts.append(row)  # a question of an experiment `new` did not run: as recorded
            continue
        given = [(again if again is not None and f"seed {s}" in again else row).get(f"seed {s}", NOT_RUN)
                 for s in seeds]
        verdicts.append({"preset": row["preset"], "chapter": row["chapter"], "claim": row["claim"],
                         **{f"seed {s}": v for s, v in zip(seeds, given)},
                         "summary": f"agrees in {given.count(AGREES)} of {len(seeds)}",
                         "robust": given[0] if len(set(given)) == 1 else VARIES})
    ran = {(p["experiment"], p["seed"]) for p in new["progress"]}
    progress = [p for p in earlier["progress"] if (p["experiment"], p["seed"]) not in ran] + new["progress"]
    answered = {(a["preset"], a["seed"]) for a in new["answers"]}
    answers = [a for a in earlier["answers"] if (a["preset"], a["seed"]) not in answered] + new["answers"]
    order = [p["experiment"] for p in earlier["progress"] + new["progress"]]
    return {**new, "folder": f"{new['folder']} + {earlier['folder']}",
            "command": f"{new['command']}; the rest kept from {earlier['folder']} (recorded {earlier['recorded']}): "
                       f"{earlier['command']}",
            "seeds": seeds, "complete": new["complete"] and earlier["complete"],
            "progress": sorted(progress, key=lambda p: (order.index(p["experiment"]), p["seed"])),
            "runs": earlier["runs"] + new["runs"], "verdicts": verdicts,
            "answers": sorted(answers, key=lambda a: a["seed"])}


def verdict_grid(record: dict, target: Path = DOCS_IMAGES) -> Path:
    """The verdict grid (figures/replicates-verdicts.png) drawn from a record's table: the chapter's findings."""
    from soccer_lab.app.experiment.presets import BEYOND_NAMES
    from soccer_lab.app.experiment.replicates import Row, _verdict_figure

    rows = [Row(r["preset"], r["chapter"], r["claim"], [r[f"seed {s}"] for s in record["seeds"]], r["summary"],
                r["robust"]) for r in record["verdicts"] if r["preset"] not in BEYOND_NAMES]
    with tempfile.TemporaryDirectory() as scratch:
        drawn = Path(scratch) / _verdict_figure(Path(scratch), record["seeds"], rows).path
        target.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(drawn, target / SUMMARY_FIGURE)
    return target / SUMMARY_FIGURE


def record_study(folder: Path, command: str, target: Path = DOCS_RESULTS, merge_with: Path | None = None) -> Path:
    record = study_record(folder, command)
    if merge_with is not None:
        record = merged_record(record, json.loads(merge_with.read_text()))
    target.mkdir(parents=True, exist_ok=True)
    path = target / STUDY_FILE
    path.write_text(json.dumps(record, indent=1) + "\n")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=Path)
    parser.add_argument("--seed", type=int, help="the replicate whose figures are copied (default: the first)")
    parser.add_argument("--figure", nargs="+", default=[SUMMARY_FIGURE, *GUIDE_FIGURES], metavar="NAME")
    parser.add_argument("--tables", action="store_true", help="print verdicts.csv as Markdown tables")
    parser.add_argument("--record", action="store_true", help=f"write docs/results/research/{STUDY_FILE}")
    parser.add_argument("--command", default="", help="the command that ran the folder, for the record")
    parser.add_argument("--merge-with", type=Path, metavar="STUDY",
                        help=f"with --record: keep what this earlier {STUDY_FILE} holds beyond the folder")
    arguments = parser.parse_args()
    figures = tuple(arguments.figure)
    if arguments.record:
        merge_with = None
        if arguments.merge_with is not None:  # read before the record is overwritten: it may be the same file
            merge_with = Path(tempfile.mkstemp(suffix=".json")[1])
            shutil.copyfile(arguments.merge_with, merge_with)
        path = record_study(arguments.folder, arguments.command, merge_with=merge_with)
        print(f"recorded {path}", file=sys.stderr)
        if merge_with is not None:  # the folder's own grid holds its seeds only; the guide's figures are seed 0's
            merge_with.unlink()
            print(f"drew {verdict_grid(json.loads(path.read_text()))}", file=sys.stderr)
            figures = ()
    for path in copy_figures(arguments.folder, arguments.seed, figures):
        print(f"copied {path}", file=sys.stderr)
    if arguments.tables:
        print(markdown_tables(arguments.folder))


if __name__ == "__main__":
    main()
