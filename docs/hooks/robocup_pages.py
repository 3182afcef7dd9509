"""mkdocs hook: `<!-- generated: robocup-study -->` and `<!-- generated: robocup-transfer -->` in a page become
what the RoboCup studies measured, read from docs/results/robocup/study.json and transfer.json, the files
scripts/robocup_results.py writes from an experiment's folder (figures: docs/images/robocup/). A study not
recorded yet says so. The pages carry no copied number."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

STUDY_MARKER = "<!-- generated: robocup-study -->"
TRANSFER_MARKER = "<!-- generated: robocup-transfer -->"
RESULTS = Path(__file__).resolve().parents[1] / "results" / "robocup"
NOT_RECORDED = ("Not recorded yet: run the study, then `python scripts/robocup_results.py FOLDER` "
                "(it writes docs/results/robocup/{name}.json).")


def _duration(seconds: float) -> str:
    minutes = round(seconds / 60)
    return f"{minutes // 60} h {minutes % 60:02d} min" if minutes >= 60 else f"{minutes} min"


def _cell(text: object) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _findings(rows: list[list[object]], header: list[str]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header),
            *("| " + " | ".join(_cell(c) for c in row) + " |" for row in rows)]


def _load(average: list[float]) -> str:
    return "/".join(f"{x:g}" for x in average)


def study_markdown(record: dict[str, Any], page_depth: int = 1) -> str:
    """The robocup study's record as markdown for a page `page_depth` folders below docs/."""
    up = "../" * page_depth
    size = (f"{record['trials_finished']} of the {record['trials_planned']} GA trials of population "
            f"{record['population']} x {record['generations']} generations, each evaluation one trial of at most "
            f"{record['max_cycles']} cycles, the server's noise {'on' if record['server_noise'] else 'off'}, "
            f"skills `{record['skills']}`: {record['evaluations']:,} trials on rcssserver")
    finished = record["trials_finished"] == record["trials_planned"]
    lines = [f"**{'Run to the end' if finished else 'Run part-way'}:** {size}.", "",
             f"**Wall time:** {_duration(record['wall_time_seconds'])} (the sum of the GA trials' own "
             f"times, each {_duration(min(record['trial_wall_time_seconds']))} to "
             f"{_duration(max(record['trial_wall_time_seconds']))}).", "",
             f"Recorded {record['recorded']} from `{record['folder']}` (`{record['command']}`; load average "
             f"{_load(record['load_average'])} when recorded).", ""]
    if not finished:
        lines += [f"The findings below are those of the {record['trials_finished']} finished trials; the same "
                  "command resumes the study, and the script records it again.", ""]
    lines += _findings([[f["where"], f["claim"], f["measured"], f["verdict"].upper() if f["verdict"] == "disagrees"
                         else f["verdict"], f["test"]] for f in record["findings"]],
                       ["chapter", "claim", "measured here", "verdict", "test"])
    lines.append("")
    for figure in record["figures"]:
        lines += [f"![{figure['caption']}]({up}{figure['file']})", ""]
    return "\n".join(lines)


def transfer_markdown(record: dict[str, Any], page_depth: int = 1) -> str:
    up = "../" * page_depth
    lines = [f"Recorded {record['recorded']} from `{record['folder']}` (`{record['command']}`: {record['sources']} "
             f"sources, {record['starts']} starts each; load average {_load(record['load_average'])}).", ""]
    lines += _findings([[f["question"], f["measured"], f["verdict"], f["test"]] for f in record["findings"]],
                       ["question", "measured", "verdict", "test"])
    lines.append("")
    lines += [f"![{Path(figure).stem}]({up}{figure})" for figure in record["figures"]]
    return "\n".join(lines)


def _recorded(name: str, render, results: Path, depth: int) -> str:
    path = results / f"{name}.json"
    if not path.is_file():
        return NOT_RECORDED.format(name=name)
    return render(json.loads(path.read_text(encoding="utf-8")), depth)


def render(markdown: str, page_depth: int = 1, results: Path = RESULTS) -> str:
    if STUDY_MARKER in markdown:
        markdown = markdown.replace(STUDY_MARKER, _recorded("study", study_markdown, results, page_depth))
    if TRANSFER_MARKER in markdown:
        markdown = markdown.replace(TRANSFER_MARKER, _recorded("transfer", transfer_markdown, results, page_depth))
    return markdown


def on_page_markdown(markdown: str, page: Any = None, **_: object) -> str:
    depth = page.file.src_uri.count("/") if page is not None else 1
    return render(markdown, depth)
