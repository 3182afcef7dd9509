"""Seconds for rule usage and simplification of one 30-rule rulebase over 100 games (docs/performance.md),
beside the floor: the same 100 games played with nothing counted.

    python benchmarks/rule_usage.py [--games 100] [--rules 30] [--seed 1] [--repeats 3]

The rulebase is the demo striker's two rules followed by --rules - 2 random rules (seeded), and
neither the goal cap nor idleness ends a game, so every game lasts its full 1000 ticks: the worst
case (real games of a good or a stuck player end earlier). The figures are the best of
--repeats runs, the sides interleaved so the machine's other load affects them alike; numba's
compilation is warmed up first and not timed.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.simplify import premise_count, simplify_exactly
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import play_games
from soccer_lab.soccer.simplify import simplify_rulebase
from soccer_lab.soccer.usage import measure_usage
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py

VOCABULARY = Vocabulary.default()


def timed(work) -> tuple[float, object]:
    start = time.perf_counter()
    result = work()
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--games", type=int, default=100)
    parser.add_argument("--rules", type=int, default=30)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=3)
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    striker = demo_rulebase(VOCABULARY)
    extra = random_rulebase(np.random.default_rng(args.seed), VOCABULARY, rules=args.rules - len(striker))
    rulebase = Rulebase(striker.rules + extra.rules)
    seeds = list(range(args.games))
    full_length = GameConfig().max_ticks
    config = GameConfig(goal_cap=full_length, idle_ticks=full_length)
    measure_usage(rulebase, seeds[:2], config, VOCABULARY, record=True)  # compile / load the numba cache

    sides = {
        "play the games (nothing counted)": lambda: play_games([rulebase] * args.games, seeds, config, VOCABULARY),
        "rule usage": lambda: measure_usage(rulebase, seeds, config, VOCABULARY),
        "exact simplification (no games)": lambda: simplify_exactly(rulebase, VOCABULARY),
        "simplification, checked on the games": lambda: simplify_rulebase(rulebase, VOCABULARY, seeds, config),
    }
    best = dict.fromkeys(sides, float("inf"))
    outcome = {}
    for _ in range(args.repeats):
        for name, work in sides.items():
            seconds, outcome[name] = timed(work)
            best[name] = min(best[name], seconds)

    usage, _ = outcome["rule usage"]
    checked = outcome["simplification, checked on the games"]
    simplified = checked.simplification.rulebase
    print(f"rulebase: {len(rulebase)} rules, {premise_count(rulebase)} premises; {args.games} games, "
          f"{usage.ticks} game-ticks ({usage.ticks / args.games:.0f} per game)")
    for name, seconds in best.items():
        print(f"{name:<40} {seconds:7.3f} s")
    step = checked.simplification.steps[-1]
    print(f"simplified: {len(simplified)} rules, {premise_count(simplified)} premises; checked step: {step.summary}")
    if args.record:
        games = f"{len(rulebase)}-rule rulebase, {args.games} full-length games"
        record("rule_usage", [
            Figure(f"rule usage, {games}", round(best["rule usage"], 2), "s", target="a few seconds"),
            Figure("exact simplification (no games)", round(best["exact simplification (no games)"], 3), "s"),
            Figure(f"simplification checked on the games, {games}",
                   round(best["simplification, checked on the games"], 2), "s", target="a few seconds"),
        ], command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
