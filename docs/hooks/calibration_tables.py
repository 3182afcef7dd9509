"""mkdocs hook: the Calibration page's measured tables, read from docs/results/calibration/*.json, the files
`python benchmarks/calibrate.py ... --record` writes (one per candidate setting of skills, roulette weighting,
noise and kicks). A page marks where each goes:

- `<!-- generated: calibration-candidates -->`: every candidate's `initial` trials against the chapter's
  Figs. 11-13, 16-17, the default first;
- `<!-- generated: calibration-selection -->`: the selection comparison per candidate that ran it;
- `<!-- generated: calibration-verdicts -->`: the default's verdict on each finding of the presets it ran,
  grouped by preset, with the report's measured figures for each disagreement;
- `<!-- generated: calibration-outcomes -->`: where the default's trials ended, every setting of every preset;
- `<!-- generated: calibration-runs -->`: how each candidate was measured (command, trials, wall time, load).

A figure lives in its file only; earlier calibrations (of earlier code) are in CHANGELOG.md."""

from __future__ import annotations

import json
from pathlib import Path

from markdown_table import load_average, table

RESULTS = Path(__file__).resolve().parents[1] / "results" / "calibration"
MARKERS = {name: f"<!-- generated: calibration-{name} -->"
           for name in ("candidates", "selection", "verdicts", "outcomes", "runs")}
NOT_RECORDED = "Not recorded yet: run `python benchmarks/calibrate.py ... --record`."
CHAPTER_ROW = ["**the chapter**", "20", "improves, plateaus around 0.75, tightly clustered", "",
               "\"very few generations\"", "never (\"early stopping did not occur\")", "grows; most score none",
               "some (the best scored 10)", "rises, settles near 2/3", "rise"]
SELECTION = ("roulette", "tournament", "elitist")


def _label(document: dict) -> str:
    c = document["candidate"]
    text = (f"{c['skills']}, {c['roulette_weighting']}, {'noise' if c['noise'] else 'no noise'}, "
            f"{'touches counted' if c['count_touches'] else 'kicks only'}")
    return f"{text} (**default**)" if document["default"] else text


def _quarter_half_end(generations: list[int]) -> list[int]:
    """Which checkpoints the table shows: a quarter, half and the end of the run (6, 12, 24 at full size)."""
    return sorted({min(1, len(generations) - 1), min(2, len(generations) - 1), len(generations) - 1})


def _along(values: list[float], generations: list[int]) -> str:
    return " → ".join(f"{values[i]:.2f}" for i in _quarter_half_end(generations))


def _ends(values: list[float], percent: bool = False) -> str:
    return " → ".join(f"{v:.0%}" if percent else f"{v:.2f}" for v in (values[0], values[-1]))


def candidates_section(documents: list[dict]) -> str:
    rows = [CHAPTER_ROW]
    for document in documents:
        s = document["initial"]
        n = s["trials"]
        generations = s["generations"]
        first = ("none" if s["first_scorer_median"] is None
                 else f"{s['first_scorer_median']:g} ({s['trials_with_scorer']}/{n})")
        cap = f"{s['trials_at_cap']}/{n}" + (f" (first at {s['first_at_cap']})" if s["first_at_cap"] is not None else "")
        low, high = s["last_average_quartiles"]
        rows.append([_label(document), n, _along(s["average_median"], generations), f"{low:.2f}–{high:.2f}", first,
                     cap, f"{s['share_scoring'][1]:.0%} → {s['share_scoring'][-1]:.0%}",
                     f"{s['over_4_goals_last']:.1%}", _ends(s["length_share"]), _ends(s["valid_rules"])])
    last = documents[0]["initial"]["generations"]
    marks = " → ".join(str(last[i]) for i in _quarter_half_end(last))
    return table(["candidate (skills, weighting, noise, kicks)", "trials",
                   f"Fig. 11: average, median at generation {marks}", "last generation's average, quartiles",
                   "Fig. 12: first generation with best ≤ 0.5 (median; trials)", "10-goal cap reached",
                   f"Fig. 13: share scoring, generation {last[1]} → {last[-1]}", f"> 4 goals, generation {last[-1]}",
                   f"Fig. 16: length / maximum, generation 0 → {last[-1]}",
                   f"Fig. 17: valid rules, generation 0 → {last[-1]}"], rows)


def _outcome(record: dict) -> str:
    text = f"{record['final_average_median']:.3f}"
    notes = []
    if record["never_spread"]:
        notes.append(f"{record['never_spread']} of {record['trials']} never spread kicking")
    if record["taken_over"]:
        notes.append(f"{record['taken_over']} of {record['trials']} taken over")
    return text + (f" ({'; '.join(notes)})" if notes else "")


def selection_section(documents: list[dict]) -> str:
    rows = []
    for document in documents:
        by_setting = {r["setting"]: r for r in document["outcomes"] if r["preset"] == "selection"}
        if not by_setting:
            continue
        initial = next(r for r in document["outcomes"] if r["preset"] == "initial")
        rows.append([_label(document), *(_outcome(by_setting[name]) if name in by_setting else "–" for name in SELECTION),
                     f"{initial['final_average_median']:.3f} ({initial['trials']} trials)"])
    if not rows:
        return "No candidate recorded with the selection comparison yet (`--also selection`)."
    return table(["candidate", *SELECTION, "`initial` plateau"], rows)


def _default(documents: list[dict]) -> dict | None:
    return next((d for d in documents if d["default"]), None)


def verdicts_section(documents: list[dict]) -> str:
    default = _default(documents)
    if default is None:
        return NOT_RECORDED
    presets: dict[str, list[dict]] = {}
    for verdict in default["verdicts"]:
        presets.setdefault(verdict["preset"], []).append(verdict)
    counts = {word: sum(v["verdict"].lower().startswith(word) for v in default["verdicts"])
              for word in ("agrees", "disagrees", "inconclusive", "too small")}
    rows = []
    for preset, verdicts in presets.items():
        agreeing = sum(v["verdict"].lower().startswith("agrees") for v in verdicts)
        others = [v for v in verdicts if not v["verdict"].lower().startswith("agrees")] or [None]
        for index, other in enumerate(others):
            shown = ["", "", "", ""] if other is None else [f"{other['where']}: {other['claim']}", other["verdict"],
                                                             other["measured"], other.get("reason", "")]
            rows.append([preset, f"{agreeing} of {len(verdicts)}"] if index == 0 else ["", ""])
            rows[-1] += shown
    size = default["size"]
    no_difference = [v for v in default["verdicts"]
                     if v.get("no_difference_found") and v["verdict"].lower().startswith("agrees")]
    summary = (f"The default at population {size['population']} × {size['generations']} generations, seed "
               f"{size['seed']} (measured {default['measured']}): **{counts['agrees']} of {len(default['verdicts'])} "
               f"findings agree, {counts['disagrees']} disagree, {counts['inconclusive']} inconclusive**"
               + (f", {counts['too small']} too small to judge" if counts["too small"] else "") + "."
               + (f" {len(no_difference)} of the agreements are \"no significant difference found\": the last "
                  "table says what difference each test could have detected." if no_difference else ""))
    sections = [summary, table(["preset", "agrees", "finding that does not agree", "verdict",
                                "measured (the report's figures)", "why (this run's data)"], rows)]
    if no_difference:
        sections.append(table(["agreement: no significant difference found", "the test, and what it could have detected"],
                              [[f"{v['where']}: {v['claim']}", v["test"]] for v in no_difference]))
    return "\n\n".join(sections)


def outcomes_section(documents: list[dict]) -> str:
    default = _default(documents)
    if default is None:
        return NOT_RECORDED
    return table(["preset", "setting", "trials", "final average: median (quartiles)", "run's best: median (std)",
                   "kicking never spread (final average ≥ 0.95)", "taken over by goal scorers (≤ 0.60)"],
                  [[r["preset"], r["setting"], r["trials"],
                    f"{r['final_average_median']:.3f} ({r['final_average_quartiles'][0]:.3f}–"
                    f"{r['final_average_quartiles'][1]:.3f})", f"{r['best_median']:.3f} ({r['best_std']:.3f})",
                    r["never_spread"], r["taken_over"]] for r in default["outcomes"]])


def runs_section(documents: list[dict]) -> str:
    return table(["candidate", "command", "trials per preset", "run / reused", "wall time", "measured, load before/after"],
                  [[_label(d), f"`{d['command']}`", ", ".join(f"{k} {v}" for k, v in d["size"]["trials"].items()),
                    f"{d['trials_run']} / {d['trials_reused']}",
                    f"{d['wall_seconds']:.0f} s on {d['workers']} workers" if d["trials_run"]
                    else "none: every trial reused (its wall time is the study's, [Replicates](replicates.md))",
                    f"{d['measured']}, {load_average(d['load_average_before'])} / {load_average(d['load_average_after'])}"]
                   for d in documents])


SECTIONS = {"candidates": candidates_section, "selection": selection_section, "verdicts": verdicts_section,
            "outcomes": outcomes_section, "runs": runs_section}


def load(results: Path = RESULTS) -> list[dict]:
    """Every recorded candidate, the default first."""
    documents = [json.loads(path.read_text(encoding="utf-8")) for path in sorted(results.glob("*.json"))]
    return sorted(documents, key=lambda d: not d["default"])


def render(markdown: str, results: Path = RESULTS) -> str:
    if not any(marker in markdown for marker in MARKERS.values()):
        return markdown
    documents = load(results)
    for name, marker in MARKERS.items():
        if marker in markdown:
            markdown = markdown.replace(marker, SECTIONS[name](documents) if documents else NOT_RECORDED)
    return markdown


def on_page_markdown(markdown: str, **_: object) -> str:
    return render(markdown)
