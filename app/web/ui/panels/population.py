"""Population view: a grid of small pitches, all played at once by the batched engine (one GameBatch,
one pymunk Space). While this tab's evolution runs, it shows the latest generation's best players
(the RunManager samples them as each generation finishes), all from the same start so the class
compares them fairly, live while the next generation is being evaluated; after the run, its last. Under
each, its true quality once known: the player re-played on the common fresh starts (app/runs/true_quality.py),
by `PlayerQualities` (player_qualities.py) on a thread of its own, never on a tab's frame loop: the best first
within a share of the time, and the whole grid when the user presses "Measure these 12 on 20 fresh starts". The
caption, not every pitch, says how many are not re-played."""

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
) -> str:
    """Small pitches in a grid of `columns`, game g where observation[g] saw it (state: the games' score and
    whether and why each ended); with `qualities`, under each its player's true quality (None: not known yet,
    an empty line: the caption says how many)."""
    cells = "".join(
        _mini_pitch(geometry, observation, g, int(state.goals[g]), END_REASONS[state.end_reason[g]] if state.done[g]
                    else None, labels[g], "" if qualities is None else _quality_line(qualities[g]))
        for g in range(len(labels))
    )
    return (
        f'<div class="population" data-games="{len(labels)}" style="{style.FONT}; display:grid; '
        f'grid-template-columns:repeat({columns}, 1fr); gap:6px">{cells}</div>'
    )


def _quality_line(quality: TrueQuality | None) -> str:
    """The player's re-played fitness (mean ± spread) under its pitch, in the label's type; until it is known an
    empty line of the same height, so the grid does not jump when it arrives."""
    text = "&nbsp;" if quality is None else f"re-played {quality.fitness:.2f} ± {quality.fitness_std:.2f}"
    value = "" if quality is None else f"{quality.fitness:.6f}"
    return (f'<div class="replayed" data-replayed="{value}" style="font-size:{style.SMALL_FONT_SIZE + 1}px; '
            f'color:{style.INK}">{text}</div>')


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
        self.replay_button = gui.add_button("Measure these players", visible=False)  # never "play": tests find Play
        self.replay_button.on_click(lambda _: self.ask_replay())
        self.grid = gui.add_html(
            f'<div style="{style.FONT}; color:{style.MUTED}; font-size:{style.FONT_SIZE}px">{escape(EMPTY_TEXT)}</div>'
        )
        self.batch: GameBatch | None = None
        self.labels: list[str] = []
        # Set from the run's thread, picked up by the session loop: (run id, generation, its players),
        # and the run that ended with how it ended.
        self._pending: tuple[int, int, Sequence["SampledPlayer"]] | None = None
        self._ended: tuple[int, str] | None = None
        self._replay_asked = False  # set by the button's thread
        self._pending_lock = threading.Lock()
        self._shown: tuple[int, int, int, int] | None = None  # run id, generation, players, seed
        self._players: Sequence["SampledPlayer"] = ()
        self._outstanding: list[tuple[tuple, bool]] = []  # re-plays asked and not answered: (shown, everyone)
        self._player_qualities: list[TrueQuality | None] | None = None  # the shown players', once answered
        self._arrived: list[tuple[tuple, bool]] = []  # answered on the re-play thread, not picked up yet
        self._caption_key: tuple | None = None
        self._measure: tuple[str, bool] | None = None  # the button's label and disabled, while shown
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

    def ask_replay(self) -> None:
        """The button: the next frame asks for every shown player's true quality (off the frame loop)."""
        with self._pending_lock:
            self._replay_asked = True

    def advance(self, ticks: int) -> None:
        """Called by the session loop (under its lock) with the ticks the main pitch advanced."""
        with self._pending_lock:
            pending, self._pending = self._pending, None
            arrived, self._arrived = self._arrived, []
            asked, self._replay_asked = self._replay_asked, False
            ended = self._ended
        if pending is not None:
            self._rebuild(*pending)
        if arrived:
            self._answered(arrived)
        if asked and self._replays and not self._replaying_all:
            self._replay_shown(everyone=True)
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
                                                qualities=qualities)

    @property
    def _replays(self) -> bool:
        """Whether the shown players get a true quality (a SimpleSoccer run, with a re-player)."""
        return self.qualities is not None and self._shown is not None and self.replayable(self._shown[0])

    @property
    def _replaying(self) -> bool:
        """A re-play of the shown players is under way."""
        return any(shown == self._shown for shown, _ in self._outstanding)

    @property
    def _replaying_all(self) -> bool:
        """A re-play the button asked for is under way (of these players, or of a generation shown before)."""
        return any(everyone for _, everyone in self._outstanding)

    def button_state(self) -> tuple[str, bool] | None:
        """The button's label and whether it is disabled, None while hidden (the projector view shows it too)."""
        return self._measure

    def player_qualities(self) -> list[TrueQuality | None] | None:
        """The shown players' true quality, by rank (None: not re-played yet); None until first answered."""
        return self._player_qualities

    def _replay_shown(self, everyone: bool = False) -> None:
        """Ask for the shown players' true quality (`everyone`: all of them, else the share of the time pays
        for): it arrives on the re-play thread, is shown next frame."""
        shown = self._shown
        self._outstanding.append((shown, everyone))

        def arrived(_: list[TrueQuality | None]) -> None:
            with self._pending_lock:
                self._arrived.append((shown, everyone))

        self.qualities.request(shown[0], self.game, [p.rulebase for p in self._players], arrived, everyone)

    def _answered(self, arrived: list[tuple[tuple, bool]]) -> None:
        """Re-plays answered: the shown players' figures are the ones known now (an elite's from a generation
        before, or a generation the button asked for that the grid has moved on from)."""
        for answer in arrived:
            self._outstanding.remove(answer)
        if self._player_qualities is not None or any(shown == self._shown for shown, _ in arrived):
            self._player_qualities = self.qualities.known(self._shown[0], [p.rulebase for p in self._players])
        self._caption_key = None

    def _rebuild(self, run_id: int, generation: int, players: Sequence["SampledPlayer"]) -> None:
        shown = list(players)[: style.POPULATION_GRID[0] * style.POPULATION_GRID[1]]
        seed = self.start_seed()  # one start for all, so the players are compared fairly
        if self._shown is None or self._shown[0] != run_id:  # a run's settings do not change while it runs
            self.game = self.game_of_run(run_id)
        self.batch = GameBatch([p.rulebase for p in shown], [seed] * len(shown), self.game, self.vocabulary)
        self.labels = [f"#{rank} · {player.fitness:.2f}" for rank, player in enumerate(shown, start=1)]
        self._shown = (run_id, generation, len(shown), seed)
        self._players = shown
        self._player_qualities = None
        if self._replays:
            self._replay_shown()

    def _show_caption(self, ended: tuple[int, str] | None) -> None:
        run_id, generation, count, seed = self._shown
        status = ended[1] if ended is not None and ended[0] == run_id else None
        done = sum(q is not None for q in self._player_qualities or ())
        key = (self._shown, status, done, self._replaying, self._replaying_all)
        if key == self._caption_key:
            return
        self._caption_key = key
        when = (f"; the run {escape(status)} after this generation" if status is not None
                else f" while generation {generation + 1} is evaluated")
        self.caption.content = (
            f'<div class="population-caption" data-run="{run_id}" data-generation="{generation}" '
            f'data-ended="{str(status is not None).lower()}" data-replaying="{str(self._replaying).lower()}" '
            f'data-replayed="{done}" style="{style.FONT}; font-size:{style.SMALL_FONT_SIZE + 1}px; '
            f'color:{style.INK}">'
            f"Run #{run_id}, generation {generation}: its {count} best players (rank · fitness), all from the start "
            f"of seed {seed} in the run's game ({escape(rules_summary(self.game))}){when}."
            f"{self._quality_sentence(count, done)}</div>"
        )
        self._show_button(count, done)

    def _quality_sentence(self, count: int, done: int) -> str:
        """What the line under each pitch is, and how many players have one: said once, here."""
        if not self._replays:
            return ""
        said = (f'<div style="margin-top:2px">Under each pitch: its fitness re-played on the '
                f"same {self.qualities.starts} fresh starts as every run's best (mean ± spread)")
        if self._replaying_all:
            return said + f"; re-playing all {count}…</div>"
        if done == count:
            return said + ".</div>"
        so_far = "re-playing the best" if self._replaying and done == 0 else f"{done} of {count} so far"
        return said + f". {so_far}; the button measures the rest ({self._cost(count - done)}).</div>"

    def _cost(self, players: int) -> str:
        """e.g. '220 games, about 2.4 s': what re-playing `players` costs, measured by the last re-play."""
        seconds = self.qualities.seconds_for(players)
        took = "" if seconds is None else f", about {max(seconds, 0.1):.1f} s"
        return f"{players * self.qualities.starts} games{took}"

    def _show_button(self, count: int, done: int) -> None:
        """'Measure these 12 on 20 fresh starts', with its cost; pressed once at a time, gone when all are known."""
        button = self.replay_button
        button.visible = self._replays and done < count
        if not button.visible:
            self._measure = None
            return
        button.label = f"Measure these {count} on {self.qualities.starts} fresh starts"
        button.hint = (f"{self._cost(count - done)} on this machine, on a thread of their own: the pitches go on "
                       "meanwhile. A player re-played before is not re-played again.")
        button.disabled = self._replaying_all
        self._measure = (button.label, button.disabled)
