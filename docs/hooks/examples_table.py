"""mkdocs hook: `<!-- generated: examples -->` in a page becomes the table of what each built-in example player
scores under each skill set, read from docs/results/examples.json (`benchmarks/examples.py --record`). The
benchmark names each figure "<example>, <skills> skills: goals a game" and notes how its games ended."""

from __future__ import annotations

import json
from pathlib import Path

MARKER = "<!-- generated: examples -->"
RESULTS = Path(__file__).resolve().parents[1] / "results" / "examples.json"
SKILL_SETS = ("sighted", "strict", "assisted")  # the default first, as the Play tab lists them


def examples_table(path: Path = RESULTS) -> str:
    document = json.loads(path.read_text(encoding="utf-8"))
    cells: dict[str, dict[str, str]] = {}
    for figure in document["figures"]:
        example, rest = figure["name"].rsplit(", ", 1)
        skills = rest.split(" skills", 1)[0]
        ended = figure.get("note", "").removeprefix("games end: ")
        cells.setdefault(example, {})[skills] = f"{figure['value']:.2f} ({ended})" if ended else f"{figure['value']:.2f}"
    lines = ["| example | " + " | ".join(f"{skills} skills" for skills in SKILL_SETS) + " |",
             "|---|" + "---|" * len(SKILL_SETS)]
    for example, by_skills in cells.items():
        lines.append(f"| {example} | " + " | ".join(by_skills.get(skills, "") for skills in SKILL_SETS) + " |")
    return ("\n".join(lines) + "\n\nGoals a game, and how the games ended (max-ticks: time up; goal-cap: the "
            f"10-goal cap; idle: 100 ticks without moving or kicking). Measured {document['measured']} by "
            f"`{document['command']}`.")


def on_page_markdown(markdown: str, **_: object) -> str:
    return markdown.replace(MARKER, examples_table()) if MARKER in markdown else markdown
