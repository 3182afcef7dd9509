"""Copy the experiment figures the research guide shows into docs/images/research/, and print the verdict
tables of a replicates folder as Markdown, so the guide's figures and tables come from a run, not by hand.

    python scripts/research_figures.py EXPERIMENT_FOLDER [--seed S] [--figure NAME ...] [--tables]

EXPERIMENT_FOLDER is what `soccer-lab experiment PRESET --replicates N --out EXPERIMENT_FOLDER` wrote. The
figures come from its figures/ (the verdict grid) and from seed-S/figures/ (one replicate's, default the
first seed); each is copied as <name> under docs/images/research/. --tables prints verdicts.csv as the
Markdown tables the guide's pages hold.
"""

from __future__ import annotations

import argparse
import csv
import shutil
import sys
from pathlib import Path

DOCS_IMAGES = Path(__file__).resolve().parent.parent / "docs" / "images" / "research"
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=Path)
    parser.add_argument("--seed", type=int, help="the replicate whose figures are copied (default: the first)")
    parser.add_argument("--figure", nargs="+", default=[SUMMARY_FIGURE, *GUIDE_FIGURES], metavar="NAME")
    parser.add_argument("--tables", action="store_true", help="print verdicts.csv as Markdown tables")
    arguments = parser.parse_args()
    for path in copy_figures(arguments.folder, arguments.seed, tuple(arguments.figure)):
        print(f"copied {path}", file=sys.stderr)
    if arguments.tables:
        print(markdown_tables(arguments.folder))


if __name__ == "__main__":
    main()
