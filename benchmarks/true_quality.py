"""What re-playing the best so far costs a Table 2 trial (target: at most 5% of its wall time). A run
re-plays its best on app/runs/true_quality.py's common starts each time the best changes (one batch of
TRUE_QUALITY_STARTS single games); this plays the Table 2 trial of benchmarks/trial.py --full (population
200 x 25 generations, every generation run, 2 workers) as a run with its folder's outputs and times the
re-plays inside it, so the cost is measured without the noise of the games around it. The same run also
times what the UI's population view adds: each generation's shown players (its 12 best playable) re-played
on the same starts in one batch, best-ranked first, an elite shown before not again, within the view's share
of the wall time (app/web/ui/player_qualities.py's PlayerQualities, here called at each generation's end
instead of on its thread), as a share of the run without it, and how many of the shown players got a
figure; what the view's button "Measure these 12 on 20 fresh starts" costs when pressed after the run (the last
generation's shown players, none known before, in one batch, against the run's seconds per generation); and, for
scale, what re-playing all of them every generation would cost.

    nice -n 19 python benchmarks/true_quality.py [--rounds 3] [--record]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

from results import Figure, add_record_option, load_average, record, this_command

HERE = Path(__file__).resolve().parent.parent

TRIAL = r"""
import json, sys, tempfile, time
from pathlib import Path
import soccer_lab.app.runs.run as run_module
import soccer_lab.app.runs.true_quality as true_quality
from soccer_lab.app.runs.run import Run, RunSettings
from soccer_lab.ga.config import GAConfig
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import play_games
spent = {"replays": 0.0, "count": 0}
original = true_quality.replayed_quality
def timed(*args, **kwargs):
    started = time.perf_counter()
    try:
        return original(*args, **kwargs)
    finally:
        spent["replays"] += time.perf_counter() - started
        spent["count"] += 1
true_quality.replayed_quality = timed
from soccer_lab.app.runs.manager import sample_players
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.player_qualities import PlayerQualities
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.soccer.config import SOCCER_VOCABULARY
shown = style.POPULATION_GRID[0] * style.POPULATION_GRID[1]
class PopulationView:
    def __init__(self, game, share):
        self.qualities = PlayerQualities(SOCCER_VOCABULARY, share=share)
        self.game, self.codec = game, ChromosomeCodec(SOCCER_VOCABULARY)
        self.generations, self.figures, self.players = 0, 0, []
    def on_generation(self, stats, population):
        players = self.players = sample_players(population, self.codec)[:shown]
        answered = self.qualities._qualities(0, self.game, [p.rulebase for p in players])
        self.generations += 1
        self.figures += sum(quality is not None for quality in answered)
SHARE = {"budget": style.POPULATION_REPLAY_SHARE, "all": None}[sys.argv[1]]
config = GAConfig(workers=2, target_fitness=0.0)
game = GameConfig()
play_games([demo_rulebase()], [0], game)  # the compiled kernels loaded before the clock starts
with tempfile.TemporaryDirectory() as folder:
    started = time.perf_counter()
    run = Run.create(RunSettings(config, game), Path(folder) / "run")
    view = PopulationView(game, SHARE)
    with run.evaluator() as evaluate:
        result = run.play(evaluate, callbacks=[view])
    wall = time.perf_counter() - started
button = PlayerQualities(SOCCER_VOCABULARY, share=None)  # pressed after the run: every shown player, none known
started = time.perf_counter()
button._qualities(0, game, [p.rulebase for p in view.players], everyone=True)
print(json.dumps({"wall": wall - view.qualities.spent, **spent, "starts": true_quality.TRUE_QUALITY_STARTS,
                  "population": view.qualities.spent, "generations": view.generations, "shown": shown,
                  "figures": view.figures, "share": SHARE, "button": time.perf_counter() - started,
                  "button_players": len(view.players)}))
"""


def trial(population: str = "budget") -> dict:
    """One Table 2 run; the population view re-plays within its share ("budget") or every shown player ("all")."""
    before = load_average()
    done = subprocess.run([sys.executable, "-c", TRIAL, population], cwd=HERE, capture_output=True, text=True,
                          check=True)
    return {**json.loads(done.stdout.strip().splitlines()[-1]), "load": [before[0], load_average()[0]]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    trial()  # unmeasured: compiles the kernels
    runs = []
    for r in range(args.rounds):
        runs.append(trial())
        print(f"  round {r + 1}: trial {runs[-1]['wall']:.2f} s, {runs[-1]['count']} re-plays "
              f"{runs[-1]['replays']:.3f} s, population view {runs[-1]['population']:.3f} s, its button "
              f"{runs[-1]['button']:.2f} s (load {runs[-1]['load']})", file=sys.stderr)
    everyone = trial("all")  # for scale: every shown player re-played every generation
    print(f"  every shown player: trial {everyone['wall']:.2f} s, population view {everyone['population']:.3f} s "
          f"(load {everyone['load']})", file=sys.stderr)
    shares = [run["replays"] / run["wall"] for run in runs]
    starts = runs[0]["starts"]
    figures = [
        Figure(f"re-playing the best so far on {starts} fresh starts, share of a Table 2 run (200 x 25, 2 workers)",
               round(100 * statistics.median(shares), 2), "%", "<= 5 %", note=f"median of {args.rounds} runs"),
        Figure("re-plays per Table 2 run (each time the best changed)", statistics.median(r["count"] for r in runs)),
        Figure("time re-playing per Table 2 run", round(statistics.median(r["replays"] for r in runs), 3), "s"),
        Figure("one Table 2 run with its folder's outputs", round(statistics.median(r["wall"] for r in runs), 2), "s"),
        Figure(f"the population view re-playing its shown players on {starts} fresh starts, best first, share of "
               "that run", round(100 * statistics.median(r["population"] / r["wall"] for r in runs), 2), "%",
               f"<= {100 * runs[0]['share']:.0f} %", note="on its own thread, beside the run"),
        Figure(f"shown players re-played per generation (of {runs[0]['shown']})",
               round(statistics.median(r["figures"] / r["generations"] for r in runs), 2)),
        Figure(f"the population view's button: its {runs[0]['button_players']} shown players re-played on {starts} "
               "fresh starts at once", round(statistics.median(r["button"] for r in runs), 2), "s",
               note="a Table 2 generation takes "
                    f"{statistics.median(r['wall'] / r['generations'] for r in runs):.2f} s"),
        Figure(f"all {everyone['shown']} shown players re-played every generation, share of the run (not done: "
               "for scale)", round(100 * everyone["population"] / everyone["wall"], 1), "%", note="one run"),
    ]
    for figure in figures:
        print(f"{figure.name}: {figure.value} {figure.unit}  {figure.note}")
    print(f"load average before {load_before}, after {load_average()}")
    if args.record:
        record("true_quality", figures, this_command(), load_before)


if __name__ == "__main__":
    main()
