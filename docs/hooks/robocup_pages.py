"""mkdocs hook: `<!-- generated: robocup-study -->` and `<!-- generated: robocup-transfer -->` in a page become
what the RoboCup studies measured, read from docs/results/robocup/study.json and transfer.json, the files
scripts/robocup_results.py writes from an experiment's folder (figures: docs/images/robocup/), and
`<!-- generated: robocup-disagreement -->` what scripts/robocup_disagreement.py measured of the one finding that
disagrees (docs/results/robocup/disagreement.json). A study not recorded yet says so. The pages carry no copied
number."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from markdown_table import duration, load_average, table

STUDY_MARKER = "<!-- generated: robocup-study -->"
TRANSFER_MARKER = "<!-- generated: robocup-transfer -->"
CHAPTER_SIZE = (200, 25)  # Table 2's population and generations
DISAGREEMENT_MARKER = "<!-- generated: robocup-disagreement -->"
RESULTS = Path(__file__).resolve().parents[1] / "results" / "robocup"
NOT_RECORDED = ("Not recorded yet: run the study, then `python scripts/robocup_results.py FOLDER` "
                "(it writes docs/results/robocup/{name}.json).")
NOT_MEASURED = ("Not measured yet: `nice -n 19 .venv/bin/python scripts/robocup_disagreement.py FOLDER` (it writes "
                "docs/results/robocup/disagreement.json).")


def _findings(rows: list[list[object]], header: list[str]) -> list[str]:
    return table(header, rows).split("\n")


def study_markdown(record: dict[str, Any], page_depth: int = 1) -> str:
    """The robocup study's record as markdown for a page `page_depth` folders below docs/."""
    up = "../" * page_depth
    size = (f"{record['trials_finished']} of the {record['trials_planned']} GA trials of population "
            f"{record['population']} x {record['generations']} generations, each evaluation one trial of at most "
            f"{record['max_cycles']} cycles, the server's noise {'on' if record['server_noise'] else 'off'}, "
            f"skills `{record['skills']}`: {record['evaluations']:,} trials on rcssserver")
    finished = record["trials_finished"] == record["trials_planned"]
    lines = [f"**{'Run to the end' if finished else 'Run part-way'}:** {size}.", "",
             f"**Wall time:** {duration(record['wall_time_seconds'])} (the sum of the GA trials' own "
             f"times, each {duration(min(record['trial_wall_time_seconds']))} to "
             f"{duration(max(record['trial_wall_time_seconds']))}).", "",
             f"Recorded {record['recorded']} from `{record['folder']}` (`{record['command']}`; load average "
             f"{load_average(record['load_average'])} when recorded).", ""]
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
             f"sources, {record['starts']} starts each; load average "
             + (f"{load_average(record['load_average_before'])} before, {load_average(record['load_average'])} at "
                "the end" if record.get("load_average_before") else load_average(record["load_average"]))
             + (f"; wall time {record['wall_time_seconds'] / 60:.0f} min" if record.get("wall_time_seconds") else "")
             + ").", ""]
    size = record.get("size")
    if size and (size["population"], size["generations"]) != CHAPTER_SIZE:
        lines[:0] = [f"**Shrunk:** population {size['population']} × {size['generations']} generations in every "
                     f"part, against the chapter's {CHAPTER_SIZE[0]} × {CHAPTER_SIZE[1]}: a first look at the "
                     "questions, not their answer at the chapter's size.", ""]
    lines += _findings([[f["question"], f["measured"], f["verdict"], f["test"]] for f in record["findings"]],
                       ["question", "measured", "verdict", "test"])
    lines.append("")
    lines += [f"![{Path(figure).stem}]({up}{figure})" for figure in record["figures"]]
    return "\n".join(lines)


def _listed(items: list[str]) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1] if items else "none"


def _ends(ends: dict[str, int]) -> str:
    return ", ".join(f"{count} {reason}" for reason, count in sorted(ends.items(), key=lambda item: -item[1]))


def _against(most: int, chapter: int, tolerance: int) -> str:
    if abs(most - chapter) <= tolerance:
        return "agrees"
    return "DISAGREES (more)" if most > chapter else "DISAGREES (fewer)"


def _names(conditions: list[dict[str, Any]]) -> str:
    return _listed([f"`{c['name']}` ({c['most_goals']})" for c in conditions])


def _conclusion(conditions: list[dict[str, Any]], chapter: int, tolerance: int) -> str:
    """Which single changes bring the most goals (in brackets) to the chapter's, and which leave none above it."""
    single = [c for c in conditions if c["factor"] not in ("none", "both")]
    within = [c for c in single if c["agrees"]]
    at_most = [c for c in within if c["most_goals"] <= chapter]
    above = [c for c in single if c["most_goals"] > chapter + tolerance]
    below = [c for c in single if c["most_goals"] < chapter - tolerance]
    parts = [f"Of the single changes (most goals in brackets), {_names(within)} bring"
             f"{'s' if len(within) == 1 else ''} the most goals to within {tolerance} of the chapter's {chapter}"]
    if at_most:
        parts.append(f"only under {_names(at_most)} does no trial score more than {chapter}")
    elif within:
        parts.append(f"but some trials score more than {chapter} under {'it' if len(within) == 1 else 'each'}")
    if above:
        parts.append(f"{_names(above)} leave{'s' if len(above) == 1 else ''} trials above {chapter + tolerance}")
    if below:
        parts.append(f"{_names(below)} stop{'s' if len(below) == 1 else ''} nearly all scoring")
    return "; ".join(parts) + "."


def disagreement_markdown(record: dict[str, Any], page_depth: int = 1) -> str:
    """What scripts/robocup_disagreement.py measured: the study's high scorers, the players found again, their
    goals under each condition, and which conditions bring the most goals to the chapter's."""
    study, found, conditions = record["study"], record["players"], record["conditions"]
    chapter, tolerance = record["chapter_most_goals"], record["tolerance"]
    over = [t for t in study["trials"] if t["most_goals"] > chapter]
    lines = [f"**In the study's folder** (`{study['folder']}`, from each generation's best fitness): the most goals "
             f"any individual scored was {study['most_goals']}; {len(over)} of its {len(study['trials'])} GA trials "
             f"had an individual scoring more than {chapter} (trials {_listed([str(t['trial']) for t in over])}); of "
             f"its {study['evaluations']:,} evaluations {study['evaluations_4_goals']:,} scored 4 goals and "
             f"{study['evaluations_more_than_4']:,} more than 4.", ""]
    players = found["players"]
    if found.get("how") == "found again":
        again = found["trials_run_again"]
        lines += [f"**The players.** The folder keeps statistics only, and the study's trials played with the "
                  "server's noise, so its players cannot be played again bit for bit: its GA trials "
                  f"{_listed([str(t['trial']) for t in again])} (those whose high scorers came first) were run "
                  f"again with their own seeds for their first {found['generations']} generations, on the study's "
                  "settings. The most goals by generation, run again / in the study: "
                  + "; ".join(f"trial {t['trial']}: {' '.join(map(str, t['most_goals_by_generation']))} / "
                              f"{' '.join(map(str, t['study_most_goals_by_generation']))}" for t in again)
                  + f". The {len(players)} players are their highest scorers, from each trial in turn while its best "
                  f"had scored more than {chapter} (from trials "
                  f"{_listed(list(dict.fromkeys(str(p['trial']) for p in players)))}; goals in the evaluation that "
                  f"found them: {', '.join(str(p['goals_seen']) for p in players)}).", ""]
    header = ["condition", "changed", "goals per trial (mean)", "most goals", "trials > 3 goals", "trials > 4 goals",
              f"chapter's {chapter} (within {tolerance})", "kicks per trial (mean)", "trials ended by"]
    rows = [[f"`{c['name']}`", c["condition"], f"{c['mean_goals']:.2f}", c["most_goals"],
             f"{c['share_more_than_3']:.0%}", f"{c['share_more_than_4']:.0%}", _against(c["most_goals"], chapter, tolerance),
             c.get("mean_kicks", "-"), _ends(c["ends"])] for c in conditions]
    lines += _findings(rows, header) + [""]
    lines += [_conclusion(conditions, chapter, tolerance), ""]
    late = sum(c["late_cycles"] for c in conditions)
    cycles = sum(c["cycles"] for c in conditions)
    lines += [f"Recorded {record['recorded']} with `{record['command']}`: {len(players)} players x {record['starts']} "
              f"seeded starts under each condition, on {record['servers']} fresh servers per condition with the "
              f"server's noise on: {duration(sum(c['seconds'] for c in conditions))} of replays"
              + (f", after {duration(found['seconds'])} finding the players" if "seconds" in found else "")
              + f"; load average "
              f"{load_average(record['load_average_before'])} before, {load_average(record['load_average_after'])} after "
              f"({record['cores']} cores). Cycles the busy machine answered too late: {late:,} of {cycles:,}."
              + ("" if record.get("finished", True) else " **Stopped part-way:** the conditions above only."), ""]
    return "\n".join(lines)


def _recorded(name: str, render, results: Path, depth: int, missing: str = NOT_RECORDED) -> str:
    path = results / f"{name}.json"
    if not path.is_file():
        return missing.format(name=name)
    return render(json.loads(path.read_text(encoding="utf-8")), depth)


def render(markdown: str, page_depth: int = 1, results: Path = RESULTS) -> str:
    if STUDY_MARKER in markdown:
        markdown = markdown.replace(STUDY_MARKER, _recorded("study", study_markdown, results, page_depth))
    if TRANSFER_MARKER in markdown:
        markdown = markdown.replace(TRANSFER_MARKER, _recorded("transfer", transfer_markdown, results, page_depth))
    if DISAGREEMENT_MARKER in markdown:
        markdown = markdown.replace(DISAGREEMENT_MARKER, _recorded("disagreement", disagreement_markdown, results,
                                                                   page_depth, NOT_MEASURED))
    return markdown


def on_page_markdown(markdown: str, page: Any = None, **_: object) -> str:
    depth = page.file.src_uri.count("/") if page is not None else 1
    return render(markdown, depth)
