"""The game on a session's pitch: the SoccerEnv (a batch of one through the one engine), the rulebase it
plays, and what the panels read from it each frame (pitch frame, crisp inputs, the scalar inference)."""

from __future__ import annotations

import numpy as np

from app.ui import style
from app.ui.context import UiContext
from app.ui.panels.svg import escape
from app.ui.pitch import PitchFrame
from fuzzy.engine import Engine, Inference
from fuzzy.printer import format_rule
from fuzzy.rule import Rulebase
from soccer.config import GameConfig
from soccer.env import SoccerEnv
from soccer.perception import BALL  # the ball's visibility colours the view cone


class Game:
    """`config`: the game's rules (default: the app's); a run's players play in their run's game."""

    def __init__(self, context: UiContext, rulebase: Rulebase, name: str, seed: int, config: GameConfig | None = None):
        self.context = context
        self.vocabulary = context.vocabulary
        self.config = config if config is not None else context.game
        self.env = SoccerEnv(rulebase, self.config, context.vocabulary)
        self.view_half_angle = self.config.world.view_width / 2
        self.set_rulebase(rulebase, name)
        self.restart(seed)

    def set_rulebase(self, rulebase: Rulebase, name: str) -> None:
        self.rulebase = rulebase
        self.name = name
        # The scalar reference engine explains the tick (degrees, strengths, clipped sets); the env's
        # batched kernel decides, and both agree bit for bit.
        self.engine = Engine(rulebase, self.vocabulary)
        self.rule_texts = [format_rule(rule, self.vocabulary) for rule in rulebase]
        self.state = self.env.set_rulebase(rulebase)
        self._inference: Inference | None = None

    def restart(self, seed: int) -> None:
        self.seed = seed
        self.state = self.env.reset(seed)
        self._inference = None

    def step(self) -> None:
        if self.done:
            return
        self.state = self.env.step()
        self._inference = None

    @property
    def done(self) -> bool:
        return bool(self.state.done)

    # ---- what the panels read ---------------------------------------------------------------
    def inputs(self) -> dict[str, float | None]:
        """The crisp inputs of the player's decision (None for an object out of view): the last one
        made, or at a fresh start (no decision yet) the one it is about to make."""
        return dict(self.state.inputs)

    def visible(self) -> dict[str, bool]:
        return dict(self.state.visible)

    def inference(self) -> Inference:
        if self._inference is None:
            self._inference = self.engine.infer(self.inputs())
        return self._inference

    def frame(self) -> PitchFrame:
        s = self.state
        return PitchFrame(
            player=s.player,
            facing=float(np.radians(s.facing)),
            ball=s.ball,
            trail=np.array(s.ball_trail, dtype=np.float64).reshape(-1, 2),
            ball_visible=self.visible()[BALL],
        )

    def status_html(self) -> str:
        s = self.state
        over = f" — game over ({escape(s.end_reason)})" if self.done else ""
        return (
            f'<div class="game-status" data-tick="{s.tick}" data-goals="{s.goals}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE + 2}px; color:{style.INK}">'
            f'<div style="font-size:{style.FONT_SIZE + 10}px; font-weight:700">Goals {s.goals}'
            f'<span style="font-weight:400; font-size:{style.FONT_SIZE + 2}px; color:{style.MUTED}"> '
            f"kicks {s.kicks}</span></div>"
            f"<div>tick {s.tick} / {self.config.max_ticks}{over}</div>"
            f'<div style="color:{style.MUTED}">seed {self.seed} · playing <b style="color:{style.INK}">'
            f"{escape(self.name)}</b></div>"
            f'<div class="game-rules" style="color:{style.MUTED}">{escape(rules_summary(self.config))}</div></div>'
        )


def rules_summary(config: GameConfig) -> str:
    """The open choices of a game (docs/research/calibration.md) in a line, e.g. "sighted skills · noise"."""
    parts = [f"{config.skills} skills"]
    if config.noise:
        parts.append("noise")
    if config.count_touches:
        parts.append("body pushes count as kicks")
    return " · ".join(parts)
