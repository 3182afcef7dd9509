"""What recording lineage costs a Table 2 trial (issue 24's target: provenance and genotypic diversity add at
most 2%), and what counting behaviours costs (an option, K games per new chromosome).

"Without" is the code before lineage existed: `--baseline` (default: where this branch left main)
unpacked with git archive into a temporary folder; "with" is this tree. The two play the same Table 2 trial
(benchmarks/trial.py --full: population 200 x 25 generations, every generation run, 2 workers), in
alternating order (ABBA), so a load that comes and goes on a shared machine falls on both alike. Each run
also times its own parts in process: breeding (next_generation, which now records births), the
statistics (generation_stats, which now counts diversity) and, with --outputs, the run folder's callback
(which now writes lineage.jsonl). Those part times are the cost itself, without the noise of the games.

    nice -n 19 python benchmarks/lineage_cost.py [--rounds 6] [--outputs] [--behaviour-seeds 2] [--record]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from results import Figure, add_record_option, load_average, record, this_command

HERE = Path(__file__).resolve().parent.parent

# Runs in a fresh process with one tree first on sys.path: the trial as benchmarks/trial.py plays it, its
# parts timed by wrapping the functions the loop calls.
TRIAL = r"""
import json, sys, tempfile, time
from pathlib import Path
sys.path.insert(0, sys.argv[1])
options = json.loads(sys.argv[2])
import soccer_lab.ga.algorithms as algorithms
from soccer_lab.ga.config import GAConfig
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import play_games
from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator
assert algorithms.__file__.startswith(sys.argv[1]), algorithms.__file__
parts = {"breeding": 0.0, "statistics": 0.0, "outputs": 0.0, "behaviours": 0.0}

def timed(owner, name, part):
    original = getattr(owner, name)
    def wrapper(*args, **kwargs):
        started = time.perf_counter()
        try:
            return original(*args, **kwargs)
        finally:
            parts[part] += time.perf_counter() - started
    setattr(owner, name, wrapper)

timed(algorithms, "next_generation", "breeding")
timed(algorithms, "generation_stats", "statistics")
if hasattr(algorithms, "BehaviourProbe"):
    timed(algorithms.BehaviourProbe, "__call__", "behaviours")
config = GAConfig(workers=2, target_fitness=0.0, **options["ga"])
game = GameConfig()
play_games([demo_rulebase()], [0], game)  # the compiled kernels loaded before the clock starts
started = time.perf_counter()
if options["outputs"]:
    from soccer_lab.app.runs.run import Run, RunSettings
    from soccer_lab.app.runs.outputs import RunOutputs
    timed(RunOutputs, "on_generation", "outputs")
    with tempfile.TemporaryDirectory() as folder:
        run = Run.create(RunSettings(config, game), Path(folder) / "run")
        with run.evaluator() as evaluate:
            result = run.play(evaluate)
else:
    result = algorithms.evolve(config, SimpleSoccerEvaluator(game), Vocabulary.default())
wall = time.perf_counter() - started
print(json.dumps({"wall": wall, **parts, "generations": len(result.history)}))
"""


def trial(tree: Path, outputs: bool, ga: dict) -> dict:
    before = load_average()
    done = subprocess.run([sys.executable, "-c", TRIAL, str(tree), json.dumps({"outputs": outputs, "ga": ga})],
                          cwd=tree, capture_output=True, text=True, check=True)
    return {**json.loads(done.stdout.strip().splitlines()[-1]), "load": [before[0], load_average()[0]]}


def interleaved(trees: dict[str, tuple[Path, dict]], rounds: int, outputs: bool) -> dict[str, list[dict]]:
    """Each tree once unmeasured (compiles its kernels), then `rounds` rounds in ABBA order."""
    names = list(trees)
    for name in names:
        trial(trees[name][0], outputs, trees[name][1])
    runs: dict[str, list[dict]] = {name: [] for name in names}
    for r in range(rounds):
        for name in (names if r % 2 == 0 else list(reversed(names))):
            runs[name].append(trial(trees[name][0], outputs, trees[name][1]))
            print(f"  {name:<12} round {r + 1}: {runs[name][-1]['wall']:.2f} s (load {runs[name][-1]['load']})",
                  file=sys.stderr)
    return runs


def median(runs: list[dict], key: str) -> float:
    return statistics.median(run[key] for run in runs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--baseline", default=None, help="git ref of the code without lineage (default: the "
                        "merge base of HEAD and main)")
    parser.add_argument("--outputs", action="store_true", help="also play the trials as runs with their folder's "
                        "outputs (checkpoint, statistics.csv, the recording, lineage.jsonl)")
    parser.add_argument("--behaviour-seeds", type=int, default=2, help="K for the behavioural diversity's cost "
                        "(0: skip it)")
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    base = args.baseline or subprocess.run(["git", "merge-base", "HEAD", "main"], cwd=HERE, capture_output=True,
                                           text=True, check=True).stdout.strip()
    figures: list[Figure] = []
    with tempfile.TemporaryDirectory() as temporary:
        baseline = Path(temporary) / "baseline"
        baseline.mkdir()
        archive = subprocess.run(["git", "archive", base], cwd=HERE, capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(baseline)], input=archive, check=True)
        for outputs in (False, True) if args.outputs else (False,):
            kind = "as a run with its folder's outputs" if outputs else "plain"
            print(f"Table 2 trial, {kind}: without lineage ({base[:7]}) and with", file=sys.stderr)
            runs = interleaved({"without": (baseline, {}), "with": (HERE, {})}, args.rounds, outputs)
            figures += _lineage_figures(runs, kind, outputs)
    if args.behaviour_seeds:
        print(f"Table 2 trial without and with behaviours on {args.behaviour_seeds} seeds", file=sys.stderr)
        runs = interleaved({"K=0": (HERE, {}), f"K={args.behaviour_seeds}": (HERE, {"behaviour_seeds": args.behaviour_seeds})},
                           args.rounds, False)
        plain, counted = runs["K=0"], runs[f"K={args.behaviour_seeds}"]
        figures += [
            Figure(f"trial with behaviours counted on K={args.behaviour_seeds} seeds / without", round(
                median(counted, "wall") / median(plain, "wall"), 3), "x", note=f"median of {args.rounds} each"),
            Figure(f"counting behaviours (K={args.behaviour_seeds}) per trial", round(median(counted, "behaviours"), 2), "s",
                   note="the probe's own time: decoding and playing the new chromosomes on the seeds"),
        ]
    for figure in figures:
        print(f"{figure.name}: {figure.value} {figure.unit}  {figure.note}")
    print(f"load average before {load_before}, after {load_average()}")
    if args.record:
        record("lineage_cost", figures, this_command(), load_before)


def _lineage_figures(runs: dict[str, list[dict]], kind: str, outputs: bool) -> list[Figure]:
    without, with_ = runs["without"], runs["with"]
    wall = median(without, "wall")
    parts = ("breeding", "statistics") + (("outputs",) if outputs else ())
    added = sum(median(with_, part) - median(without, part) for part in parts)
    note = f"median of {len(with_)} each, ABBA; load average {min(r['load'][0] for r in with_ + without):.1f}-" \
           f"{max(r['load'][1] for r in with_ + without):.1f}"
    return [
        Figure(f"Table 2 trial ({kind}) without lineage", round(wall, 2), "s", note=note),
        Figure(f"Table 2 trial ({kind}) with lineage", round(median(with_, "wall"), 2), "s", note=note),
        Figure(f"with / without ({kind})", round(median(with_, "wall") / wall, 3), "x", target="<= 1.02"),
        Figure(f"added by births, diversity{' and lineage.jsonl' if outputs else ''} ({kind})",
               round(100 * added / wall, 2), "% of the trial", target="<= 2 %",
               note=f"{added * 1000:.0f} ms: the {', '.join(parts)} parts' medians, with minus without"),
    ]


if __name__ == "__main__":
    main()
