"""mkdocs hook: `<!-- generated: performance -->` in a page becomes one table of today's figures, read from
docs/results/*.json, the files the benchmarks write with `--record` (benchmarks/results.py); `<!-- generated:
figures NAME WORD -->` the figures of NAME.json whose name holds WORD (a guide's own few). A figure lives
in its file only; earlier figures are in CHANGELOG.md."""

from __future__ import annotations

import json
import re
from pathlib import Path

from markdown_table import load_average

MARKER = "<!-- generated: performance -->"
FIGURES = re.compile(r"<!-- generated: figures (\w+) (\w+) -->")
RESULTS = Path(__file__).resolve().parents[1] / "results"
SHOWN_ELSEWHERE = {"examples"}  # results that are not speeds, each in its guide's own table (docs/hooks/*_table.py)


def shown(value: object, unit: str) -> str:
    if isinstance(value, float):
        value = f"{value:,.3g}" if abs(value) < 1000 else f"{value:,.0f}"
    elif isinstance(value, int):
        value = f"{value:,}"
    return f"{value} {unit}".strip()


def performance_table(results: Path = RESULTS) -> str:
    documents = [json.loads(path.read_text(encoding="utf-8")) for path in sorted(results.glob("*.json"))
                 if path.stem not in SHOWN_ELSEWHERE]
    if not documents:
        return "No figures recorded yet: run a benchmark with `--record`."
    lines = ["| figure | measured | target | command | when, load average before/after |",
             "|---|---|---|---|---|"]
    for document in documents:
        when = (f"{document['measured']}, {load_average(document.get('load_average_before'))} / "
                f"{load_average(document.get('load_average_after'))}")
        for figure in document["figures"]:
            note = f" ({figure['note']})" if figure.get("note") else ""
            lines.append(f"| {figure['name']}{note} | **{shown(figure['value'], figure.get('unit', ''))}** | "
                         f"{figure.get('target', '')} | `{document['command']}` | {when} |")
    machines = {(d["machine"]["cores"], d["machine"]["python"]) for d in documents if d.get("machine")}
    described = "; ".join(f"{cores} cores, Python {python}" for cores, python in sorted(machines))
    return "\n".join(lines) + f"\n\nMeasured on: {described}. Load average: the 1-, 5- and 15-minute figures."


def figures_table(name: str, word: str, results: Path = RESULTS) -> str:
    """The figures of results/NAME.json whose name holds `word`, with the command and load that measured them."""
    path = results / f"{name}.json"
    if not path.is_file():
        return f"No figures recorded yet: run `python benchmarks/{name}.py --record`."
    document = json.loads(path.read_text(encoding="utf-8"))
    chosen = [figure for figure in document["figures"] if re.search(rf"\b{word}\b", figure["name"])]
    if not chosen:
        return f"No {word} figures recorded yet: run `python benchmarks/{name}.py --record`."
    lines = ["| figure | measured | target |", "|---|---|---|"]
    for figure in chosen:
        note = f" ({figure['note']})" if figure.get("note") else ""
        lines.append(f"| {figure['name']}{note} | **{shown(figure['value'], figure.get('unit', ''))}** | "
                     f"{figure.get('target', '')} |")
    return "\n".join(lines) + (f"\n\nMeasured {document['measured']} with `{document['command']}`, load average "
                               f"before/after {load_average(document.get('load_average_before'))} / "
                               f"{load_average(document.get('load_average_after'))}.")


def on_page_markdown(markdown: str, **_: object) -> str:
    if MARKER in markdown:
        markdown = markdown.replace(MARKER, performance_table())
    return FIGURES.sub(lambda match: figures_table(*match.groups()), markdown)
