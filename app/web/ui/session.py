"""One browser tab: its own pitch, game, rulebase and editor, and the loop that plays the game in real
time (times the speed), sending each tick as it is played, at most FRAME_RATE times a second (fewer when many
tabs share the server: frame_share.py).

Every control callback and the play loop take the session's lock, so a click never sees a half-made
tick. Evolution runs elsewhere (the RunManager's threads); the session only listens.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

import viser

from soccer_lab.app.web.access import LOCAL, ScopedRuns, ScopedStore, Visitor
from soccer_lab.app.web.pitch_link import LINK_PARAMETER, LinkError, PitchLink, decode_link
from soccer_lab.app.rule_inspection import SIMPLIFY_PLAYS, checked_cost, rule_usage, simplification
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.number_field import FieldError
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.game import Game
from soccer_lab.app.web.ui.layout import Layout
from soccer_lab.app.web.ui.match_game import COLOURS, LETTERS, MatchGame, hex_colour
from soccer_lab.app.web.ui.panels.breeding import BreedingPanel
from soccer_lab.app.web.ui.panels.classroom import ClassPanel
from soccer_lab.app.web.ui.panels.editor import EditorPanel
from soccer_lab.app.web.ui.panels.evolve import EvolvePanel
from soccer_lab.app.web.ui.panels.inference import InferencePanel
from soccer_lab.app.web.ui.panels.knockout import KnockoutPanel
from soccer_lab.app.web.ui.panels.library import LibraryPanel
from soccer_lab.app.web.ui.panels.lineage import LineagePanel
from soccer_lab.app.web.ui.panels.match import MatchPanel
from soccer_lab.app.web.ui.panels.play import PlayControls
from soccer_lab.app.web.ui.panels.policy_view import PolicyPanel
from soccer_lab.app.web.ui.panels.population import PopulationPanel
from soccer_lab.app.runs.environments import SIMPLE
from soccer_lab.app.runs.outputs import best_of_run
from soccer_lab.app.store import NotFound
from soccer_lab.app.web.ui.pitch import PitchGeometry, PitchView
from soccer_lab.app.web.ui.projector import ProjectorView
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig

if TYPE_CHECKING:
    from soccer_lab.app.web.classroom.tournament import Tournament

log = logging.getLogger(__name__)
MAX_CATCH_UP = 0.25  # seconds of play made up at most after a stall (a busy machine): no bursts
DUE_EARLY = 0.02  # of a tick: a wake-up this early still plays it, not a frame later
IDLE_WAKE = 0.1  # seconds: paused or slow, the loop still looks for a finished generation this often
# A new tab: the pitch first; once the browser has taken it in (at most PITCH_SEEN_WAIT seconds) the Play tab
# (the score and tick counter, the controls) and the game plays; the other panels come PANELS_AFTER seconds
# of play later (docs/design.md, "First paint": a browser without a GPU spends seconds laying panels out).
PITCH_SEEN_WAIT = 2.0
PANELS_AFTER = 0.75


class Session:
    """`visitor`: whose session it is (classroom mode; LOCAL otherwise), what its panels may see and change.
    `origin`: the page's origin, for links to this pitch; `link`: the token of the pitch link the tab was
    opened with (app/web/pitch_link.py), or None. `tournament`: the class's (classroom mode), for the Class tab."""

    def __init__(self, client: viser.ClientHandle, context: UiContext, layout: Layout,
                 connected: Callable[[], bool], *, visitor: Visitor = LOCAL, origin: str | None = None,
                 link: str | None = None, tournament: Tournament | None = None):
        self.client = client
        self.context = context
        self.layout = layout
        self.visitor = visitor
        self.store = ScopedStore(context.store, visitor)
        self.runs = ScopedRuns(context.runs, visitor)
        self.origin = origin
        self.tournament = tournament
        self._connected = connected  # whether the tab is still open
        self.lock = threading.RLock()
        # one rule usage or simplification at a time per tab: each costs seconds of a thread viser's callbacks
        # share with every tab, so clicking again while one plays must not queue more
        self._inspecting = threading.Lock()
        self.playing = True  # the first minute: the demo player is already playing
        self._tick_budget = 0.0
        self._closed = threading.Event()
        self._pitch_seen = threading.Event()
        self.ready = threading.Event()  # every panel is built (the game plays from the Play tab's)
        self.skills: str | None = None  # the skill set chosen on this tab (None: the app's)
        self.pitch_run: int | None = None  # the run the pitch's player came from (None: a saved rulebase, ...)
        self._ticks_per_second = 1.0 / context.game.world.tick_seconds  # at 1x speed
        self.game: Game | MatchGame = self.first_game(context)  # a MatchGame while a match is watched
        self.link_problem: str | None = None  # why the link the tab was opened with was not played
        self.opened_link = self._open_link(link) if link is not None else None
        self._show_pitch()
        self._thread = threading.Thread(target=self._loop, name=f"ui-session-{client.client_id}", daemon=True)
        self._thread.start()

    @staticmethod
    def first_game(context: UiContext) -> Game:
        """Every tab's game as it opens: the demo player from the first seed."""
        return Game(context, context.demo_rulebase(), context.demo_name, seed=style.DEFAULT_SEED)

    def _open_link(self, token: str) -> PitchLink | None:
        """The linked pitch as it was: its rules, game and seed, played to its tick (the same game bit for bit).
        A link that cannot be opened leaves the demo playing and one line saying why (shown in the Play tab)."""
        try:
            link = decode_link(token)
            game = Game(self.context, link.rulebase(self.context.vocabulary), link.name, link.seed,
                        link.game_config(self.context.game))
        except LinkError as exc:
            self.link_problem = f"This link could not be opened: {exc}. Playing the demo instead."
            return None
        while game.state.tick < link.tick and not game.done:
            game.step()
        self.game = game
        self.skills = game.config.skills  # the tab goes on with the link's skill set
        self.playing = not link.paused
        return link

    def pitch_link(self) -> str:
        """A link to this pitch as it is now (rules, seed, game rules, speed, tick, paused)."""
        with self.lock:
            game = self.game
            if isinstance(game, MatchGame):
                return MATCH_NOT_LINKED
            link = PitchLink.of(format_rulebase(game.rulebase, self.context.vocabulary), game.name, game.seed,
                                int(game.state.tick), float(self.controls.speed.value), not self.playing,
                                game.config, self.context.game)
        return f"{self.origin or ''}/ui/?{LINK_PARAMETER}={link.token()}"

    # ---- layout ---------------------------------------------------------------------------
    # The pitch first, the panels after (docs/design.md, "First paint"): a browser without a GPU
    # spends seconds laying out the panels, and would draw the pitch only after them.
    def _show_pitch(self) -> None:
        self.projector: ProjectorView | None = None  # built with the Play tab
        self.pitch = PitchView(self.client.scene, PitchGeometry.from_world(self.context.game.world))
        self.pitch.show(self.game.frame())
        self._aspect = self.client.camera.aspect

        @self.client.camera.on_update
        def _(camera: viser.CameraHandle) -> None:
            # The browser answers the camera sent below once it has taken in the pitch. Refit when the
            # canvas changes shape (a window resized), not when the user pans.
            self._pitch_seen.set()
            if abs(camera.aspect - self._aspect) > 0.01:
                self._aspect = camera.aspect
                if self.projector is not None:
                    self.projector.canvas_changed()
                else:
                    self.pitch.fit_camera(camera)

        self.pitch.fit_camera(self.client.camera)
        self.client.flush()

    def _build_play_tab(self) -> None:
        """The score, the tick counter and the play controls: all a tab needs to play."""
        gui = self.client.gui
        self.projector = ProjectorView(self.client, self.pitch, self.layout.right_panel_id,
                                       on_leave=self.toggle_projector, on_toggle=self._render,
                                       on_watch=self.show_thinking_of,
                                       on_measure=lambda: self.population.ask_replay())
        # Tabs and buttons without icons: viser reads each icon from a 2 MB zip file the first time it
        # is used, seconds that the first visitor after a start would wait for.
        self._tabs = gui.add_tab_group()
        self._play_tab = self._tabs.add_tab("Play")
        with self._play_tab:
            self.controls = PlayControls(
                gui, on_play=self.set_playing, on_step=self.step_once, on_new_start=self.new_start,
                on_reset_view=self.projector.fit_camera, on_skills=self.set_skills,
                on_projector=self.toggle_projector, on_thinking=self.show_thinking_of,
                skills=self.game.config.skills, make_link=self.pitch_link, notice=self.link_problem,
            )
            if self.opened_link is not None:
                self.controls.speed.value = self.opened_link.speed
                self.controls.seed.value = self.opened_link.seed
        self._render()

    def _build_panels(self) -> None:
        """Every other panel, once the game plays."""
        gui, context, tabs = self.client.gui, self.context, self._tabs
        with self._play_tab, gui.add_folder("Match: two players"):
            self.match_panel = MatchPanel(gui, self.store, context.vocabulary,
                                          current=lambda: (self.game.rulebase, self.game.name),
                                          on_watch=self.watch_picked, tournament=self.tournament)
        with tabs.add_tab("Rules"):
            self.editor = EditorPanel(
                gui, context.vocabulary, self.store, (self.game.rulebase, self.game.name),
                on_apply=self.load_rulebase, on_example=self.play_player, on_saved=self._saved,
                simplify=self.simplify, best_of=self.best_of_pitch,
            )
        with tabs.add_tab("Evolve"):
            self.evolve = EvolvePanel(
                gui, self.runs, self.store, on_load=self.play_player,
                on_generation=lambda *finished: self.population.generation_finished(*finished),
                on_run_ended=lambda run_id, status: self.population.run_ended(run_id, status),
                on_runs_changed=self._runs_changed, api_url=context.api_url,
                viewer_problem=context.viewer_problem,
            )
        with tabs.add_tab("Library"):
            self.library = LibraryPanel(gui, self.store, self.runs, context.vocabulary, context.api_url,
                                        on_load=self.play_player, viewer_problem=context.viewer_problem)
        if self.tournament is not None:
            with tabs.add_tab("Class"):
                self.classroom = ClassPanel(gui, self.tournament, self.visitor, context.vocabulary,
                                            current=lambda: (self.game.rulebase, self.game.name),
                                            on_watch=self.watch_entry)
                self.knockout = KnockoutPanel(gui, self.tournament, self.visitor, context.vocabulary,
                                              on_watch=self.watch_match)
            with self.projector.class_tab():  # the round's table and "Watch this game" in the projector view too
                self.projector_class = ClassPanel(gui, self.tournament, self.visitor, context.vocabulary,
                                                  current=lambda: (self.game.rulebase, self.game.name),
                                                  on_watch=self.watch_entry)
            with self.projector.knockout_tab():  # the bracket in large type, any match watched from there too
                self.projector_knockout = KnockoutPanel(gui, self.tournament, self.visitor, context.vocabulary,
                                                        on_watch=self.watch_match, controls=False,
                                                        large=True)
        # The panels themselves (docked, sized, the right one's tabs) are the server's: see layout.py.
        with self.layout.right_tab("Inference"):
            self.inference = InferencePanel(gui, context.vocabulary, on_change=self.refresh,
                                            on_usage=self.measure_usage, world=context.game.world)
        with self.layout.right_tab("Policy map"):
            self.policy = PolicyPanel(gui, context.vocabulary, self.game.rulebase, self.game.view_half_angle,
                                      on_change=self.refresh)
        with self.layout.right_tab("Population"):
            self.population = PopulationPanel(gui, context.game.world, context.vocabulary,
                                              start_seed=lambda: self.game.seed, game_of_run=self.run_game,
                                              qualities=context.player_qualities, replayable=self.plays_simple_soccer)
        with self.layout.right_tab("Lineage"):
            self.lineage = LineagePanel(gui, self.store, context.vocabulary,
                                        population_shown=self.population.shown_players,
                                        current_run=lambda: self.evolve.run_id, on_load=self.play_player)
        with self.layout.right_tab("Breeding"):
            self.breeding = BreedingPanel(gui, self.store, context.vocabulary, context.game.world,
                                          start_seed=lambda: self.game.seed, game_of_run=self.run_game,
                                          app_game=context.game, demo=(context.demo_rulebase(), context.demo_name),
                                          current_run=lambda: self.evolve.run_id)
        self.ready.set()
        self._render()

    # ---- controls -------------------------------------------------------------------------
    def toggle_projector(self) -> None:
        with self.lock:
            self.projector.toggle()

    def watch_match(self, a: Rulebase, b: Rulebase, names: tuple[str, str], seed: int, config: GameConfig,
                    vocabulary: Vocabulary) -> None:
        """Play the match of A against B on this tab's pitch, from `seed`'s start, in `config`'s game (per half)
        and `vocabulary` (e.g. Vocabulary.with_opponent()): two halves, the sides swapped at half time, the same
        match `play_matches(a, b, [seed], config, vocabulary)` counts. The Play tab shows the score, the half
        and the tick, and the thinking switch (A / B) for the Inference panel; it plays at once. The entry point
        for any panel that lets a user watch a match (a class knockout's)."""
        self.pitch_run = None
        with self.lock:
            self.game = MatchGame(self.context, (a, b), names, seed, config, vocabulary)
            self.playing = True
            self._tick_budget = 0.0
            if self.projector is not None:  # the Play tab is built (a call before it waits for nothing)
                self.controls.seed.value = seed
                self.controls.show_skills(config.skills)
            self._show_watched()

    def watch_picked(self, a: Rulebase, b: Rulebase, names: tuple[str, str]) -> None:
        """The Match folder's two players, from the Seed field's start (the pitch's seed if it is not a number),
        in the app's game with this tab's skill set."""
        try:
            seed = int(self.controls.seed.value)
        except FieldError:
            seed = self.game.seed
        config = self.context.game.model_copy(update={"skills": self.skills or self.context.game.skills})
        self.watch_match(a, b, names, seed, config, self.context.vocabulary)

    def show_thinking_of(self, player: int) -> None:
        """In a match, the Inference panel, the membership degrees, the policy map and the rules editor show
        A's (0) or B's (1) thinking."""
        with self.lock:
            if not isinstance(self.game, MatchGame):
                return
            self.game.watch(player)
            self._show_watched()

    def _show_watched(self) -> None:
        if self.ready.is_set():
            self._show_rulebase(self.game.rulebase, self.game.name)
        elif self.projector is not None:
            self._render()

    def _saved(self) -> None:
        """A rulebase was saved: the lists that offer saved rulebases offer it."""
        self.library.refresh()
        self.match_panel.refresh()

    def set_playing(self, playing: bool) -> None:
        with self.lock:
            self.playing = playing
            self._tick_budget = 0.0

    def step_once(self) -> None:
        with self.lock:
            if self.game.done:
                self.game.restart(self.game.seed)
            if isinstance(self.game, MatchGame):
                self.game.skip_half_time()
            self.game.step()
            self._render()

    def new_start(self, seed: int) -> None:
        with self.lock:
            self.game.restart(seed)
            self._render()

    def set_skills(self, skills: str) -> None:
        """The same player from a new start of the same seed, with another skill set; it stays this tab's choice
        for the rulebases it puts on the pitch next."""
        with self.lock:
            self.skills = skills
            game = self.game
            config = game.config.model_copy(update={"skills": skills})
            if isinstance(game, MatchGame):  # the same match from its start, with the new skills
                self.game = MatchGame(self.context, game.players, game.names, game.seed, config, game.vocabulary)
                self.game.watch(game.watched)
            else:
                self.game = Game(self.context, game.rulebase, game.name, game.seed, config)
            self.controls.show_skills(skills)
            self._render()

    def load_rulebase(self, rulebase: Rulebase, name: str, *, restart: bool = False) -> None:
        """Put `rulebase` on the pitch in the same game's rules (the game goes on from where it is unless
        `restart`): the editor's rules. In a match, they play alone from the match's start."""
        with self.lock:
            if isinstance(self.game, MatchGame):
                self.game = Game(self.context, rulebase, name, self.game.seed, self.game.config)
                self._show_rulebase(rulebase, name)
                return
            self.game.set_rulebase(rulebase, name)
            if restart:
                self.game.restart(self.game.seed)
            self._show_rulebase(rulebase, name)

    def play_player(self, rulebase: Rulebase, name: str, run_id: int | None = None) -> None:
        """A new player on the pitch, from a new start of the same seed: a run's player in its run's game
        (run_game), a saved rulebase or example (`run_id` None) in the app's, with the tab's skill set."""
        if run_id is None:
            config = self.context.game.model_copy(update={"skills": self.skills or self.context.game.skills})
        else:
            config = self.run_game(run_id)
        self.pitch_run = run_id
        with self.lock:
            if isinstance(self.game, Game) and config == self.game.config:
                self.game.set_rulebase(rulebase, name)
                self.game.restart(self.game.seed)
            else:
                self.game = Game(self.context, rulebase, name, self.game.seed, config)
            self._show_rulebase(rulebase, name)
            self.controls.show_skills(self.game.config.skills)

    def watch_entry(self, rulebase: Rulebase, name: str, seed: int, config: GameConfig) -> None:
        """A tournament entry's game: its rules from a round's start, in the round's game."""
        self.pitch_run = None
        with self.lock:
            self.game = Game(self.context, rulebase, name, seed, config)
            self.controls.seed.value = seed
            self._show_rulebase(rulebase, name)

    def _runs_changed(self) -> None:
        """A run started or ended: the panels that list runs list it (a panel built later lists them then)."""
        if not self.ready.is_set():
            return
        self.library.refresh()
        self.lineage.refresh()
        self.breeding.refresh()
        self.match_panel.refresh()

    def best_of_pitch(self, rulebase: Rulebase) -> dict | None:
        """The figures of the run's best `rulebase` is, when the pitch's player came from that run and is its
        best so far (the library keeps them beside the saved rules); None otherwise."""
        if self.pitch_run is None:
            return None
        try:
            if parse_rulebase(self.store.best_individual(self.pitch_run).rules, self.context.vocabulary) != rulebase:
                return None
            return best_of_run(self.store, self.pitch_run)
        except (NotFound, RuleSyntaxError):
            return None

    def plays_simple_soccer(self, run_id: int) -> bool:
        """Whether a run evaluates in SimpleSoccer (its players' true quality is SimpleSoccer's, not rcssserver's)."""
        try:
            return self.store.get_run(run_id).config.get("env", SIMPLE) == SIMPLE
        except NotFound:
            return False

    def run_game(self, run_id: int) -> GameConfig:
        """The game a run's players play in on this tab: the run's rules (skills, noise, kick counting,
        limits, fitness) in the app's world, which the pitch is drawn to; the app's game when the stored
        settings no longer validate."""
        try:
            game = self.runs.pitch_game(run_id)
        except (NotFound, ValueError):
            game = self.context.game
        return game.model_copy(update={"world": self.context.game.world})

    def _show_rulebase(self, rulebase: Rulebase, name: str) -> None:
        with self.lock:
            self.editor.show_rulebase(rulebase, name)
            self.inference.show_usage(None)  # it counted the rules of the previous rulebase
            self.policy.show_rulebase(rulebase)
            self._render()

    def measure_usage(self, games: int) -> None:
        """Rule usage over `games` games from the pitch's seed, shown beside the rules. The games are
        played outside the lock, so the pitch goes on meanwhile."""
        with self.lock:
            rulebase, seed, config = self.game.rulebase, self.game.seed, self.game.config
        try:
            checked_cost(rulebase, games, config.max_ticks)
            with self._inspection():
                usage = rule_usage(rulebase, self.context.vocabulary, games, seed, config)
        except ValueError as exc:
            self.inference.say_usage(f"Usage not measured: {exc}", error=True)
            return
        with self.lock:
            if self.game.rulebase is not rulebase:  # it counted rules no longer on the pitch
                self.inference.say_usage("Usage not shown: the rules on the pitch changed while it was measured. "
                                         "Press Measure rule usage again.", error=True)
                return
            self.inference.show_usage(usage)
            self._render()

    def simplify(self, rulebase: Rulebase, games: int):
        """The rules simplified: exact steps, then checked on `games` games from the pitch's seed."""
        with self.lock:
            seed, config = self.game.seed, self.game.config
        checked_cost(rulebase, games, config.max_ticks, SIMPLIFY_PLAYS)  # ValueError naming the limit
        with self._inspection():
            return simplification(rulebase, self.context.vocabulary, games, seed, config)

    @contextmanager
    def _inspection(self) -> Iterator[None]:
        """Holds this tab's one rule usage or simplification; ValueError while another one plays."""
        if not self._inspecting.acquire(blocking=False):
            raise ValueError("this tab is still measuring rule usage or simplifying: wait for it to finish")
        try:
            yield
        finally:
            self._inspecting.release()

    def refresh(self) -> None:
        with self.lock:
            self._render()

    def close(self) -> None:
        """The tab is gone: stop drawing and listening (quick: called from viser's event loop)."""
        self._closed.set()
        if self.ready.is_set():  # else the loop, having built the panels, sees the tab closed
            self._close_panels()

    def _close_panels(self) -> None:
        self.evolve.close()
        self.match_panel.close()
        if self.tournament is not None:
            self.classroom.close()
            self.projector_class.close()
            self.knockout.close()
            self.projector_knockout.close()

    def join(self, timeout: float) -> bool:
        """Wait for the loop to end after close(); whether it has."""
        self._thread.join(timeout)
        return not self._thread.is_alive()

    # ---- the loop -------------------------------------------------------------------------
    def _loop(self) -> None:
        self._pitch_seen.wait(PITCH_SEEN_WAIT)
        if not self._built(self._build_play_tab):
            return
        last = time.perf_counter()
        panels_due = last + PANELS_AFTER
        while not self._closed.is_set():
            now = time.perf_counter()
            if not self.ready.is_set() and now >= panels_due and not self._built(self._build_panels):
                return
            try:
                with self.lock:
                    if self._closed.is_set():
                        break
                    # a tab drawing few frames (many tabs open) plays a frame's ticks at each
                    self._advance(min(now - last, max(MAX_CATCH_UP, 2.0 / self.context.frames.rate)))
            except Exception:  # a broken frame must not kill the tab's loop
                if not self._connected():  # the tab closed under us: viser removed its panels first
                    break
                log.exception("session frame failed")
            last = now
            self._closed.wait(self._until_next_tick())

    def _built(self, build: Callable[[], None]) -> bool:
        """Build panels under the lock; False when the tab closed meanwhile (and its loop should end)."""
        with self.lock:
            try:
                build()
            except Exception:
                if self._connected():
                    raise
                return False  # the tab closed while its panels were built
        if self._closed.is_set():
            if self.ready.is_set():
                self._close_panels()
            return False
        return True

    def _advance(self, elapsed: float) -> None:
        ticks = self._due_ticks(elapsed) if self.playing else 0
        if self.ready.is_set():
            self.population.advance(ticks)
            self.breeding.advance(ticks)
        if ticks == 0:
            return
        if self.game.done:  # the end stays on screen, with its reason, until the teacher starts the next game
            return
        # Up to the tab's frame rate (FRAME_RATE, less with many tabs open: frame_share.py), every tick goes
        # to the browser (a late wake-up sends two in a row); faster, each frame's last.
        each = self._tick_rate() <= self.context.frames.rate
        for _ in range(ticks):
            if self.game.done:
                break
            self.game.step()
            if each:
                self._render()
        if not each:
            self._render()

    def _tick_rate(self) -> float:
        return float(self.controls.speed.value) * self._ticks_per_second

    def _due_ticks(self, elapsed: float) -> int:
        """Ticks due after `elapsed` seconds of play, so the game runs at `speed` times real time."""
        self._tick_budget += elapsed * self._tick_rate()
        ticks = int(self._tick_budget + DUE_EARLY)
        self._tick_budget -= ticks
        return ticks

    def _until_next_tick(self) -> float:
        """Seconds to sleep: until the next tick is due, so each tick is sent (and drawn) on its own;
        never less than a frame (faster games send several ticks a frame), never more than IDLE_WAKE or a
        frame."""
        frame = 1.0 / self.context.frames.rate
        if not self.playing:
            return IDLE_WAKE
        due_in = (1.0 - DUE_EARLY - self._tick_budget) / self._tick_rate()
        return min(max(due_in, frame), max(IDLE_WAKE, frame))

    def _render(self) -> None:
        if self._closed.is_set():  # a control's callback may still arrive from a closed tab
            return
        game = self.game
        # One batch: the pitch, its label, the panels and the status line arrive together and show one tick
        # (in two, the panels showed a tick the pitch had not drawn yet: "dash 100" beside "Dribble: kick 8").
        match = isinstance(game, MatchGame)
        with self.client.atomic():
            self.controls.show_status(game.status_html())
            self.controls.show_match(match)
            self.projector.show(game)
            if self.ready.is_set():
                self.inference.show(game.inputs(), game.rule_texts, game.inference(), game.outcome_text(),
                                    game.outcome_refused(), tick=int(game.state.tick),
                                    whose=thinking_html(game) if match else "")
                self.projector.show_population(self.population.grid.content, self.population.button_state())
                self.policy.show_current(game.inputs())
            self.pitch.show(game.frame())


MATCH_NOT_LINKED = "A link opens one player's game: a match has no link yet (its players and seed are in the Play tab)."


def thinking_html(match: MatchGame) -> str:
    """The Inference panel's first line in a match: whose thinking it shows, in that player's colour."""
    p = match.watched
    return (f'<div class="inference-whose" data-watched="{LETTERS[p]}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE + 1}px; font-weight:700; color:{hex_colour(COLOURS[p])}">'
            f"Thinking of {LETTERS[p]}: {escape(match.names[p])}</div>")
