"""UI frame cost on the server: 30 frames per second for one game with all panels live.

Builds what a session sends each frame — one simulator tick, the scalar inference that explains it,
the pitch frame, the decision, rule, output-set and membership panels, and the policy map — for a
rulebase of RULES rules, and reports the time per frame and the frame rate that leaves (the websocket
and the browser's drawing come on top; with one tab they stay far below this on localhost). `--match`
also measures a match's frame (app/web/ui/match_game.py: two players of RULES rules each, the panels
explaining one of them), beside the game's.

    python benchmarks/ui_frame.py [--frames 300] [--rules 10] [--match]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.game import Game
from soccer_lab.app.web.ui.match_game import MatchGame
from soccer_lab.app.web.ui.panels.membership import input_html, input_names
from soccer_lab.app.web.ui.panels.outputs import outputs_html
from soccer_lab.app.web.ui.panels.policy import policy_grid, policy_map_html
from soccer_lab.app.web.ui.panels.rules import decision_html, rules_html
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py

SEED = 7


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--rules", type=int, default=10)
    parser.add_argument("--match", action="store_true", help="also a match's frame (two players), beside a game's")
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    vocabulary = Vocabulary.default()
    context = UiContext(None, None, vocabulary, GameConfig())
    rng = np.random.default_rng(SEED)
    rulebase = random_rulebase(rng, vocabulary, rules=args.rules)
    per_frame = frame_cost(Game(context, rulebase, "benchmark", seed=SEED), vocabulary, args.frames)
    print(f"{args.rules} rules: {per_frame * 1e3:.2f} ms per frame on the server "
          f"-> {1 / per_frame:.0f} frames/s possible (target {style.FRAME_RATE:.0f})")
    figures = [Figure(f"UI, one game with every panel live, {args.rules} rules (server side)",
                      round(per_frame * 1e3, 2), "ms per frame",
                      target=f"{style.FRAME_RATE:.0f} frames/s ({1e3 / style.FRAME_RATE:.0f} ms)",
                      note=f"{1 / per_frame:.0f} frames/s possible")]
    if args.match:
        other = random_rulebase(rng, vocabulary, rules=args.rules)
        match = MatchGame(context, (rulebase, other), ("A", "B"), SEED, GameConfig(), vocabulary)
        per_match_frame = frame_cost(match, vocabulary, args.frames)
        print(f"a match, {args.rules} rules each: {per_match_frame * 1e3:.2f} ms per frame "
              f"({per_match_frame / per_frame:.2f}x a game's) -> {1 / per_match_frame:.0f} frames/s possible")
        figures.append(Figure(f"UI, one match with every panel live, {args.rules} rules each (server side)",
                              round(per_match_frame * 1e3, 2), "ms per frame",
                              target=f"{style.FRAME_RATE:.0f} frames/s ({1e3 / style.FRAME_RATE:.0f} ms)",
                              note=f"{per_match_frame / per_frame:.2f}x a game's frame"))
    if args.record:
        record("ui_frame", figures, command=this_command(), load_before=load_before)


def frame_cost(game: Game | MatchGame, vocabulary: Vocabulary, frames: int) -> float:
    """Seconds per frame: a tick of `game` and everything the panels draw of it (restarted when it ends)."""
    game.step()  # compile and warm up
    grid = policy_grid(vocabulary, game.rulebase, 30.0, 0.0, True, game.view_half_angle, "power")
    start = time.perf_counter()
    for frame in range(frames):
        if game.done:
            game.restart(SEED + frame)
        game.step()
        inputs, inference = game.inputs(), game.inference()
        game.frame()
        game.status_html()
        decision_html(vocabulary, inference)
        rules_html(game.rule_texts, inference, only_fired=False)
        outputs_html(vocabulary, inference)
        for name in input_names(vocabulary):
            input_html(vocabulary, name, inputs.get(name))
        if frame % round(style.FRAME_RATE * style.POLICY_REFRESH_SECONDS) == 0:
            ball = inputs["ball_distance"], inputs["ball_direction"]
            policy_map_html(vocabulary, grid, "power", ball if ball[0] is not None else None)
    return (time.perf_counter() - start) / frames


if __name__ == "__main__":
    main()
