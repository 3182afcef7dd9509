"""Microseconds per game-tick of SimpleSoccer with the full controller (docs/performance.md): 200 random rulebases
played (a) together by the batched engine in one pymunk Space and (b) one Space per game in a Python
loop (each game its own batch of one, the same kernel), and the ratio, in one run. Then (c) the same
rulebases paired in matches (soccer/match.py: 100 matches of two halves, both halves in one batch), in
µs per player-tick (a half's tick moves two players), against (a)'s game-tick (target: at most 1.5×).

    python benchmarks/sim_throughput.py [--games 200] [--rules 10] [--seed 0] [--loop-games 40] [--full-length]
                                        [--skills strict|assisted|sighted]

With the default game rules most random players never touch the ball and their games end after
idle_ticks, so the last ticks of a batch carry only a few live games and the per-game-tick cost
includes that tail. `--full-length` sets idle_ticks to max_ticks, so every game plays its 1000 ticks:
the steady state of a whole population, which the performance target is about.

The per-game loop plays the first --loop-games of the games (it is the slow side) and is scaled per
game-tick. Both sides are warmed up first so numba compilation is not timed.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SKILL_SET_NAMES, GameConfig
from soccer_lab.soccer.engine import GameBatch
from soccer_lab.soccer.match import MatchBatch
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py

VOCABULARY = Vocabulary.default()


def time_batched(rulebases, seeds, config) -> tuple[float, int]:
    batch = GameBatch(rulebases, seeds, config, VOCABULARY)
    start = time.perf_counter()
    results = batch.run()
    return time.perf_counter() - start, sum(r.ticks for r in results)


def time_per_game(rulebases, seeds, config) -> tuple[float, int]:
    batches = [GameBatch([r], [s], config, VOCABULARY) for r, s in zip(rulebases, seeds)]
    start = time.perf_counter()
    ticks = sum(b.run()[0].ticks for b in batches)
    return time.perf_counter() - start, ticks


def time_matches(rulebases, seeds, config) -> tuple[float, int]:
    """Rulebases paired (0 with 1, 2 with 3, ...), each pair one match of two halves: seconds and player-ticks."""
    pairs = list(zip(rulebases[0::2], rulebases[1::2]))
    halves = [half for a, b in pairs for half in ((a, b), (b, a))]
    batch = MatchBatch(halves, [seed for seed in seeds[: len(pairs)] for _ in range(2)], config, VOCABULARY)
    start = time.perf_counter()
    results = batch.run()
    return time.perf_counter() - start, 2 * sum(r.ticks for r in results)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--games", type=int, default=200)
    parser.add_argument("--rules", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--loop-games", type=int, default=40)
    parser.add_argument("--full-length", action="store_true", help="no idle ending: every game plays max_ticks")
    parser.add_argument("--skills", choices=SKILL_SET_NAMES, default=GameConfig().skills)
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    rng = np.random.default_rng(args.seed)
    rulebases = [random_rulebase(rng, VOCABULARY, rules=args.rules) for _ in range(args.games)]
    seeds = [args.seed * 1_000_003 + g for g in range(args.games)]
    config = GameConfig(skills=args.skills)
    if args.full_length:
        config = config.model_copy(update={"idle_ticks": config.max_ticks})
    time_batched(rulebases[:2], seeds[:2], config)  # compile / load the numba cache
    time_matches(rulebases[:2], seeds[:1], config)

    batched_s, batched_ticks = time_batched(rulebases, seeds, config)
    loop_n = min(args.loop_games, args.games)
    loop_s, loop_ticks = time_per_game(rulebases[:loop_n], seeds[:loop_n], config)
    batched_us = 1e6 * batched_s / batched_ticks
    loop_us = 1e6 * loop_s / loop_ticks
    length = "full-length games" if args.full_length else f"idle games end after {config.idle_ticks} ticks"
    print(f"games: {args.games} random rulebases of {args.rules} rules, {args.skills} skills, {length}: "
          f"{batched_ticks} game-ticks")
    print(f"batched engine (one Space):     {batched_us:7.3f} us per game-tick ({batched_s:.2f} s)")
    print(f"one Space per game, Python loop: {loop_us:7.3f} us per game-tick ({loop_n} games, {loop_ticks} game-ticks)")
    print(f"speed-up: {loop_us / batched_us:.1f}x")
    match_s, player_ticks = time_matches(rulebases, seeds, config)
    match_us = 1e6 * match_s / player_ticks
    print(f"matches (two players a pitch):   {match_us:7.3f} us per player-tick ({player_ticks} player-ticks, "
          f"{match_us / batched_us:.2f}x the game-tick)")
    if args.record:
        record("sim_throughput", [
            Figure(f"SimpleSoccer, {args.games} games at once, full controller, one core ({length})",
                   round(batched_us, 2), "µs per game-tick", target="≤ 2 µs" if args.full_length else ""),
            Figure("the same games, one Space per game in a Python loop, against the batch",
                   round(loop_us / batched_us, 1), "× slower", target="≥ 10×"),
            Figure("the same players paired in matches (two a pitch), per player-tick, against the game-tick",
                   round(match_us / batched_us, 2), "×", target="≤ 1.5×"),
        ], command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
