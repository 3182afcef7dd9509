"""What a rule usage or simplification request costs, and so where app/rule_inspection.py's bound lies.

A request plays its games while the client waits, so its bound is in seconds: at most REQUEST_SECONDS.
The seconds grow with the game ticks played and, per tick, with the rules: a tick costs the world's part
(physics, the observation, the skills) plus each rule's inference. This script times rule usage and
checked simplification (the worst case: random rules that never win, so the candidate is replayed) over
full-length games for several rulebase sizes, fits seconds = game ticks x (world + rules x rule), and
prints the constants the bound uses:

- TICK_COST_RULES: a game tick's world part, in rules (world / rule);
- PREMISES_PER_RULE: premises past a rule's first that cost one rule's inference: 20-premise rules timed
  beside one-premise ones;
- GAME_COST_TICKS: a game's setup (its world, its engine), in ticks: games of one tick timed at each size,
  seconds per game / ((rules + TICK_COST_RULES) x rule) - 1, the largest over the sizes;
- the seconds MAX_WORK, the bound on (rules + TICK_COST_RULES) x games x max_ticks x plays, stands for (a
  usage request plays its games once, a simplification twice: the original recorded, the candidate
  compared). It is set well under REQUEST_SECONDS: a school's laptop is slower than this machine, and a
  simplification keeps a row per game tick of both plays in memory (benchmarks/server_memory.py).

Then it times the heaviest request the bound allows at each size and game length (1, 10, 100 and full-length
ticks), with three kinds of rules: random ones (seeded: they seldom fire), the demo striker's repeated
(they fire every tick) and rules of 20 premises each (PREMISES_PER_RULE's case), the figures docs/reference/limits.md points to; and simplification's exact steps
alone (games 0) on MAX_RULES random rules (`--record` writes docs/results/request_cost.json).

    python benchmarks/request_cost.py [--games 40] [--rules 1 20 100 300 1000] [--repeats 3] [--record]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from soccer_lab.app.rule_inspection import (GAME_COST_TICKS, MAX_RULES, MAX_WORK, PREMISES_PER_RULE, TICK_COST_RULES,
                                            affordable_games)
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.simplify import premise_count
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.simplify import simplify_rulebase
from soccer_lab.soccer.usage import measure_usage
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py

VOCABULARY = Vocabulary.default()
REQUEST_SECONDS = 5.0
HEAVIEST_SECONDS = 2.0  # issue 36: the heaviest accepted request, on this machine
TICKS = GameConfig().max_ticks
TICK_LENGTHS = (1, 10, 100, TICKS)


def no_end(ticks: int = TICKS) -> GameConfig:
    """Games of `ticks` that last their full length: the worst case."""
    return GameConfig(max_ticks=ticks, goal_cap=ticks, idle_ticks=ticks)


def rulebase_of(rules: int, seed: int = 1) -> Rulebase:
    """The demo striker's rules, then random ones (seeded) up to `rules`."""
    striker = demo_rulebase(VOCABULARY)
    if rules <= len(striker):
        return Rulebase(striker.rules[:rules])
    extra = random_rulebase(np.random.default_rng(seed), VOCABULARY, rules=rules - len(striker))
    return Rulebase(striker.rules + extra.rules)


def firing_rulebase(rules: int) -> Rulebase:
    """The demo striker's rules repeated up to `rules`: rules that fire, every tick."""
    striker = demo_rulebase(VOCABULARY).rules
    return Rulebase((striker * (rules // len(striker) + 1))[:rules])


def long_rulebase(rules: int, premises: int | None = None) -> Rulebase:
    """Rules of `premises` (LONG_PREMISES) premises each (true most ticks, so every premise is evaluated)."""
    said = " and ".join((["Ball is not At", "Goal is not At"] * LONG_PREMISES)[:premises or LONG_PREMISES])
    return parse_rulebase("\n".join([f"if {said} then GoToBall VeryHigh"] * rules), VOCABULARY)


LONG_PREMISES = 20
KINDS = {"random": rulebase_of, "firing": firing_rulebase, "long": long_rulebase}


def seconds(work) -> float:
    start = time.perf_counter()
    work()
    return time.perf_counter() - start


def usage(rulebase: Rulebase, games: int, ticks: int = TICKS) -> float:
    return seconds(lambda: measure_usage(rulebase, list(range(games)), no_end(ticks), VOCABULARY))


def simplify(rulebase: Rulebase, games: int, ticks: int = TICKS) -> float:
    return seconds(lambda: simplify_rulebase(rulebase, VOCABULARY, list(range(games)), no_end(ticks)))


def fit(sizes: list[int], per_tick: list[float]) -> tuple[float, float]:
    """(world, rule): seconds per game tick = world + rules x rule, least squares."""
    rule, world = np.polyfit(np.array(sizes, dtype=float), np.array(per_tick), 1)
    return float(world), float(rule)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--games", type=int, default=40, help="full-length games per measurement")
    parser.add_argument("--rules", type=int, nargs="+", default=[1, 20, 100, 300, 1000])
    parser.add_argument("--repeats", type=int, default=3)
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    usage(rulebase_of(2), 2)  # compile / load the numba cache, not timed

    # the best of --repeats, so another job's moment on the machine does not bend the fit
    per_tick = [min(usage(rulebase_of(rules), args.games) for _ in range(args.repeats)) / (args.games * TICKS)
                for rules in args.rules]
    world, rule = fit(args.rules, per_tick)
    print(f"usage: seconds per game tick = {world * 1e6:.2f} us + rules x {rule * 1e6:.4f} us "
          f"(games of {TICKS} ticks, {args.games} per size)")
    print(f"  TICK_COST_RULES = world / rule = {world / rule:.0f}   (app/rule_inspection.py has {TICK_COST_RULES})")
    print(f"  MAX_WORK = {MAX_WORK:,} stands for {MAX_WORK * rule:.1f} s (at most {REQUEST_SECONDS:.0f} s)")

    # a premise's share: the same number of rules with LONG_PREMISES premises each, over one-premise ones
    short, long = (min(usage(long_rulebase(100, premises), args.games) for _ in range(args.repeats))
                   for premises in (1, LONG_PREMISES))
    extra_rules = (long / short - 1) * (100 + TICK_COST_RULES)  # what the extra premises cost, in rules
    per_rule = 100 * (LONG_PREMISES - 1) / extra_rules if extra_rules > 0 else float("inf")
    print(f"  PREMISES_PER_RULE = premises worth one rule = {per_rule:.1f}   (app/rule_inspection.py has "
          f"{PREMISES_PER_RULE})")
    # a game's setup: games of one tick, where the setup is nearly all there is
    setup = max(min(usage(rulebase_of(rules), args.games * 5, 1) for _ in range(args.repeats)) / (args.games * 5)
                / ((rules + TICK_COST_RULES) * rule) - 1 for rules in args.rules)
    print(f"  GAME_COST_TICKS = a game's setup in ticks = {setup:.0f}   (app/rule_inspection.py has {GAME_COST_TICKS})")

    figures = [Figure("a game tick's world part, in rules' inference", round(world / rule), "rules",
                      note=f"world {world * 1e6:.2f} us, a rule {rule * 1e6:.4f} us per game tick; "
                           f"app/rule_inspection.py TICK_COST_RULES = {TICK_COST_RULES}"),
               Figure("premises worth one rule's inference", round(per_rule, 1), "premises",
                      note=f"app/rule_inspection.py PREMISES_PER_RULE = {PREMISES_PER_RULE}"),
               Figure("a game's setup, in game ticks (largest over the sizes)", round(setup), "ticks",
                      note=f"app/rule_inspection.py GAME_COST_TICKS = {GAME_COST_TICKS}"),
               Figure(f"MAX_WORK ({MAX_WORK:,}) in seconds, by the fit", round(MAX_WORK * rule, 1), "s",
                      target=f"<= {REQUEST_SECONDS:.0f} s")]
    print(f"the heaviest request the bound allows (at most {HEAVIEST_SECONDS:.0f} s here, {REQUEST_SECONDS:.0f} s "
          "on a slower machine):")
    heaviest = 0.0
    for rules in args.rules:
        for ticks in TICK_LENGTHS:
            for route, plays, timed in (("usage", 1, usage), ("simplify", 2, simplify)):
                took = {}
                for kind, make in KINDS.items():
                    rulebase = make(rules)
                    games = affordable_games(rules, ticks, plays, premise_count(rulebase))
                    if games:
                        took[f"{kind} x {games}"] = timed(rulebase, games, ticks)
                if not took:
                    continue
                heaviest = max(heaviest, *took.values())
                shown = ", ".join(f"{kind} games {t:.2f} s" for kind, t in took.items())
                print(f"  {route:<8} {rules:>5} rules, games of {ticks:>5} ticks: {shown}", flush=True)
                figures.append(Figure(f"{route}, {rules:,} rules x the most games allowed x {ticks:,} ticks, the "
                                      "slowest of random, firing and 20-premise rules", round(max(took.values()), 2),
                                      "s", target=f"<= {HEAVIEST_SECONDS:.0f} s", note=shown))
    exact = simplify(rulebase_of(MAX_RULES), 0)
    print(f"  simplify {MAX_RULES} random rules, exact steps only (games 0): {exact:.2f} s")
    figures.append(Figure(f"simplify, {MAX_RULES:,} random rules, exact steps only (games 0)", round(exact, 2), "s",
                          target=f"<= {HEAVIEST_SECONDS:.0f} s"))
    figures.append(Figure("the heaviest accepted request, of all above", round(max(heaviest, exact), 2), "s",
                          target=f"<= {HEAVIEST_SECONDS:.0f} s"))
    if args.record:
        record("request_cost", figures, command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
