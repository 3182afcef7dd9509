"""Why the full RoboCup study's players score more than the chapter's: its best players replayed on rcssserver
under one changed condition at a time. Writes docs/results/robocup/disagreement.json, which
docs/robocup/full-study.md shows ("When a finding disagrees", docs/hooks/robocup_pages.py).

    nice -n 19 .venv/bin/python scripts/robocup_disagreement.py STUDY_FOLDER [--seed 0] [--starts 10]

The chapter (6.1, Fig. 10): no individual scored more than 3 goals on rcssserver; in the study some scored
more than 4. Two differences could explain it (docs/robocup/full-study.md): the chapter's games restarted after a
goal in a way it does not describe (soccer-lab's trainer puts the ball back after 5 cycles), and they were played
in real time, where answers reach the server late (soccer-lab's client answers every cycle in time).

1. The study's folder: the most goals per GA trial and generation (from each generation's best fitness; the
   RoboCup composite fitness is 1 / (2 goals) for a scorer) and how many evaluations scored 4 or more.
2. Its best players. The study's folder keeps statistics only (its code predates the trials' .best.json), and
   its trials ran with the server's noise, so they cannot be played again bit for bit. The players are
   found again the way the study found them: its `--trials` GA trials whose high scorers came first are run again
   with their own seeds (statistics.csv) for their first `--generations`, on the study's GA and trial settings;
   every evaluation is kept, and the `--players` highest scorers (distinct rulebases, from each trial in turn)
   are the players.
3. Each player plays the same `--starts` seeded starts under each condition, on fresh servers (the server's
   noise on, as in the study and the chapter): as the study played them, then with one condition changed
   (CONDITIONS: how play restarts after a goal, or answers reaching the server late; soccer/rcss/trial.py,
   TrialConfig.restart_wait_cycles, restart, answer_delay, answer_delay_spread), and the two most plausible
   together.

`--seed` fixes the starts and the late answers' draws; the server's noise is not seedable (rcssserver seeds it
from the clock), so figures vary a little from run to run. Run it with `nice -n 19` beside other work: each
server wants a core. `--players-from FILE` takes the players from an earlier disagreement.json instead of
finding them again.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import os
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any, Sequence

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from soccer_lab.app.experiment.presets import ROBOCUP  # noqa: E402
from soccer_lab.app.experiment.report import MOST_GOALS_TOLERANCE, ROBOCUP_MOST_GOALS  # noqa: E402
from soccer_lab.app.experiment.runner import plan  # noqa: E402
from soccer_lab.fuzzy.parser import parse_rulebase  # noqa: E402
from soccer_lab.fuzzy.printer import format_rulebase  # noqa: E402
from soccer_lab.fuzzy.rule import Rulebase  # noqa: E402
from scripts.robocup_results import options_of  # noqa: E402
from soccer_lab.soccer.config import SOCCER_VOCABULARY  # noqa: E402

RESULT = ROOT / "docs" / "results" / "robocup" / "disagreement.json"
# Conditions: name -> (factor, what it is, the TrialConfig options it changes from the study's)
CONDITIONS: dict[str, tuple[str, str, dict[str, Any]]] = {
    "study": ("none", "as the study played them: the trainer restarts 5 cycles after a goal, answers in time", {}),
    "trainer-50": ("restart", "the trainer restarts 50 cycles after a goal (rcssserver's own pause)",
                   {"restart_wait_cycles": 50}),
    "server-restart": ("restart", "nobody restarts: rcssserver's 50-cycle pause, the other side's kick-off, "
                                  "a drop ball 100 cycles later", {"restart": "server"}),
    "late-1": ("late answers", "every answer 1 cycle late", {"answer_delay": 1}),
    "late-2": ("late answers", "every answer 2 cycles late", {"answer_delay": 2}),
    "late-0-2": ("late answers", "each answer 0 to 2 cycles late, at random", {"answer_delay_spread": 2}),
    "server-restart+late-0-2": ("both", "rcssserver's restart and answers 0 to 2 cycles late",
                                {"restart": "server", "answer_delay_spread": 2}),
}


def most_goals(row: dict[str, str], population: int) -> int:
    """The most goals an individual of this generation scored, from its best fitness (1 / (2 goals) when it
    scored; a non-scorer's is above 0.5) and, for 0 or 1, from the goal shares."""
    best = float(row["best"])
    if best < 0.5:
        return round(1 / (2 * best))
    return 1 if float(row["goals_1"]) * population >= 0.5 else 0


def study_summary(folder: Path) -> dict[str, Any]:
    """What the study's folder records of its high scorers, by GA trial and generation."""
    options = options_of(folder)
    population = options.population
    rows: dict[int, list[dict[str, str]]] = {}
    with (folder / "statistics.csv").open(newline="") as handle:
        for row in csv.DictReader(handle):
            if row["preset"] == ROBOCUP:
                rows.setdefault(int(row["trial"]), []).append(row)
    trials = []
    for trial, generations in sorted(rows.items()):
        generations.sort(key=lambda row: int(row["generation"]))
        count = lambda columns: int(round(sum(float(r[c]) * population for r in generations for c in columns)))
        trials.append({"trial": trial, "seed": int(generations[0]["seed"]),
                       "most_goals_by_generation": [most_goals(r, population) for r in generations],
                       "evaluations_4_goals": count(("goals_4",)),
                       "evaluations_more_than_4": count(("goals_more",))})
    for trial in trials:
        trial["most_goals"] = max(trial["most_goals_by_generation"])
    most = [t["most_goals"] for t in trials]
    return {"folder": folder.name, "population": population,
            "generations": len(rows[min(rows)]), "evaluations": population * sum(len(g) for g in rows.values()),
            "most_goals": max(most),
            "trials_by_most_goals": {str(goals): sum(1 for m in most if m == goals) for goals in range(max(most) + 1)},
            "evaluations_4_goals": sum(t["evaluations_4_goals"] for t in trials),
            "evaluations_more_than_4": sum(t["evaluations_more_than_4"] for t in trials),
            "trials": trials}


def first_high_generation(trial: dict[str, Any]) -> int:
    """The first generation in which the trial had an individual scoring more than the chapter's most."""
    return next((g for g, most in enumerate(trial["most_goals_by_generation"]) if most > ROBOCUP_MOST_GOALS), 10**9)


def choose_trials(study: dict[str, Any], count: int) -> list[dict[str, Any]]:
    """The study's GA trials whose high scorers came first (then those with the most scoring more than 4)."""
    return sorted(study["trials"], key=lambda t: (first_high_generation(t), -t["evaluations_more_than_4"]))[:count]


def choose_players(found: list[tuple[int, int, int, Rulebase]], trials: list[int], count: int) -> list[dict[str, Any]]:
    """From (goals, trial, generation, rulebase) of every evaluation: distinct rulebases, each trial's highest
    scorers first, taken from the trials in turn while any scored more than the chapter's most, then the
    highest of the rest."""
    ranked: dict[int, list[tuple[int, int, int, Rulebase]]] = {trial: [] for trial in trials}
    seen: set[Rulebase] = set()
    for entry in sorted(found, key=lambda f: -f[0]):  # stable: in each trial, the earliest of equals first
        if entry[3] not in seen and len(entry[3]) > 0:
            seen.add(entry[3])
            ranked[entry[1]].append(entry)
    chosen: list[tuple[int, int, int, Rulebase]] = []
    while len(chosen) < count and any(ranked.values()):
        high = [trial for trial in trials if ranked[trial] and ranked[trial][0][0] > ROBOCUP_MOST_GOALS]
        if high:
            chosen += [ranked[trial].pop(0) for trial in high][:count - len(chosen)]
        else:
            best = max((trial for trial in trials if ranked[trial]), key=lambda trial: ranked[trial][0][0])
            chosen.append(ranked[best].pop(0))
    return [{"trial": trial, "generation": generation, "goals_seen": goals,
             "rules": format_rulebase(rulebase, SOCCER_VOCABULARY)} for goals, trial, generation, rulebase in chosen]


def find_players(folder: Path, study: dict[str, Any], servers: int, trial_count: int, generations: int,
                 players: int) -> dict[str, Any]:
    """Runs the chosen GA trials again for their first `generations` (their own seeds, the study's GA and trial
    settings) and keeps every evaluation; the `players` highest scorers, distinct rulebases, are the players."""
    from soccer_lab.ga.algorithms import evolve
    from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
    from soccer_lab.soccer.rcss.servers import ServerPool, noise_options

    class Keeping(RcssEvaluator):
        """The study's evaluator, keeping every (generation, rulebase, result)."""

        def __init__(self, *args: Any, **kwargs: Any):
            super().__init__(*args, **kwargs)
            self.generation = -1
            self.kept: list[tuple[int, Rulebase, Any]] = []

        def start_generation(self) -> None:
            super().start_generation()
            self.generation += 1

        def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list[Any]:
            results = super().__call__(rulebases, seeds)
            self.kept += [(self.generation, r, result) for r, result in zip(rulebases, results)]
            return results

    (setting,) = plan(ROBOCUP, options_of(folder)).presets[0].settings
    found, rerun = [], []
    started = time.perf_counter()
    for trial in choose_trials(study, trial_count):
        config = setting.ga.model_copy(update={"seed": trial["seed"], "max_generations": generations})
        with ServerPool(None, servers, noise_options(setting.trial.noise)) as pool, \
                Keeping(pool.addresses, setting.trial) as evaluate:
            evolve(config, evaluate, SOCCER_VOCABULARY)
        by_generation = [[r.goals for g, _, r in evaluate.kept if g == generation] for generation in range(generations)]
        rerun.append({"trial": trial["trial"], "seed": trial["seed"],
                      "most_goals_by_generation": [max(goals) for goals in by_generation],
                      "study_most_goals_by_generation": trial["most_goals_by_generation"][:generations],
                      "evaluations_4_goals": sum(g == 4 for goals in by_generation for g in goals),
                      "evaluations_more_than_4": sum(g > 4 for goals in by_generation for g in goals)})
        found += [(result.goals, trial["trial"], generation, rulebase) for generation, rulebase, result in evaluate.kept]
    return {"how": "found again", "generations": generations, "trials_run_again": rerun,
            "seconds": round(time.perf_counter() - started, 1),
            "players": choose_players(found, [t["trial"] for t in rerun], players)}


def replay(players: list[dict[str, Any]], folder: Path, seeds: list[int], servers: int,
           conditions: Sequence[str], measured: list[dict[str, Any]], done=lambda: None) -> None:
    """Every player on every start under each condition, each condition on fresh servers; each condition's
    figures appended to `measured` as it finishes (then `done()`)."""
    from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
    from soccer_lab.soccer.rcss.servers import ServerPool, noise_options

    (setting,) = plan(ROBOCUP, options_of(folder)).presets[0].settings
    rulebases = [parse_rulebase(p["rules"], SOCCER_VOCABULARY) for p in players]
    for name in conditions:
        factor, label, changes = CONDITIONS[name]
        config = setting.trial.model_copy(update=changes)
        started = time.perf_counter()
        with ServerPool(None, servers, noise_options(config.noise)) as pool, \
                RcssEvaluator(pool.addresses, config) as evaluate:
            results = evaluate([r for r in rulebases for _ in seeds], [s for _ in rulebases for s in seeds])
        goals = np.array([r.goals for r in results]).reshape(len(rulebases), len(seeds))
        ends = Counter(r.end.split(" (")[0] for r in results)
        entry = {"name": name, "factor": factor, "condition": label, "options": changes,
                 "goals": goals.tolist(), "most_goals": int(goals.max()), "mean_goals": round(float(goals.mean()), 2),
                 "player_means": [round(float(m), 2) for m in goals.mean(axis=1)],
                 "mean_kicks": round(float(np.mean([r.kicks for r in results])), 1),
                 "share_more_than_3": round(float(np.mean(goals > 3)), 3),
                 "share_more_than_4": round(float(np.mean(goals > 4)), 3),
                 "agrees": bool(abs(int(goals.max()) - ROBOCUP_MOST_GOALS) <= MOST_GOALS_TOLERANCE),
                 "ends": dict(sorted(ends.items())), "late_cycles": sum(r.late_cycles for r in results),
                 "cycles": sum(r.ticks for r in results), "seconds": round(time.perf_counter() - started, 1)}
        measured.append(entry)
        print(f"{name:>15}: goals max {entry['most_goals']}, mean {entry['mean_goals']}, >3 {entry['share_more_than_3']:.0%}, "
              f">4 {entry['share_more_than_4']:.0%}; ends {entry['ends']}; late {entry['late_cycles']}; "
              f"{entry['seconds']} s", flush=True)
        done()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the study's folder (`soccer-lab experiment robocup --out`)")
    parser.add_argument("--seed", type=int, default=0, help="fixes the starts and the late answers' draws")
    parser.add_argument("--starts", type=int, default=10, help="seeded starts each player plays under each condition")
    parser.add_argument("--players", type=int, default=10, help="the study's highest scorers to replay (choose_players)")
    parser.add_argument("--trials", type=int, default=3, help="the study's GA trials run again to find them")
    parser.add_argument("--generations", type=int, default=4, help="their first generations run again")
    parser.add_argument("--servers", type=int, default=2, help="rcssservers at once (each wants a core)")
    parser.add_argument("--conditions", default=",".join(CONDITIONS), help="comma-separated, of: " + ", ".join(CONDITIONS))
    parser.add_argument("--players-from", type=Path, help="an earlier disagreement.json: its players, not found again")
    parser.add_argument("--out", type=Path, default=RESULT)
    args = parser.parse_args()
    folder = args.folder.resolve()
    conditions = [name for name in args.conditions.split(",") if name]
    unknown = [name for name in conditions if name not in CONDITIONS]
    if unknown:
        parser.error(f"unknown condition {unknown[0]!r}; choose from {', '.join(CONDITIONS)}")
    started = time.perf_counter()
    load_before = [round(x, 2) for x in os.getloadavg()]
    study = study_summary(folder)
    print(f"study {study['folder']}: most goals {study['most_goals']}; trials by their most goals "
          f"{study['trials_by_most_goals']}; evaluations with 4 goals {study['evaluations_4_goals']}, "
          f"more than 4 {study['evaluations_more_than_4']}", flush=True)
    if args.players_from is not None:
        found = json.loads(args.players_from.read_text())["players"]
    else:
        found = find_players(folder, study, args.servers, args.trials, args.generations, args.players)
    print(f"players: {[(p['trial'], p['generation'], p['goals_seen']) for p in found['players']]}", flush=True)
    seeds = [int(s) for s in np.random.SeedSequence(args.seed).generate_state(args.starts, np.uint32)]
    measured: list[dict[str, Any]] = []
    record = {
        "recorded": datetime.date.today().isoformat(),
        "command": "nice -n 19 .venv/bin/python scripts/robocup_disagreement.py " + " ".join(sys.argv[1:]).replace(
            str(args.folder), folder.name),
        "seed": args.seed, "starts": args.starts, "start_seeds": seeds, "servers": args.servers,
        "chapter_most_goals": ROBOCUP_MOST_GOALS, "tolerance": MOST_GOALS_TOLERANCE,
        "study": study, "players": found, "conditions": measured, "finished": False,
        "load_average_before": load_before, "cores": os.cpu_count(),
    }

    def write() -> None:  # after each condition: a run stopped part-way keeps what it measured
        record.update(wall_time_seconds=round(time.perf_counter() - started, 1),
                      load_average_after=[round(x, 2) for x in os.getloadavg()])
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")

    write()
    replay(found["players"], folder, seeds, args.servers, conditions, measured, write)
    record["finished"] = True
    write()
    print(f"wrote {args.out} ({record['wall_time_seconds']} s)")


if __name__ == "__main__":
    main()
