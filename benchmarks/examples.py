"""What each built-in example player does under each skill set (docs/teaching/what-the-player-did.md): mean
goals a game and how its games end, over the same starts (seeds 0 .. GAMES-1), played in one batch each.

    python benchmarks/examples.py [--games 50] [--record]
"""

from __future__ import annotations

import argparse
from collections import Counter
from statistics import fmean

from results import Figure, add_record_option, load_average, record

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SKILL_SET_NAMES, GameConfig
from soccer_lab.soccer.engine import play_games
from soccer_lab.soccer.examples import examples


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--games", type=int, default=50)
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    vocabulary = Vocabulary.default()
    figures = []
    for example in examples():
        rulebase = example.rulebase(vocabulary)
        for skills in SKILL_SET_NAMES:
            results = play_games([rulebase] * args.games, list(range(args.games)), GameConfig(skills=skills), vocabulary)
            goals = fmean(r.goals for r in results)
            ends = Counter(r.end_reason for r in results)
            ended = ", ".join(f"{reason} {count}" for reason, count in ends.most_common())
            print(f"{example.title:<22} {skills:<9} goals {goals:5.2f}  fitness {fmean(r.fitness for r in results):.3f}"
                  f"  ends: {ended}")
            figures.append(Figure(f"{example.title}, {skills} skills: goals a game", round(goals, 2),
                                  note=f"games end: {ended}"))
    if args.record:
        record("examples", figures, command=f"python benchmarks/examples.py --games {args.games} --record",
               load_before=load_before)


if __name__ == "__main__":
    main()
