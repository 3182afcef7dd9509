"""The game on a session's pitch: the SoccerEnv (a batch of one through the one engine), the rulebase it
plays, and what the panels read from it each frame (pitch frame, crisp inputs, the scalar inference)."""

from __future__ import annotations

import numpy as np

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.command_mark import command_mark
from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.web.ui.pitch import PitchFrame, PitchGeometry
from soccer_lab.fuzzy.engine import Engine, Inference
from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.env import SoccerEnv
from soccer_lab.soccer.outcome import end_reason_sentence
from soccer_lab.soccer.perception import BALL  # the ball's visibility colours the view cone


class Game:
    """`config`: the game's rules (default: the app's); a run's players play in their run's game."""

    def __init__(self, context: UiContext, rulebase: Rulebase, name: str, seed: int, config: GameConfig | None = None):
        self.context = context
        self.vocabulary = context.vocabulary
        self.config = config if config is not None else context.game
        self.env = SoccerEnv(rulebase, self.config, context.vocabulary)
        self.geometry = PitchGeometry.from_world(self.config.world)
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
            command=command_mark(s, self.geometry.goal, self.geometry.grass),
        )

    def outcome_text(self) -> str | None:
        """What the player did on its last decision and why, in a sentence (None before the first)."""
        outcome = self.state.outcome
        return outcome.describe(self.config.skills, self.vocabulary) if outcome is not None else None

    def outcome_refused(self) -> bool:
        """Whether the last decision's skill could not do what its action asks."""
        return self.state.outcome is not None and self.state.outcome.refused

    def status_html(self) -> str:
        s, config = self.state, self.config
        return (
            f'<div class="game-status" data-tick="{s.tick}" data-goals="{s.goals}" data-idle="{s.idle}" '
            f'data-done="{str(self.done).lower()}" style="{style.FONT}; font-size:{style.FONT_SIZE + 2}px; '
            f'color:{style.INK}">'
            f'<div style="font-size:{style.FONT_SIZE + 10}px; font-weight:700">Goals {s.goals}'
            f'<span style="font-weight:400; font-size:{style.FONT_SIZE + 2}px; color:{style.MUTED}"> '
            f"kicks {s.kicks}</span></div>"
            f"<div>tick {s.tick} / {config.max_ticks}</div>"
            f'<div style="color:{style.MUTED}">seed {self.seed} · playing <b style="color:{style.INK}">'
            f"{escape(self.name)}</b></div>"
            f"{self._idle_html()}{self._end_html()}{self._changed_rules_html()}</div>"
        )

    def _changed_rules_html(self) -> str:
        """The game's choices beyond its skill set (the Skills control below names that), when any is on."""
        changed = rules_summary(self.config, skills=False)
        return f'<div class="game-rules" style="color:{style.MUTED}">{escape(changed)}</div>' if changed else ""

    def _idle_html(self) -> str:
        """The idle countdown, once the player has stood still a tick: the game ends when it runs out."""
        s, limit = self.state, self.config.idle_ticks
        if s.idle == 0 or self.done:
            return ""
        share = min(s.idle / limit, 1.0)
        return (
            f'<div class="idle" data-idle="{s.idle}" style="margin-top:4px; font-size:{style.FONT_SIZE}px; '
            f'color:{style.ERROR if share > 0.5 else style.INK}">idle {s.idle} / {limit} ticks '
            f'<span style="color:{style.MUTED}">(the game ends when the player neither moves nor kicks for '
            f"{limit} ticks)</span>"
            f'<div style="height:6px; background:{style.GRID}; border-radius:3px"><div style="width:{100 * share:.0f}%; '
            f'height:6px; background:{style.ERROR}; border-radius:3px"></div></div></div>'
        )

    def end_sentence(self) -> str:
        """Why the game ended, in words (the game is over)."""
        s, config = self.state, self.config
        return end_reason_sentence(s.end_reason, config.max_ticks, config.goal_cap, config.idle_ticks)

    def _end_html(self) -> str:
        if not self.done:
            return ""
        s = self.state
        why = self.end_sentence()
        last = self.outcome_text()
        tried = f" Last it did: {escape(last)}." if last and s.end_reason == "idle" else ""
        return (
            f'<div class="game-over" data-reason="{escape(s.end_reason)}" style="margin-top:4px; '
            f'font-size:{style.FONT_SIZE}px; color:{style.ERROR}; font-weight:600">Game over: {escape(why)}.'
            f'<span style="font-weight:400; color:{style.INK}">{tried}</span>'
            f'<div class="next-game" style="font-weight:400; color:{style.INK}">The game stays over: <b>New random '
            f"start</b> or <b>Restart this seed</b> (Play tab) plays the next one.</div></div>"
        )


def rules_summary(config: GameConfig, skills: bool = True) -> str:
    """The open choices of a game (docs/research/calibration.md) in a line, e.g. "sighted skills · noise"."""
    parts = [f"{config.skills} skills"] if skills else []
    if config.noise:
        parts.append("noise")
    if config.count_touches:
        parts.append("body pushes count as kicks")
    return " · ".join(parts)
