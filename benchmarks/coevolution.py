"""The cost of a co-evolution generation against a solo one (docs/research/matches.md): the same GA (population
200, Table 2's operators, one worker) for a few generations, scored alone (the chapter's games) and co-evolving
against a hall of fame (each evaluation a match, two halves, against each of M members drawn: HallEvaluator).
Reports seconds per generation of each and their ratio; a generation's cost depends on how long its games and
halves last, so the same seed is used for both.

    python benchmarks/coevolution.py [--population-size 200] [--generations 5] [--hall-size 10] [--hall-sample 3]
                                     [--seed 0] [--max-ticks 1000] [--record]
"""

from __future__ import annotations

import argparse
import time

from soccer_lab.ga.algorithms import evolve
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import CoevolutionConfig, GAConfig
from soccer_lab.ga.hall_of_fame import founded_hall
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator
from soccer_lab.soccer.examples import example
from soccer_lab.soccer.match import HallEvaluator, play_matches
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py


def seconds_per_generation(config: GAConfig, game: GameConfig, coevolve: CoevolutionConfig | None) -> float:
    if coevolve is None:
        result = evolve(config, SimpleSoccerEvaluator(game), SOCCER_VOCABULARY)
    else:
        demo = ChromosomeCodec(SOCCER_VOCABULARY).encode(example("demo").rulebase(SOCCER_VOCABULARY))
        hall = founded_hall(demo, "the built-in demo", coevolve.hall_size, coevolve.hall_sample)
        result = evolve(config, HallEvaluator(config=game), SOCCER_VOCABULARY, hall=hall)
    return result.history[-1].wall_time / len(result.history)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population-size", type=int, default=200)
    parser.add_argument("--generations", type=int, default=5)
    parser.add_argument("--hall-size", type=int, default=CoevolutionConfig().hall_size)
    parser.add_argument("--hall-sample", type=int, default=CoevolutionConfig().hall_sample)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--max-ticks", type=int, default=GameConfig().max_ticks)
    add_record_option(parser)
    args = parser.parse_args()

    config = GAConfig(population_size=args.population_size, max_generations=args.generations, seed=args.seed,
                      target_fitness=0.0, workers=1)
    game = GameConfig(max_ticks=args.max_ticks)
    coevolve = CoevolutionConfig(hall_size=args.hall_size, hall_sample=args.hall_sample)
    demo = example("demo").rulebase(SOCCER_VOCABULARY)
    play_matches(demo, demo, [0], GameConfig(max_ticks=10), SOCCER_VOCABULARY)  # compiled before timing
    load_before = load_average()
    started = time.perf_counter()
    solo = seconds_per_generation(config, game, None)
    together = seconds_per_generation(config, game, coevolve)
    print(f"population {args.population_size}, {args.generations} generations, one worker, seed {args.seed}: "
          f"solo {solo:.2f} s a generation, co-evolving against {args.hall_sample} of a hall of "
          f"{args.hall_size} {together:.2f} s a generation: {together / solo:.1f}x "
          f"(load {load_before} -> {load_average()}, {time.perf_counter() - started:.0f} s)")
    if args.record:
        size = f"population {args.population_size}, one worker"
        record("coevolution", [
            Figure(f"solo generation ({size})", round(solo, 2), "s"),
            Figure(f"co-evolution generation, {args.hall_sample} opponents of a hall of {args.hall_size} ({size})",
                   round(together, 2), "s"),
            Figure("co-evolution generation against a solo one", round(together / solo, 1), "x",
                   note=f"each evaluation {args.hall_sample} matches of two halves, two players a half"),
        ], command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
