"""What the docs hooks share: a Markdown table of measured values, and a load average as the pages show it.
Not a hook itself; mkdocs puts a hook's folder on sys.path while loading it, so the hooks import this."""

from __future__ import annotations


def cell(text: object) -> str:
    """A value as one table cell: a `|` escaped, lines joined."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def table(columns: list[str], rows: list[list[object]]) -> str:
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    return "\n".join(lines + ["| " + " | ".join(cell(c) for c in row) + " |" for row in rows])


def load_average(average: list[float] | None) -> str:
    """The 1-, 5- and 15-minute load averages as "1.2/0.9/0.5" ("?" when not recorded)."""
    return "/".join(f"{x:g}" for x in average) if average else "?"


def duration(seconds: float) -> str:
    """A wall time as "1 h 05 min" or "4 min 07 s"."""
    minutes, second = divmod(round(seconds), 60)
    hours, minute = divmod(minutes, 60)
    return f"{hours} h {minute:02d} min" if hours else f"{minute} min {second:02d} s"
