"""Where the benchmarks put the figures the docs show: one JSON file per benchmark in docs/results/.

A figure has one home. A benchmark run with `--record` writes its file (the figures, the command that
measured them, the load average before and after, the machine); the docs' Performance page reads every
file there, so no guide carries a copied number. Earlier figures are history: CHANGELOG.md keeps them.

    from results import Figure, add_record_option, load_average, record   # benchmarks/ is the script's folder
    add_record_option(parser)
    ...
    if args.record:
        record("trial", [Figure("Table 2 trial", 4.1, "s", target="< 10 s")], command="python benchmarks/trial.py --full")
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import sys
from dataclasses import asdict, dataclass
from pathlib import Path

RESULTS_DIR = Path(__file__).resolve().parent.parent / "docs" / "results"


@dataclass(frozen=True)
class Figure:
    """One measured figure: what it is, its value and unit, and the target it is held to (if any)."""

    name: str
    value: float | int | str
    unit: str = ""
    target: str = ""
    note: str = ""


def add_record_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--record", action="store_true",
                        help=f"write the figures to {RESULTS_DIR.relative_to(RESULTS_DIR.parent.parent)}/ "
                             "for the docs' Performance page (measure on a quiet machine)")


def this_command() -> str:
    """The command that ran this benchmark, as the docs show it (without --record)."""
    return " ".join(["python", f"benchmarks/{Path(sys.argv[0]).name}", *(a for a in sys.argv[1:] if a != "--record")])


def load_average() -> list[float]:
    return [round(x, 2) for x in os.getloadavg()]


def record(benchmark: str, figures: list[Figure], command: str, load_before: list[float] | None = None,
           directory: Path = RESULTS_DIR) -> Path:
    """Write docs/results/<benchmark>.json (replacing the previous measurement of that benchmark)."""
    return record_document(directory / f"{benchmark}.json",
                           {"benchmark": benchmark, "figures": [asdict(figure) for figure in figures]},
                           command=command, load_before=load_before)


def record_document(path: Path, document: dict, command: str, load_before: list[float] | None = None) -> Path:
    """Write `document` to `path` with what every recorded measurement carries: the command, the day, the
    load average before and after, the machine (a script whose results are tables, not figures, uses this)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    document = {**document, "command": command, "measured": datetime.date.today().isoformat(),
                "load_average_before": load_before, "load_average_after": load_average(),
                "machine": {"cores": os.cpu_count(), "python": platform.python_version(),
                            "system": platform.platform(terse=True)}}
    path.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
    shown = path.relative_to(RESULTS_DIR.parent.parent) if path.is_relative_to(RESULTS_DIR) else path
    print(f"recorded in {shown}", file=sys.stderr)
    return path
