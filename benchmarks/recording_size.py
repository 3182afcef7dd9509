"""The size of a run's rerun recording (issue 25: recordings bounded in size), for a GA run of the chapter's
population (200) over 100 generations with the default games: what one generation adds (its statistics and
its best player's replayed game, about 60 KB) and what the blueprint adds (sent when its replay tabs double,
and at the end: app/runs/recording.py).

    python benchmarks/recording_size.py [--population 200] [--generations 100] [--record]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from results import Figure, add_record_option, load_average, record


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--population", type=int, default=200)
    parser.add_argument("--generations", type=int, default=100)
    parser.add_argument("--seed", type=int, default=1)
    add_record_option(parser)
    args = parser.parse_args()
    from soccer_lab.app.runs.run import Run, RunSettings

    load_before = load_average()
    with tempfile.TemporaryDirectory() as folder:
        # target 0: the run plays all its generations (the chapter's 0.05 could end it early)
        settings = RunSettings.build({"population_size": args.population, "max_generations": args.generations,
                                      "target_fitness": 0.0, "seed": args.seed}, {})
        run = Run.create(settings, Path(folder) / "run")
        started = time.perf_counter()
        with run.evaluator() as evaluate:
            result = run.play(evaluate)
        wall = time.perf_counter() - started
        size = run.folder.recording.stat().st_size
    generations = len(result.history)
    print(f"{args.population} x {generations} run: recording {size / 2**20:.2f} MB "
          f"({size / generations / 1024:.0f} KB a generation), run took {wall:.0f} s")
    print(f"load average before {load_before}, after {load_average()}")
    if args.record:
        record("recording_size", [
            Figure(f"recording of a {args.population} x {generations} run", round(size / 2**20, 2), "MB",
                   note="statistics, each generation's best's replay, the blueprint"),
            Figure("recording per generation", round(size / generations / 1024), "KB")],
            command=f"python benchmarks/recording_size.py --population {args.population} "
                    f"--generations {args.generations}", load_before=load_before)


if __name__ == "__main__":
    main()
