"""mkdocs hook: the research guide's measured tables, read from docs/results/research/study.json, the file
`python scripts/research_figures.py FOLDER --record` writes from a replicates folder. A page marks where
each goes:

- `<!-- generated: research-run -->`: the command, the size, each replicate's finished trials against the
  plan, and each invocation's wall time with the load average around it;
- `<!-- generated: research-verdicts -->`: each finding of the chapter (and question beyond it) per
  replicate, and its robust verdict;
- `<!-- generated: research-answers -->`: each question beyond the chapter per replicate: answer, measured
  figures and test.

A figure lives in the file only; an unfinished run says how far it got, and the tables it cannot fill say
so instead of showing anything."""

from __future__ import annotations

import json
from pathlib import Path

from markdown_table import duration, load_average, table

RESULTS = Path(__file__).resolve().parents[1] / "results" / "research" / "study.json"
RUN, VERDICTS, ANSWERS = (f"<!-- generated: research-{name} -->" for name in ("run", "verdicts", "answers"))
NOT_RECORDED = ("Not recorded yet: run the study, then `python scripts/research_figures.py FOLDER --record "
                "--command \"...\"`.")


def run_section(study: dict) -> str:
    size = study["size"]
    text = [f"Command: `{study['command'] or 'not given'}`; folder `{study['folder']}`, experiment seeds "
            f"{', '.join(map(str, study['seeds']))}; size: population {size['population']}, {size['generations']} "
            f"generations (Table 2's control), games of {size['max_ticks']} ticks, each trial's best re-played on "
            f"{size['replays']} fresh starts; recorded {study['recorded']}. "
            + ("Finished." if study["complete"] else "**Not finished**: the verdicts below wait for every trial.")]
    text.append(table(["experiment", "seed", "trials finished", "games finished"],
                       [[p["experiment"], p["seed"], f"{p['finished']} of {p['trials']}",
                         f"{p['games_finished']:,} of {p['games']:,} ({p['games_finished'] / p['games']:.0%})"]
                        for p in study["progress"]]))
    if study["runs"]:
        total = sum(run["seconds"] for run in study["runs"])
        text.append(table(["invocation", "started", "wall time", "trials run", "skipped",
                            "load average before / after", "cores"],
                           [[f"{run['preset']} seeds {','.join(map(str, run['seeds']))}", run["started"],
                             duration(run["seconds"]), run["ran"], run["skipped"],
                             f"{load_average(run['load_average_before'])} / {load_average(run['load_average_after'])}",
                             run["cores"]] for run in study["runs"]]))
        text.append(f"Wall time, all invocations: {duration(total)}. Load average: the 1-, 5- and 15-minute "
                    "figures; above the core count, trials waited for a core.")
    else:
        text.append("No invocation of this folder finished with its wall time logged (runs.jsonl) yet.")
    return "\n\n".join(text)


def verdicts_section(study: dict) -> str:
    rows = study["verdicts"]  # verdicts.csv: the chapter's findings, then the questions beyond it
    if not rows:
        return "No verdicts yet: the run above has not finished."
    columns = list(rows[0])
    from soccer_lab.app.experiment.presets import BEYOND_NAMES

    chapter = [row for row in rows if row["preset"] not in BEYOND_NAMES]
    counts: dict[str, int] = {}
    for row in chapter:
        counts[row["robust"]] = counts.get(row["robust"], 0) + 1
    summary = "" if not chapter else (f"The chapter's {len(chapter)} findings at {len(study['seeds'])} seeds: "
               + ", ".join(f"**{n}** {verdict}" for verdict, n in sorted(counts.items(), key=lambda c: -c[1])) + ".")
    return (summary + "\n\n" if summary else "") + table(columns, [[row[c] for c in columns] for row in rows])


def answers_section(study: dict) -> str:
    if not study["answers"]:
        return "No answers yet: the run above has not finished its presets beyond the chapter."
    return table(["preset", "chapter", "seed", "answer", "measured", "test"],
                  [[a["preset"], a["where"], a["seed"], a["answer"], a["measured"], a["test"]]
                   for a in study["answers"]])


def render(markdown: str, results: Path = RESULTS) -> str:
    if not any(marker in markdown for marker in (RUN, VERDICTS, ANSWERS)):
        return markdown
    if not results.is_file():
        return markdown.replace(RUN, NOT_RECORDED).replace(VERDICTS, NOT_RECORDED).replace(ANSWERS, NOT_RECORDED)
    study = json.loads(results.read_text(encoding="utf-8"))
    return (markdown.replace(RUN, run_section(study)).replace(VERDICTS, verdicts_section(study))
            .replace(ANSWERS, answers_section(study)))


def on_page_markdown(markdown: str, **_: object) -> str:
    return render(markdown)
