"""mkdocs hook: the matches study's run and answers in docs/research/matches.md, read from
docs/results/research/matches.json (what `python scripts/matches_results.py FOLDER --record` writes):

- `<!-- generated: matches-run -->`: the command, the size, each setting's finished trials against the plan,
  each invocation's wall time with the load average around it, and the crowd share by generation of the
  co-evolved trials finished so far;
- `<!-- generated: matches-answers -->`: each question's answer, measured figures and test, and the study's
  figures, once every trial has finished.

A figure lives in the file only; an unfinished run says how far it got."""

from __future__ import annotations

import json
from pathlib import Path

from markdown_table import duration, load_average, table

RESULTS = Path(__file__).resolve().parents[1] / "results" / "research" / "matches.json"
RUN, ANSWERS = "<!-- generated: matches-run -->", "<!-- generated: matches-answers -->"
NOT_RECORDED = ("Not recorded yet: run the study, then `python scripts/matches_results.py FOLDER --record "
                "--command \"...\"`.")
FIGURES = (("matches-crowd_share.png", "Kiddie soccer: the crowd share by generation in the co-evolved runs"),
           ("matches-head_to_head.png", "Head to head: each trial's best, mean goal difference per match"))


def run_section(study: dict) -> str:
    size = study["size"]
    text = [f"Command: `{study['command'] or 'not given'}`; folder `{study['folder']}`, experiment seed "
            f"{size['seed']}; size: population {size['population']}, {size['generations']} generations, games of "
            f"{size['max_ticks']} ticks, each trial's best re-played on {size['replays']} fresh starts; recorded "
            f"{study['recorded']}. " + ("Finished." if study["complete"] else
                                        "**Not finished**: the answers below wait for every trial.")]
    text.append(table(["setting", "trials finished"],
                      [[p["setting"], f"{p['finished']} of {p['trials']}"] for p in study["progress"]]))
    if study["runs"]:
        text.append(table(["started", "wall time", "trials run", "skipped", "load average before / after", "cores"],
                          [[run["started"], duration(run["seconds"]), run["ran"], run["skipped"],
                            f"{load_average(run['load_average_before'])} / {load_average(run['load_average_after'])}",
                            run["cores"]] for run in study["runs"]]))
    else:
        text.append("No invocation of this folder finished with its wall time logged (runs.jsonl) yet.")
    crowd = study.get("crowd_share", {})
    if crowd:
        generations = max(len(c["median_by_generation"]) for c in crowd.values())
        shown = [g for g in range(generations) if g % 4 == 0 or g == generations - 1]
        text.append("Kiddie soccer so far: the share of ticks both players are within 5 m of the ball, median over "
                    "the co-evolved trials finished, by generation:\n\n"
                    + table(["setting", "trials", *(f"gen {g}" for g in shown)],
                            [[setting, c["trials"], *(f"{c['median_by_generation'][g]:.1%}"
                                                      if g < len(c["median_by_generation"]) else "-" for g in shown)]
                             for setting, c in crowd.items()]))
    return "\n\n".join(text)


def answers_section(study: dict) -> str:
    if not study["answers"]:
        return "No answers yet: the run above has not finished."
    text = [table(["question", "answer", "measured", "test"],
                  [[f"{a['where']} {a['question']}", a["answer"], a["measured"], a["test"]] for a in study["answers"]])]
    text += [f"![{caption}](../images/research/{name})" for name, caption in FIGURES]
    replicates = study.get("replicates")
    if replicates and replicates["answers"]:
        seeds = replicates["seeds"]
        text.append(f"The same study at experiment seeds {', '.join(map(str, seeds))} (`{replicates['command']}`, "
                    f"folder `{replicates['folder']}`): an answer is robust when every seed gives it.\n\n"
                    + table(["question", *(f"seed {seed}" for seed in seeds), "robust answer"],
                            [[a["where"], *a["by_seed"], a["robust"]] for a in replicates["answers"]]))
    return "\n\n".join(text)


def render(markdown: str, results: Path = RESULTS) -> str:
    if RUN not in markdown and ANSWERS not in markdown:
        return markdown
    if not results.is_file():
        return markdown.replace(RUN, NOT_RECORDED).replace(ANSWERS, NOT_RECORDED)
    study = json.loads(results.read_text(encoding="utf-8"))
    return markdown.replace(RUN, run_section(study)).replace(ANSWERS, answers_section(study))


def on_page_markdown(markdown: str, **_: object) -> str:
    return render(markdown)
