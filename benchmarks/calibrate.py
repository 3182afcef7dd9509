"""Calibration: for one candidate setting of the choices the chapter leaves open (skill set, roulette
weighting, noise, whether body pushes count as kicks), run the chapter's Table 2 trials and its GA
against random search, and print the chapter's SimpleSoccer figures (as its text describes them)
beside ours.

    python benchmarks/calibrate.py --skills strict --roulette-weighting linear       # full size
    python benchmarks/calibrate.py --skills assisted --trials 3 --population 50      # a quick look

Full size is the chapter's: `initial` (20 Table 2 trials: Figs. 11-13, 16-17 at 64 genes) and `random`
(10 trials each of the 100-generation elitist GA and of random search at 20,000 evaluations: Figs. 28,
31). `--also selection long ...` adds other presets of the study, for their verdicts. The trials run
through the experiment machinery (app/experiment/), into --out when given, so a second call with the
same options reuses them; a table of every setting's outcome and the report's own verdicts on the
presets run follow. `--record` also writes them to docs/results/calibration/<candidate>.json, the file
the docs' Calibration page reads (docs/hooks/calibration_tables.py); point `--out` at a study's replicate
(`--out runs/all-x3/seed-0 --also ...`) to judge the default from the trials the study already ran.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.presets import PRESET_NAMES, ExperimentOptions
from soccer_lab.app.experiment.report import GOAL_SCORING, NEVER_KICKING, SCORERS_SPREAD, assess_findings
from soccer_lab.app.experiment.runner import Plan, assemble, plan, prepare_folder, run_trials
from soccer_lab.app.experiment.table import StatisticsTable
from soccer_lab.ga.config import GAConfig
from soccer_lab.soccer.config import SKILL_SET_NAMES
from results import RESULTS_DIR, load_average, record_document, this_command  # benchmarks/results.py

INITIAL, RANDOM = "initial", "random"
GOAL_CAP_FITNESS = GAConfig().target_fitness  # 10 goals (Table 1): a run would stop here (section 5.3)
CHECKPOINTS = (0.0, 0.25, 0.5, 0.75, 1.0)  # where along the run curves are shown (share of the generations)


class Printer:
    """Progress on stderr, in evaluations, so the table on stdout stays clean."""

    def __init__(self) -> None:
        self.started = time.perf_counter()

    def update(self, completed: int, total: int, *, skipped: int = 0) -> None:
        seconds = time.perf_counter() - self.started
        print(f"\r{completed}/{total} evaluations, {seconds:.0f} s", end="", file=sys.stderr, flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    defaults = ExperimentOptions()
    parser.add_argument("--skills", choices=SKILL_SET_NAMES, default=defaults.skills)
    parser.add_argument("--roulette-weighting", choices=("linear", "inverse"), default=defaults.roulette_weighting)
    parser.add_argument("--noise", action=argparse.BooleanOptionalAction, default=defaults.noise)
    parser.add_argument("--count-touches", action=argparse.BooleanOptionalAction, default=defaults.count_touches,
                        help="count every tick the player's body pushes the ball as a kick")
    parser.add_argument("--trials", type=int, help="trials per setting (default: the chapter's, 20 and 10)")
    parser.add_argument("--population", type=int, default=defaults.population)
    parser.add_argument("--generations", type=int, default=defaults.generations)
    parser.add_argument("--seed", type=int, default=defaults.seed)
    parser.add_argument("--no-random", action="store_true", help="skip the GA against random search (Figs. 28, 31)")
    parser.add_argument("--also", nargs="+", default=[], metavar="PRESET",
                        choices=[name for name in PRESET_NAMES if name not in (INITIAL, RANDOM)],
                        help="other presets of the study to run, for their verdicts (e.g. selection long)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", type=Path, help="experiment folder to keep (and reuse) the trials in")
    parser.add_argument("--record", action="store_true",
                        help="write the tables to docs/results/calibration/ for the docs' Calibration page")
    arguments = parser.parse_args()
    options = ExperimentOptions(trials=arguments.trials, population=arguments.population,
                                generations=arguments.generations, seed=arguments.seed, skills=arguments.skills,
                                noise=arguments.noise, count_touches=arguments.count_touches,
                                roulette_weighting=arguments.roulette_weighting)
    names = ([INITIAL] if arguments.no_random else [INITIAL, RANDOM]) + arguments.also
    load_before = load_average()
    if arguments.out is None:
        with tempfile.TemporaryDirectory() as folder:
            document = calibrate(options, names, Path(folder), arguments.workers)
    else:
        document = calibrate(options, names, arguments.out, arguments.workers)
    if arguments.record:
        record_document(RESULTS_DIR / "calibration" / f"{candidate_name(options)}.json", document,
                        command=this_command(), load_before=load_before)


def candidate_name(options: ExperimentOptions) -> str:
    """The candidate's file name: its skills, weighting, noise and kicks, e.g. sighted-linear-quiet-kicks."""
    return "-".join([options.skills, options.roulette_weighting, "noise" if options.noise else "quiet",
                     "touches" if options.count_touches else "kicks"])


def calibrate(options: ExperimentOptions, names: list[str], folder: Path, workers: int) -> dict:
    """Run (or reuse) the candidate's trials, print its tables and return them for --record."""
    plans = [plan(name, options) for name in names]
    experiment = Plan([p for each in plans for p in each.presets], [m for each in plans for m in each.memberships])
    prepare_folder(folder, options.identity())
    started = time.perf_counter()
    with LocalExecutor(workers) as executor:
        ran, skipped = run_trials(experiment, folder, executor, Printer())
    seconds = time.perf_counter() - started
    print(file=sys.stderr)
    table = assemble(experiment, folder)
    evaluations = sum(spec.setting.evaluations for spec in experiment.specs)
    game = options.game()
    print(f"candidate: skills {game.skills}, roulette weighting {options.roulette_weighting}, noise {game.noise}, "
          f"touches counted as kicks {game.count_touches}; "
          f"population {options.population} x {options.generations} generations")
    print(f"{len(experiment.specs)} trials ({ran} run, {skipped} reused), {evaluations} evaluations, "
          f"{seconds:.0f} s on {workers} workers (load average before the report: {os.getloadavg()[0]:.1f})")
    print()
    rows = figure_rows(table, experiment)
    print("| figure | the chapter | ours |")
    print("|---|---|---|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    print()
    print(f"| preset | setting | trials | final average: median (quartiles) | run's best: median (std) | kicking never "
          f"spread (final average >= {NEVER_KICKING}) | taken over by goal scorers (<= {SCORERS_SPREAD}) |")
    print("|---|---|---|---|---|---|---|")
    outcomes = outcome_records(table, experiment)
    for row in outcome_rows(outcomes):
        print("| " + " | ".join(row) + " |")
    print()
    print("| report finding | verdict | measured |")
    print("|---|---|---|")
    verdicts = [(finding, assessment) for finding, assessment in assess_findings(table, experiment.presets)
                if finding.preset in names]
    for finding, assessment in verdicts:
        print(f"| {finding.where}: {finding.claim} | {assessment.shown} | {assessment.measured} |")
    defaults = ExperimentOptions()
    return {
        "candidate": {"skills": game.skills, "roulette_weighting": options.roulette_weighting,
                      "noise": game.noise, "count_touches": game.count_touches},
        "default": all(getattr(options, k) == getattr(defaults, k)
                       for k in ("skills", "roulette_weighting", "noise", "count_touches")),
        "size": {"population": options.population, "generations": options.generations,
                 "max_ticks": options.max_ticks, "seed": options.seed,
                 "trials": {p.name: len(table.final(p.name, p.settings[0].label, "mean")) for p in experiment.presets}},
        "wall_seconds": round(seconds, 1), "trials_run": ran, "trials_reused": skipped, "workers": workers,
        "initial": initial_summary(table, experiment),
        "figures": [dict(zip(("figure", "chapter", "ours"), row)) for row in rows],
        "outcomes": outcomes,
        "verdicts": [{"preset": f.preset, "where": f.where, "claim": f.claim, "verdict": a.shown,
                      "measured": a.measured, "test": a.test, "reason": a.reason,
                      "no_difference_found": a.no_difference_found} for f, a in verdicts],
    }


def initial_summary(table: StatisticsTable, experiment: Plan) -> dict:
    """The `initial` trials at CHECKPOINTS of the run: the figures the Calibration page compares."""
    setting = next(p for p in experiment.presets if p.name == INITIAL).settings[0]
    mean = table.curves(INITIAL, setting.label, "mean")
    best = table.curves(INITIAL, setting.label, "best")
    scorers = 1.0 - table.curves(INITIAL, setting.label, "goals_0")
    genes = table.curves(INITIAL, setting.label, "genes_mean") / setting.ga.max_length
    valid = table.curves(INITIAL, setting.label, "valid_rules_mean")
    points = _checkpoints(mean.shape[1])
    first_scorer = [int(np.argmax(curve <= GOAL_SCORING)) for curve in best if np.any(curve <= GOAL_SCORING)]
    first_cap = [int(np.argmax(curve <= GOAL_CAP_FITNESS)) for curve in best if np.any(curve <= GOAL_CAP_FITNESS)]
    low, high = np.nanpercentile(mean[:, -1], [25, 75])

    def at(curve: np.ndarray) -> list[float]:
        return [round(float(curve[g]), 4) for g in points]

    return {
        "trials": len(mean), "generations": points,
        "average_median": at(np.nanmedian(mean, axis=0)),
        "last_average_quartiles": [round(float(low), 4), round(float(high), 4)],
        "first_scorer_median": float(np.median(first_scorer)) if first_scorer else None,
        "trials_with_scorer": len(first_scorer),
        "trials_at_cap": len(first_cap), "first_at_cap": min(first_cap) if first_cap else None,
        "share_scoring": at(np.nanmean(scorers, axis=0)),
        "over_4_goals_last": round(float(np.nanmean(table.curves(INITIAL, setting.label, "goals_more")[:, -1])), 4),
        "length_share": at(np.nanmedian(genes, axis=0)),
        "valid_rules": at(np.nanmedian(valid, axis=0)),
        "valid_rules_rose": int(np.sum(valid[:, -1] > valid[:, 0])),
    }


def outcome_records(table: StatisticsTable, experiment: Plan) -> list[dict]:
    """Each setting of each preset run: where its trials ended (the report's outcome columns)."""
    records = []
    for preset in experiment.presets:
        for setting in table.settings(preset.name):
            final = table.final(preset.name, setting, "mean")
            best = table.best_so_far(preset.name, setting)
            low, high = np.percentile(final, [25, 75])
            records.append({"preset": preset.name, "setting": setting, "trials": len(final),
                            "final_average_median": round(float(np.median(final)), 4),
                            "final_average_quartiles": [round(float(low), 4), round(float(high), 4)],
                            "best_median": round(float(np.median(best)), 4), "best_std": round(float(np.std(best)), 4),
                            "never_spread": int(np.sum(final >= NEVER_KICKING)),
                            "taken_over": int(np.sum(final <= SCORERS_SPREAD))})
    return records


def outcome_rows(outcomes: list[dict]) -> list[list[str]]:
    return [[r["preset"], r["setting"], str(r["trials"]),
             f"{r['final_average_median']:.3f} ({r['final_average_quartiles'][0]:.3f}-"
             f"{r['final_average_quartiles'][1]:.3f})", f"{r['best_median']:.3f} ({r['best_std']:.3f})",
             str(r["never_spread"]), str(r["taken_over"])] for r in outcomes]


def figure_rows(table: StatisticsTable, experiment: Plan) -> list[list[str]]:
    presets = {p.name: p for p in experiment.presets}
    initial = presets[INITIAL]
    setting = initial.settings[0]
    mean = table.curves(INITIAL, setting.label, "mean")
    best = table.curves(INITIAL, setting.label, "best")
    scorers = 1.0 - table.curves(INITIAL, setting.label, "goals_0")
    many = table.curves(INITIAL, setting.label, "goals_more")
    genes = table.curves(INITIAL, setting.label, "genes_mean") / setting.ga.max_length
    valid = table.curves(INITIAL, setting.label, "valid_rules_mean")
    trials = len(mean)
    rows = [
        ["Fig. 11 average fitness", "improves steadily, then plateaus around 0.75; trials tightly clustered",
         f"{_along(np.nanmedian(mean, axis=0))} (median over {trials} trials); last generation "
         f"{_spread(mean[:, -1])}"],
        ["Fig. 12 best fitness", "good individuals (<= 0.5) after very few generations",
         _first_at(best, GOAL_SCORING, "best <= 0.5")],
        ["Fig. 12 / 5.3 10-goal cap", "early stopping (best <= 0.05) did not occur in any experiment",
         _first_at(best, GOAL_CAP_FITNESS, "best <= 0.05") + f"; {np.mean(best <= GOAL_CAP_FITNESS):.0%} of all "
         "generations"],
        ["Fig. 13 goal scorers", "more players score over the generations; most score none (less developed "
         "than RoboCup's); the best scored 10",
         f"share scoring >= 1 goal {_along(np.nanmean(scorers, axis=0), percent=True)} (mean over trials); "
         f"> 4 goals in the last generation {np.nanmean(many[:, -1]):.1%}; lowest best {np.nanmin(best):.3f}"],
        ["Fig. 16 chromosome length", "rises in the first few generations, settles near 2/3 of the maximum",
         f"length / maximum {_along(np.nanmedian(genes, axis=0))}"],
        ["Fig. 17 valid rules per chromosome", "rise in every trial",
         f"{_along(np.nanmedian(valid, axis=0))}; rose in {int(np.sum(valid[:, -1] > valid[:, 0]))} of {trials}"],
    ]
    if RANDOM in presets:
        rows += _random_rows(table, presets[RANDOM])
    return rows


def _random_rows(table: StatisticsTable, random: object) -> list[list[str]]:
    ga, search = (s.label for s in random.settings)  # type: ignore[attr-defined]
    long_setting = random.settings[0]  # type: ignore[attr-defined]
    ga_best = np.minimum.accumulate(table.curves(RANDOM, ga, "best"), axis=1)
    search_best = np.minimum.accumulate(table.curves(RANDOM, search, "best"), axis=1)
    ga_evaluations = table.evaluations(RANDOM, ga)
    search_evaluations = table.evaluations(RANDOM, search)
    marks = []
    for share in (0.25, 0.5, 1.0):
        budget = share * ga_evaluations[-1]
        a = ga_best[:, _at(ga_evaluations, budget)]
        b = search_best[:, _at(search_evaluations, budget)]
        marks.append(f"{budget:.0f}: GA {np.median(a):.3f} (std {np.std(a):.3f}), random {np.median(b):.3f} "
                     f"(std {np.std(b):.3f})")
    found = int(np.sum(search_best[:, -1] <= GOAL_SCORING))
    genes = table.curves(RANDOM, ga, "genes_mean") / long_setting.ga.max_length
    rules = table.curves(RANDOM, ga, "rules_mean")
    half = rules.shape[1] // 2
    rising = int(np.sum(rules[:, -1] > rules[:, half]))
    return [
        ["Fig. 31 GA vs random search (run's best so far, median at equal evaluations)",
         "random search finds scorers (<= 0.5) with some consistency; the GA finds better ones, more consistently",
         "; ".join(marks) + f"; random search found a scorer in {found} of {len(search_best)} trials"],
        ["Fig. 30 average fitness, GA vs random", "the GA improves its average; random search does not",
         f"GA {_along(np.nanmedian(table.curves(RANDOM, ga, 'mean'), axis=0))}; random "
         f"{_along(np.nanmedian(table.curves(RANDOM, search, 'mean'), axis=0))}"],
        ["Fig. 28 length (100 generations)", "plateaus at about 2/3 of the maximum",
         f"length / maximum {_along(np.nanmedian(genes, axis=0))}"],
        ["Fig. 28 rules per chromosome (100 generations)", "grow steadily, still increasing after 100 generations",
         f"{_along(np.nanmedian(rules, axis=0))}; rose over the second half in {rising} of {len(rules)}"],
    ]


def _at(evaluations: np.ndarray, budget: float) -> int:
    """The first generation having spent `budget` evaluations (the last if none has)."""
    return min(int(np.searchsorted(evaluations, budget)), len(evaluations) - 1)


def _checkpoints(length: int) -> list[int]:
    """The generations at CHECKPOINTS of a run of `length` generations (0, 6, 12, 18, 24 for 25)."""
    return sorted({round(share * (length - 1)) for share in CHECKPOINTS})


def _along(curve: np.ndarray, percent: bool = False) -> str:
    """The curve at CHECKPOINTS of the run: "g0 0.92 -> g6 0.80 -> ..."."""
    points = _checkpoints(len(curve))
    return " -> ".join(f"g{g} {curve[g]:.0%}" if percent else f"g{g} {curve[g]:.2f}" for g in points)


def _spread(values: np.ndarray) -> str:
    low, high = np.nanpercentile(values, [25, 75])
    return f"median {np.nanmedian(values):.3f}, quartiles {low:.3f}-{high:.3f}"


def _first_at(best: np.ndarray, level: float, what: str) -> str:
    firsts = [int(np.argmax(curve <= level)) for curve in best if np.any(curve <= level)]
    text = f"{what} in {len(firsts)} of {len(best)} trials"
    return text + (f", first at generation {np.median(firsts):.0f} (median; range {min(firsts)}-{max(firsts)})"
                   if firsts else "")


if __name__ == "__main__":
    main()
