"""Times one Table 2 trial (docs/performance.md): population 200 x 25 generations with the chapter's defaults,
SimpleSoccer games, 2 worker processes. Target: under 10 s on a 2-core machine.

With --outputs the trial is played as `soccer-lab evolve` and the app play a run (soccer_lab.app.runs.run.Run, in a
temporary run folder: checkpoint, statistics.csv, best rules, the rerun recording with each generation's
best player's game), and the time spent replaying those games is reported too.

    python benchmarks/trial.py [--workers 2] [--seed 0] [--population-size 200] [--generations 25] [--full]
                               [--outputs] [--skills strict|assisted|sighted] [--roulette-weighting linear|inverse]
                               [--behaviour-seeds K]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import evolve
from soccer_lab.ga.config import GAConfig
from soccer_lab.soccer.config import SKILL_SET_NAMES, GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import play_games
from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py

VOCABULARY = Vocabulary.default()

TABLE_2 = GAConfig()  # the chapter's Table 2: population 200, 25 generations
TARGET_SECONDS = 10.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--population-size", type=int, default=TABLE_2.population_size)
    parser.add_argument("--generations", type=int, default=TABLE_2.max_generations)
    parser.add_argument("--full", action="store_true",
                        help="run every generation (target fitness 0): the worst case, a stable figure")
    parser.add_argument("--outputs", action="store_true",
                        help="play it as a run, with its folder's outputs and a replay of each generation's best")
    parser.add_argument("--skills", choices=SKILL_SET_NAMES, default=GameConfig().skills)
    parser.add_argument("--roulette-weighting", choices=("linear", "inverse"), default=TABLE_2.roulette_weighting)
    parser.add_argument("--behaviour-seeds", type=int, default=0,
                        help="K: count distinct behaviours, every new chromosome playing K common seeds (ga/diversity.py)")
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    config = TABLE_2.model_copy(update={"workers": args.workers, "seed": args.seed,
                                        "population_size": args.population_size,
                                        "max_generations": args.generations,
                                        "roulette_weighting": args.roulette_weighting,
                                        "behaviour_seeds": args.behaviour_seeds}
                                | ({"target_fitness": 0.0} if args.full else {}))
    game = GameConfig(skills=args.skills)
    play_games([demo_rulebase()], [args.seed], game)  # load the compiled kernels before the clock starts

    started = time.perf_counter()
    if args.outputs:
        result, replaying = _as_a_run(config, game)
    else:
        result = evolve(config, SimpleSoccerEvaluator(game), VOCABULARY)
    seconds = time.perf_counter() - started

    behaviours = f", behaviours on {config.behaviour_seeds} seeds" if config.behaviour_seeds else ""
    print(f"trial ({game.skills} skills, {config.roulette_weighting} roulette weighting{behaviours}): population "
          f"{config.population_size} x {len(result.history)} generations "
          f"({result.stop_reason}), {result.evaluations} evaluations, workers {config.workers}")
    print(f"best fitness {result.best.fitness:.4f}")
    print(f"wall time {seconds:.2f} s (target < {TARGET_SECONDS:.0f} s: {'met' if seconds < TARGET_SECONDS else 'MISSED'})")
    if args.outputs:
        print(f"of which replaying each generation's best into the recording: {replaying:.2f} s")
    if args.record:
        record("trial", [Figure(
            f"one Table 2 trial ({config.population_size} × {len(result.history)} generations, {game.skills} "
            f"skills), {config.workers} workers", round(seconds, 2), "s", target=f"< {TARGET_SECONDS:.0f} s")],
            command=this_command(), load_before=load_before)


def _as_a_run(config: GAConfig, game: GameConfig) -> tuple[object, float]:
    """The trial as a Run in a temporary folder; its result and the seconds spent in the replays."""
    from soccer_lab.app.runs.run import GenerationReplays, Run, RunSettings

    spent = [0.0]
    replay = GenerationReplays.replay

    def timed(self, generation, individual):
        started = time.perf_counter()
        replay(self, generation, individual)
        spent[0] += time.perf_counter() - started

    GenerationReplays.replay = timed
    with tempfile.TemporaryDirectory() as folder:
        run = Run.create(RunSettings(config, game), Path(folder) / "run")
        with run.evaluator() as evaluate:
            result = run.play(evaluate)
    return result, spent[0]


if __name__ == "__main__":
    main()
