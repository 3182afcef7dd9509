"""A match on a session's pitch: the MatchEnv (soccer/match_env.py, the match `play_matches` counts), the two
players' rules, whose thinking the panels show, and what they read from it each frame. It answers what the
session and the panels ask a Game (app/web/ui/game.py) with the watched player's rules, inputs and decision,
so the Inference panel, the membership degrees and the policy map follow the player chosen."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.command_mark import command_mark
from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.game import rules_summary
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.web.ui.pitch import MatchMarks, PitchFrame, PitchGeometry
from soccer_lab.fuzzy.engine import Engine, Inference
from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.match_env import MatchEnv, MatchState
from soccer_lab.soccer.outcome import Outcome, end_reason_sentence
from soccer_lab.soccer.perception import BALL

LETTERS = ("A", "B")
COLOURS = (style.PLAYER, style.OPPONENT)  # A's, B's: on the pitch and beside their names
HALF_TIME_TICKS = 30  # ticks' time the half-time score stays on screen before the second half kicks off


class _Seen(NamedTuple):
    """What command_mark reads of a tick, for one player in the pitch's frame."""

    outcome: Outcome | None
    player: tuple[float, float]
    facing: float  # degrees
    ball: tuple[float, float]


def hex_colour(rgb: tuple[int, int, int]) -> str:
    return "#%02x%02x%02x" % rgb


class MatchGame:
    """`names`: A's and B's, as the Play tab and the pitch show them; `watched`: whose thinking the panels show
    (0: A, 1: B)."""

    def __init__(self, context: UiContext, players: tuple[Rulebase, Rulebase], names: tuple[str, str], seed: int,
                 config: GameConfig, vocabulary: Vocabulary):
        self.context = context
        self.vocabulary = vocabulary
        self.config = config
        self.players = players
        self.names = names
        self.env = MatchEnv(*players, config, vocabulary)
        self.geometry = PitchGeometry.from_world(config.world)
        self.view_half_angle = config.world.view_width / 2
        self._engines = tuple(Engine(rulebase, vocabulary) for rulebase in players)
        self._rule_texts = tuple([format_rule(rule, vocabulary) for rule in rulebase] for rulebase in players)
        self.watched = 0
        self.restart(seed)

    # ---- what the session does to it ----------------------------------------------------------
    def restart(self, seed: int) -> None:
        self.seed = seed
        self.state: MatchState = self.env.reset(seed)
        self._half_time_left = HALF_TIME_TICKS
        self._inference: Inference | None = None

    def step(self) -> None:
        """One tick; at half time the score stays on screen HALF_TIME_TICKS ticks' time before the kick-off."""
        if self.done:
            return
        if self.state.half_over and self._half_time_left > 0:
            self._half_time_left -= 1
            return
        self.state = self.env.step()
        self._inference = None

    def skip_half_time(self) -> None:
        """The next step kicks off the second half at once (the Step button: one click, one tick)."""
        self._half_time_left = 0

    def watch(self, player: int) -> None:
        """Show the thinking of A (0) or B (1)."""
        self.watched = player
        self._inference = None

    @property
    def done(self) -> bool:
        return bool(self.state.done)

    # ---- the watched player, as a Game's player --------------------------------------------------
    @property
    def rulebase(self) -> Rulebase:
        return self.players[self.watched]

    @property
    def name(self) -> str:
        return self.names[self.watched]

    @property
    def rule_texts(self) -> list[str]:
        return self._rule_texts[self.watched]

    def inputs(self) -> dict[str, float | None]:
        """The watched player's crisp inputs, in its own frame, as its rules saw them."""
        return dict(self.state.minds[self.watched].inputs)

    def inference(self) -> Inference:
        if self._inference is None:
            self._inference = self._engines[self.watched].infer(self.inputs())
        return self._inference

    def outcome_text(self) -> str | None:
        outcome = self.state.minds[self.watched].outcome
        return outcome.describe(self.config.skills, self.vocabulary) if outcome is not None else None

    def outcome_refused(self) -> bool:
        outcome = self.state.minds[self.watched].outcome
        return outcome is not None and outcome.refused

    # ---- the pitch ----------------------------------------------------------------------------
    def attacks_right(self, player: int) -> bool:
        """Whether `player` attacks the goal at +x (the screen's right) this half."""
        return self.state.a_on_left == (player == 0)

    def frame(self) -> PitchFrame:
        s, watched = self.state, self.watched
        seen = [_Seen(m.outcome, s.players[p], s.facings[p], s.ball) for p, m in enumerate(s.minds)]
        goal = (self.geometry.half_length * (1 if self.attacks_right(watched) else -1), 0.0)
        return PitchFrame(
            player=s.players[0],
            facing=float(np.radians(s.facings[0])),
            ball=s.ball,
            trail=np.array(s.ball_trail, dtype=np.float64).reshape(-1, 2),
            ball_visible=s.minds[0].visible[BALL],
            command=command_mark(seen[watched], goal, self.geometry.grass),
            match=MatchMarks(
                player=s.players[1], facing=float(np.radians(s.facings[1])), ball_visible=s.minds[1].visible[BALL],
                labels=(self.pitch_label(0), self.pitch_label(1)), watched=watched),
        )

    def pitch_label(self, player: int) -> str:
        """The letter under a player on the pitch, with the way it attacks: "A →" or "← B" (the names, which may
        be long, are beside the letters in the Play tab and the projector's band)."""
        letter = LETTERS[player]
        return f"{letter} →" if self.attacks_right(player) else f"← {letter}"

    # ---- the words ----------------------------------------------------------------------------
    def clock(self) -> str:
        s = self.state
        return f"half {s.half} of 2 · tick {s.tick} / {self.config.max_ticks}"

    def score_html(self, size: int) -> str:
        """A's name and goals, B's goals and name, in a line, each name in its player's colour (the projector's)."""
        s = self.state
        a, b = (self._name_html(p) for p in (0, 1))
        return (f'<span class="match-score" data-goals="{s.goals[0]}-{s.goals[1]}" style="font-size:{size}px; '
                f'font-weight:700">{a} <span style="color:{style.INK}">{s.goals[0]} – {s.goals[1]}</span> {b}</span>')

    def score_rows_html(self, size: int) -> str:
        """A row per player, its name in its colour and its goals at the right (the Play tab's, narrow)."""
        s = self.state
        rows = "".join(
            f'<div style="display:flex; gap:8px; align-items:baseline"><span style="flex:1; min-width:0; '
            f'overflow-wrap:anywhere">{self._name_html(p)}</span><span class="match-goals" '
            f'style="color:{style.INK}">{s.goals[p]}</span></div>' for p in (0, 1))
        return (f'<div class="match-score" data-goals="{s.goals[0]}-{s.goals[1]}" style="font-size:{size}px; '
                f'font-weight:700; line-height:1.2; {style.SCROLLBAR_ROOM}">{rows}</div>')

    def _name_html(self, player: int) -> str:
        return (f'<span class="match-name" data-player="{LETTERS[player]}" style="color:{hex_colour(COLOURS[player])}">'
                f"● {LETTERS[player]} {escape(self.names[player])}</span>")

    def sides_sentence(self) -> str:
        left = 0 if self.state.a_on_left else 1
        return (f"{LETTERS[left]} attacks → (the right goal), {LETTERS[1 - left]} attacks ← this half"
                f"{'; the sides swap at half time' if self.state.half == 1 else ''}")

    def break_sentence(self) -> str:
        """Half time, or full time with the winner; "" while a half plays."""
        s = self.state
        if s.done:
            a, b = s.goals
            winner = f"{LETTERS[0]} {self.names[0]} wins" if a > b else \
                f"{LETTERS[1]} {self.names[1]} wins" if b > a else "a draw"
            return f"Full time: {winner} {a}–{b}"
        if s.half_over:
            why = end_reason_sentence(s.end_reason, self.config.max_ticks, self.config.goal_cap,
                                      self.config.idle_ticks).replace("the player", "both players")
            return f"Half time, {why}: the players swap sides"
        return ""

    def end_sentence(self) -> str:
        return self.break_sentence()

    def thinking_sentence(self) -> str:
        return f"The panels show the thinking of {LETTERS[self.watched]}: {self.names[self.watched]}"

    def status_html(self) -> str:
        s, config = self.state, self.config
        pause = self.break_sentence()
        changed = rules_summary(config)
        return (
            f'<div class="game-status match-status" data-tick="{s.tick}" data-half="{s.half}" '
            f'data-goals="{s.goals[0]}-{s.goals[1]}" data-done="{str(self.done).lower()}" '
            f'data-watched="{LETTERS[self.watched]}" style="{style.FONT}; font-size:{style.FONT_SIZE + 2}px; '
            f'color:{style.INK}">'
            f"{self.score_rows_html(style.FONT_SIZE + 6)}"
            f'<div class="match-clock">{self.clock()}</div>'
            f'<div class="match-sides" style="color:{style.MUTED}; font-size:{style.FONT_SIZE}px">'
            f"{self.sides_sentence()}</div>"
            + (f'<div class="match-break" style="color:{style.ERROR}; font-weight:600">{escape(pause)}.</div>'
               if pause else "")
            + f'<div class="match-thinking" style="font-size:{style.FONT_SIZE}px">{escape(self.thinking_sentence())}'
            f'</div><div style="color:{style.MUTED}; font-size:{style.FONT_SIZE}px">seed {self.seed} · '
            f"{escape(changed)}</div></div>"
        )
