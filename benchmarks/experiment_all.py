"""Wall time of one experiment preset, and from its evaluation rate an estimate for `experiment all` at
full size (evaluations differ in cost, good players play longer games, so the estimate is rough).

    python benchmarks/experiment_all.py crossover              # full size (20 trials x 5,000 evaluations)
    python benchmarks/experiment_all.py selection --trials 2 --generations 5    # a quick look
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.presets import ALL, BEYOND_NAMES, PRESET_NAMES, ExperimentOptions
from soccer_lab.app.experiment.runner import plan, run_experiment
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("preset", choices=(*PRESET_NAMES, *BEYOND_NAMES))
    parser.add_argument("--trials", type=int)
    parser.add_argument("--generations", type=int, default=ExperimentOptions().generations)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    add_record_option(parser)
    arguments = parser.parse_args()
    load_before = load_average()
    options = ExperimentOptions(trials=arguments.trials, generations=arguments.generations)
    with tempfile.TemporaryDirectory() as folder:
        started = time.perf_counter()
        outcome = run_experiment(arguments.preset, options, Path(folder), LocalExecutor(arguments.workers))
        seconds = time.perf_counter() - started
    games = sum(spec.setting.games for spec in outcome.plan.specs)  # each best's replays aside
    rate = games / seconds
    everything = sum(spec.setting.games for spec in plan(ALL, ExperimentOptions()).specs)
    print(f"{arguments.preset}: {len(outcome.plan.specs)} trials, {games} games, {seconds:.1f} s "
          f"on {arguments.workers} workers ({rate:.0f} games/s)")
    print(f"experiment all at full size: {everything} games (shared trials counted once), "
          f"estimated {everything / rate / 60:.1f} min at this rate")
    if arguments.record:
        record("experiment_all", [
            Figure(f"`{arguments.preset}` preset, {len(outcome.plan.specs)} trials, {games:,} evaluations, "
                   f"{arguments.workers} workers", round(seconds, 1), "s", note=f"{rate:.0f} evaluations/s"),
            Figure("`experiment all` at full size, estimated from that rate", round(everything / rate / 60, 1), "min",
                   target="< 30 min", note=f"{everything:,} evaluations"),
        ], command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
