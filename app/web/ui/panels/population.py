"""Population view: a grid of small pitches, all played at once by the batched engine (one GameBatch,
one pymunk Space). While this tab's evolution runs, it shows the latest generation's best players
(the RunManager samples them as each generation finishes), all from the same start so the class
compares them fairly, live while the next generation is being evaluated; after the run, its last. Under
each, its true quality: the player re-played on the common fresh starts (app/runs/true_quality.py), by
`PlayerQualities` (player_qualities.py) on a thread of its own, never on a tab's frame loop."""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Callable, Sequence

import numpy as np
import viser

from soccer_lab.app.runs.true_quality import TrueQuality
from soccer_lab.app.words import plural
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.game import rules_summary
from soccer_lab.app.web.ui.panels.svg import escape, svg_open
from soccer_lab.app.web.ui.pitch import PitchGeometry
from soccer_lab.app.web.ui.player_qualities import PlayerQualities
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig, WorldConfig
from soccer_lab.soccer.engine import END_REASONS, GameBatch, GameState, Observation
from soccer_lab.soccer.outcome import END_REASON_LABELS

if TYPE_CHECKING:
    from soccer_lab.app.runs.manager import SampledPlayer

EMPTY_TEXT = ("Start an evolution in the Evolve tab. Once its first generation has been evaluated, that "
              "generation's best players play here, side by side, while the next one is evaluated.")


def population_html(
    geometry: PitchGeometry, observation: Observation, state: GameState, labels: Sequence[str],
    columns: int = style.POPULATION_GRID[0], qualities: Sequence[TrueQuality | None] | None = None,
    replaying: bool = True,
) -> str:
    """Small pitches in a grid of `columns`, game g where observation[g] saw it (state: the games' score and
    whether and why each ended); with `qualities`, under each its player's true quality (None: being re-played
    while `replaying`, else not re-played)."""
    cells = "".join(
        _mini_pitch(geometry, observation, g, int(state.goals[g]), END_REASONS[state.end_reason[g]] if state.done[g]
                    else None, labels[g], "" if qualities is None else _quality_line(qualities[g], replaying))
        for g in range(len(labels))
    )
    return (
        f'<div class="population" data-games="{len(labels)}" style="{style.FONT}; display:grid; '
        f'grid-template-columns:repeat({columns}, 1fr); gap:6px">{cells}</div>'
    )


def _quality_line(quality: TrueQuality | None, replaying: bool = True) -> str:
    """The player's re-played fitness (mean ± spread) under its pitch; 're-playing…' until known, 'not
    re-played' when the re-play budget had no time for it."""
    if quality is not None:
        text = f"re-played {quality.fitness:.2f} ± {quality.fitness_std:.2f}"
    else:
        text = "re-playing…" if replaying else "not re-played"
    value = "" if quality is None else f"{quality.fitness:.6f}"
    return (f'<div class="replayed" data-replayed="{value}" style="margin-top:-4px; "font-size:{style.SMALL_FONT_SIZE}px; '
            f'color:{style.MUTED}">{text}</div>')


def _mini_pitch(geometry: PitchGeometry, observation: Observation, g: int, goals: int, ended: str | None,
                label: str, below: str = "") -> str:
    margin = style.MINI_PITCH_MARGIN
    width = 2 * (geometry.half_length + margin) + geometry.goal_depth
    height = 2 * (geometry.half_width + margin)
    scale = style.MINI_PITCH_WIDTH / width
    h = height * scale

    def x(value: float) -> float:
        return (value + geometry.half_length + margin) * scale

    def y(value: float) -> float:
        return (value + geometry.half_width + margin) * scale  # +y (the player's right) is down, as on the pitch

    hl, hw, goal = geometry.half_length, geometry.half_width, geometry.goal_half_width
    px, py = observation.player_x[g], observation.player_y[g]
    facing = np.radians(observation.facing[g])
    bx, by = observation.ball_x[g], observation.ball_y[g]
    grass = style.MINI_PITCH_GRASS if ended is None else style.MINI_PITCH_DONE
    why = "" if ended is None else (  # a grey pitch says why its game is over
        f'<text x="{style.MINI_PITCH_WIDTH / 2:.1f}" y="{h * 0.3:.1f}" font-size="13" font-weight="700" fill="white" '
        f'stroke="{style.MINI_PITCH_DONE}" stroke-width="4" paint-order="stroke" text-anchor="middle">'
        f"{escape(END_REASON_LABELS.get(ended, ended))}</text>")
    return (
        f'<div class="mini-pitch" data-goals="{goals}" data-done="{str(ended is not None).lower()}" '
        f'data-end-reason="{escape(ended or "running")}">'
        # the label and the goals over the pitch, in the panel's text size (read from the back of a class)
        f'<div style="display:flex; justify-content:space-between; font-size:{style.SMALL_FONT_SIZE + 1}px; '
        f'color:{style.INK}"><span>{escape(label)}</span><b>{plural(goals, "goal")}</b></div>'
        f"{svg_open(style.MINI_PITCH_WIDTH, h)}"
        f'<rect width="{style.MINI_PITCH_WIDTH}" height="{h:.1f}" fill="{grass}" rx="3"/>'
        f'<rect x="{x(-hl):.1f}" y="{y(-hw):.1f}" width="{2 * hl * scale:.1f}" height="{2 * hw * scale:.1f}" '
        f'fill="none" stroke="white" stroke-width="1"/>'
        f'<line x1="{x(0):.1f}" y1="{y(-hw):.1f}" x2="{x(0):.1f}" y2="{y(hw):.1f}" stroke="white" stroke-width="1"/>'
        f'<rect x="{x(hl):.1f}" y="{y(-goal):.1f}" width="{geometry.goal_depth * scale:.1f}" '
        f'height="{2 * goal * scale:.1f}" fill="white"/>'
        f'<circle cx="{x(px):.1f}" cy="{y(py):.1f}" r="3.5" fill="{style.MINI_PITCH_PLAYER}" stroke="white" stroke-width="1"/>'
        f'<line x1="{x(px):.1f}" y1="{y(py):.1f}" x2="{x(px) + 7 * np.cos(facing):.1f}" '
        f'y2="{y(py) + 7 * np.sin(facing):.1f}" stroke="white" stroke-width="1.5"/>'
        f'<circle cx="{x(bx):.1f}" cy="{y(by):.1f}" r="2.5" fill="{style.BALL_HEX}"/>{why}</svg>{below}</div>'
    )


class PopulationPanel:
    """`start_seed()`: the seed every small pitch starts from (the main pitch's, so the class sees a
    start it knows); `game_of_run(run_id)`: the game a run's players play in (its own skills and rules, so
    the grid shows them as they were evaluated). The small pitches are drawn to `world`. `qualities`
    re-plays the shown players of a run for which `replayable(run_id)` (a SimpleSoccer run: an rcssserver
    run's fitness is not SimpleSoccer's); None: no true quality shown."""

    def __init__(self, gui: viser.GuiApi, world: WorldConfig, vocabulary: Vocabulary, *,
                 start_seed: Callable[[], int], game_of_run: Callable[[int], GameConfig],
                 qualities: PlayerQualities | None = None, replayable: Callable[[int], bool] = lambda run_id: True):
        self.vocabulary = vocabulary
        self.start_seed = start_seed
        self.game_of_run = game_of_run
        self.qualities = qualities
        self.replayable = replayable
        self.game: GameConfig | None = None  # the shown run's
        self.geometry = PitchGeometry.from_world(world)
        self.caption = gui.add_html("")
        self.grid = gui.add_html(
            f'<div style="{style.FONT}; color:{style.MUTED}; font-size:{style.FONT_SIZE}px">{escape(EMPTY_TEXT)}</div>'
        )
        self.batch: GameBatch | None = None
        self.labels: list[str] = []
        # Set from the run's thread, picked up by the session loop: (run id, generation, its players),
        # and the run that ended with how it ended.
        self._pending: tuple[int, int, Sequence["SampledPlayer"]] | None = None
        self._ended: tuple[int, str] | None = None
        self._pending_lock = threading.Lock()
        self._shown: tuple[int, int, int, int] | None = None  # run id, generation, players, seed
        self._players: Sequence["SampledPlayer"] = ()
        self._replaying = False  # the shown players' true quality is being re-played
        self._player_qualities: list[TrueQuality | None] | None = None  # the shown players', once answered
        self._arrived: tuple[tuple, list[TrueQuality | None]] | None = None  # set by the re-play thread
        self._caption_key: tuple | None = None
        self._last_render = 0.0

    def shown_players(self) -> tuple[int, int, Sequence["SampledPlayer"]] | None:
        """The run, generation and players (by rank) the small pitches show; None before the first."""
        return None if self._shown is None else (self._shown[0], self._shown[1], self._players)

    def generation_finished(self, run_id: int, generation: int, players: Sequence["SampledPlayer"]) -> None:
        """Called from the run's thread: the next frame plays this generation's players."""
        if players:
            with self._pending_lock:
                self._pending = (run_id, generation, players)

    def run_ended(self, run_id: int, status: str) -> None:
        """Called from the run's thread: no generation follows (finished, stopped or failed)."""
        with self._pending_lock:
            self._ended = (run_id, str(status))

    def advance(self, ticks: int) -> None:
        """Called by the session loop (under its lock) with the ticks the main pitch advanced."""
        with self._pending_lock:
            pending, self._pending = self._pending, None
            arrived, self._arrived = self._arrived, None
            ended = self._ended
        if pending is not None:
            self._rebuild(*pending)
        if arrived is not None and arrived[0] == self._shown:  # not a generation shown before
            self._player_qualities, self._replaying, self._caption_key = arrived[1], False, None
        if self.batch is None:
            return
        self._show_caption(ended)
        for _ in range(ticks):
            self.batch.step()
        now = time.perf_counter()
        if now - self._last_render >= style.POPULATION_REFRESH_SECONDS:
            self._last_render = now
            qualities = (self._player_qualities or [None] * len(self.labels)) if self._replays else None
            self.grid.content = population_html(self.geometry, self.batch.observation, self.batch.state, self.labels,
                                                qualities=qualities, replaying=self._replaying)

    @property
    def _replays(self) -> bool:
        """Whether the shown players get a true quality (a SimpleSoccer run, with a re-player)."""
        return self.qualities is not None and self._shown is not None and self.replayable(self._shown[0])

    def player_qualities(self) -> list[TrueQuality | None] | None:
        """The shown players' true quality, by rank (None: not re-played, the budget spent); None until answered."""
        return self._player_qualities

    def _replay_shown(self) -> None:
        """Ask for the shown players' true quality: it arrives on the re-play thread, is shown next frame."""
        self._player_qualities, self._replaying = None, self._replays
        if not self._replaying:
            return
        shown = self._shown

        def arrived(qualities: list[TrueQuality | None]) -> None:
            with self._pending_lock:
                self._arrived = (shown, qualities)

        self.qualities.request(shown[0], self.game, [p.rulebase for p in self._players], arrived)

    def _rebuild(self, run_id: int, generation: int, players: Sequence["SampledPlayer"]) -> None:
        shown = list(players)[: style.POPULATION_GRID[0] * style.POPULATION_GRID[1]]
        seed = self.start_seed()  # one start for all, so the players are compared fairly
        if self._shown is None or self._shown[0] != run_id:  # a run's settings do not change while it runs
            self.game = self.game_of_run(run_id)
        self.batch = GameBatch([p.rulebase for p in shown], [seed] * len(shown), self.game, self.vocabulary)
        self.labels = [f"#{rank} · {player.fitness:.2f}" for rank, player in enumerate(shown, start=1)]
        self._shown = (run_id, generation, len(shown), seed)
        self._players = shown
        self._replay_shown()

    def _show_caption(self, ended: tuple[int, str] | None) -> None:
        run_id, generation, count, seed = self._shown
        status = ended[1] if ended is not None and ended[0] == run_id else None
        if (self._shown, status) == self._caption_key:
            return
        self._caption_key = (self._shown, status)
        replayed = ""
        if self._replays:
            starts = self.qualities.starts
            done = sum(q is not None for q in self._player_qualities or ())
            replayed = (f" Under each, its fitness re-played on the same {starts} fresh starts as every run's best "
                        "(mean ± spread), best-ranked first" + ("" if self.qualities.share is None else
                                                                 f" within {self.qualities.share:.0%} of the time")
                        + ": "
                        + ("being re-played." if self._replaying else f"{done} of {count} re-played."))
        when = (f"; the run {escape(status)} after this generation" if status is not None
                else f" while generation {generation + 1} is evaluated")
        self.caption.content = (
            f'<div class="population-caption" data-run="{run_id}" data-generation="{generation}" '
            f'data-ended="{str(status is not None).lower()}" data-replaying="{str(self._replaying).lower()}" '
            f'style="{style.FONT}; font-size:{style.FONT_SIZE}px">'
            f"Run #{run_id}, generation {generation}: its {count} best players (rank · fitness), all from the "
            f"start of seed {seed} in the run's game ({escape(rules_summary(self.game))}), played together by "
            f"the batched engine{when}.{replayed}</div>"
        )
