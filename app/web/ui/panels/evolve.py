"""Evolve panel: every GA parameter (the chapter's defaults), whom players are scored against (alone, as
in the chapter; matches against a fixed player; co-evolution against a hall of fame), start, stop,
generation progress, live best and mean fitness, and the best player so far loadable onto the pitch while
evolution goes on."""

from __future__ import annotations

import typing
from typing import Any, Callable, Sequence

import numpy as np
import viser
import viser.uplot

from soccer_lab.app.web.access import ScopedRuns, ScopedStore
from soccer_lab.app.runs.environments import RCSS, RCSS_WORKERS, default_workers
from soccer_lab.app.runs.outputs import run_replayed_note
from soccer_lab.app.runs.manager import RunEvent, RunStateError, SampledPlayer, describe_place
from soccer_lab.app.store import NotFound, RunStatus
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.number_field import FieldError, NumberField
from soccer_lab.app.web.ui.panels.diversity import DiversityPlot
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.web.ui.panels.viewer_link import run_viewer_link
from soccer_lab.app.web.validation import describe_problem, dotted
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.ga.config import SEED_BOUND, CoevolutionConfig, GAConfig
from soccer_lab.ga.state import GA, RANDOM_SEARCH
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.examples import DEMO, ORDER, example
from soccer_lab.soccer.rcss.servers import MAX_SERVERS

ALGORITHMS = {"GA": GA, "Random search": RANDOM_SEARCH}  # what the teacher picks -> the run's algorithm
SIMPLESOCCER, RCSSSERVER = "SimpleSoccer", "rcssserver"  # where evaluations play (rcss: servers the run starts)
ALONE, FIXED, COEVOLVE = "Alone (the chapter's)", "A fixed player", "Co-evolve (hall of fame)"  # whom it plays
LABELS = {  # what a teacher reads next to each field; fields missing here show their own name
    "population_size": "Population size",
    "max_generations": "Generations (max)",
    "max_length": "Chromosome length (max genes)",
    "consequent_probability": "P(gene is a consequent)",
    "crossover": "Crossover",
    "crossover_probability": "Crossover probability",
    "mutation_probability": "Mutation probability",
    "mutation_rate": "Mutation rate (per gene)",
    "selection": "Selection",
    "roulette_weighting": "Roulette weight (1-f linear, 1/f inverse)",
    "tournament_size": "Tournament size",
    "tournament_selector": "Tournament: P(better wins)",
    "elite_fraction": "Elite fraction",
    "target_fitness": "Target fitness (stop at or below)",
    "seed": "Run seed (empty: a new one each run)",  # not the pitch's Seed (Play tab)
    "workers": "Worker processes",
    "behaviour_seeds": "Behaviour seeds (count distinct behaviours; 0: off)",
    "skills": "Skills (strict: kicks only within reach; sighted: and sees the goal)",
    "noise": "Movement noise",
    "count_touches": "Body pushes count as kicks",
}
# The GameConfig choices the chapter leaves open; the rest are its rules.
GAME_FIELDS = ("skills", "noise", "count_touches")


def ga_fields() -> dict[str, Any]:
    """Field name -> pydantic FieldInfo of GAConfig, the one place the parameters and defaults live."""
    return dict(GAConfig.model_fields)


def game_fields() -> dict[str, Any]:
    """The GAME_FIELDS' pydantic FieldInfo of GameConfig (where their defaults live)."""
    return {name: GameConfig.model_fields[name] for name in GAME_FIELDS}


class EvolvePanel:
    """Starts and follows this tab's evolution. Generations are numbered from 0, the evaluated initial
    population, as everywhere else. Callbacks: `on_load(rulebase, name, run_id)` puts the best player so far
    on the pitch (in its run's game); `on_generation(run_id, generation, players)` hands each finished generation's best
    players on and `on_run_ended(run_id, status)` says the run is over (both from the run's thread);
    `on_runs_changed()` follows a run starting or ending."""

    def __init__(
        self,
        gui: viser.GuiApi,
        runs: ScopedRuns,
        store: ScopedStore,
        *,
        on_load: Callable[[Rulebase, str, int], None],
        on_generation: Callable[[int, int, Sequence[SampledPlayer]], None],
        on_run_ended: Callable[[int, RunStatus], None],
        on_runs_changed: Callable[[], None],
        api_url: str | None = None,
        viewer_problem: str | None = None,
    ):
        self.runs = runs
        self.api_url = api_url
        self.viewer_problem = viewer_problem  # why there is no rerun viewer to link to (None: there is)
        self.store = store
        self.on_load = on_load
        self.on_generation = on_generation
        self.on_run_ended = on_run_ended
        self.on_runs_changed = on_runs_changed
        self.run_id: int | None = None
        self.total_generations = int(GAConfig.model_fields["max_generations"].default)  # of the run on show
        self.generations: list[int] = []
        self.best: list[float] = []  # each generation's best (noisy: one game each), as the chapter's Figs. 9, 12
        self.best_so_far: list[float] = []  # the run's running minimum: what a class watches fall
        self.mean: list[float] = []
        self.inputs: dict[str, viser.GuiInputHandle | NumberField] = {}
        self.algorithm = gui.add_dropdown("Algorithm", tuple(ALGORITHMS), initial_value="GA")
        self.where = gui.add_dropdown("Play on", (SIMPLESOCCER, RCSSSERVER), initial_value=SIMPLESOCCER,
                                      hint="rcssserver: the run starts its own servers (serve --rcssserver PATH)")
        self.servers = NumberField(gui, "rcssservers", 1, minimum=1, maximum=MAX_SERVERS, integer=True,
                                   hint="Servers the run starts, trials spread over them")
        self.servers.visible = False  # only for runs on rcssserver
        self.opponent = gui.add_dropdown("Opponent", (ALONE, FIXED, COEVOLVE), initial_value=ALONE,
                                         hint="Alone: the chapter's games. Otherwise every evaluation is matches: "
                                              "against one player, or against earlier generations' bests")
        self.opponent_player = gui.add_dropdown("Opponent player", ORDER, initial_value=DEMO,
                                                hint="An example player; co-evolving, generation 0's opponent, "
                                                     "kept in the hall of fame")
        hall = CoevolutionConfig.model_fields
        self.hall_size = NumberField.for_field(gui, "Hall of fame size", hall["hall_size"],
                                               hint=hall["hall_size"].description)
        self.hall_sample = NumberField.for_field(gui, "Opponents per generation", hall["hall_sample"],
                                                 hint=hall["hall_sample"].description)
        self._show_opponent_fields()
        self.name = gui.add_text("Run name (empty: from the settings)", initial_value="")
        self.game_inputs: dict[str, viser.GuiInputHandle | NumberField] = {}
        with gui.add_folder("GA parameters (chapter's Table 2)", expand_by_default=False):
            for name, field in ga_fields().items():
                self.inputs[name] = self._input(gui, name, field)
        with gui.add_folder("Game options", expand_by_default=False):
            for name, field in game_fields().items():
                self.game_inputs[name] = self._input(gui, name, field)
        buttons = gui.add_button_group("Evolution", ("Start", "Stop"))
        self.progress = gui.add_progress_bar(0.0)
        self.within = gui.add_html("")  # the generation in progress: players evaluated of the population
        self.status = gui.add_html(self._status_html("Not started. Press Start: the chapter's defaults are set."))
        self.seed_line = gui.add_html("")  # the run's seed: typed into Run seed, it plays the same run again
        self.viewer = gui.add_html("")  # the run on show, in rerun's viewer
        self.plot = gui.add_uplot(
            data=self._plot_data(),
            series=self._plot_series(),
            scales=self._plot_scales(),
            # The legend names the latest values itself (uPlot's live legend shows "--" until hovered).
            legend=viser.uplot.Legend(live=False),
            title=self._plot_title(),
            aspect=1.4,
            padding=style.PLOT_PADDING,
            axes=(viser.uplot.Axis(incrs=style.GENERATION_STEPS), viser.uplot.Axis()),
        )
        self.diversity = DiversityPlot(gui)
        self.load_best = gui.add_button("Load best so far onto the pitch", disabled=True)
        self._remove_listener = self.runs.add_listener(self._on_event)

        @buttons.on_click
        def _(event: viser.GuiEvent) -> None:
            self.start() if event.target.value == "Start" else self.stop()

        @self.where.on_update
        def _(_: viser.GuiEvent) -> None:
            self.servers.visible = self.where.value == RCSSSERVER
            self._show_opponent_fields()

        @self.opponent.on_update
        def _(_: viser.GuiEvent) -> None:
            self._show_opponent_fields()

        @self.load_best.on_click
        def _(_: viser.GuiEvent) -> None:
            self.load_best_so_far()

    def _show_opponent_fields(self) -> None:
        """Matches are played in SimpleSoccer: the opponent's fields show for the choice that uses them."""
        simple = self.where.value == SIMPLESOCCER
        self.opponent.visible = simple
        self.opponent_player.visible = simple and self.opponent.value != ALONE
        self.hall_size.visible = self.hall_sample.visible = simple and self.opponent.value == COEVOLVE

    def opponent_settings(self) -> dict[str, Any]:
        """The run's opponent and co-evolution settings for the choice shown ({} when it plays alone);
        FieldError for a hall field that holds no usable number."""
        if self.where.value != SIMPLESOCCER or self.opponent.value == ALONE:
            return {}
        chosen = self.opponent_player.value
        if self.opponent.value == FIXED:
            return {"opponent": example(chosen).text}
        coevolve = {"hall_size": int(self.hall_size.value), "hall_sample": int(self.hall_sample.value)}
        return {"coevolve": coevolve, **({"opponent": example(chosen).text} if chosen != DEMO else {})}

    @staticmethod
    def _input(gui: viser.GuiApi, name: str, field: Any) -> viser.GuiInputHandle | NumberField:
        label = LABELS.get(name, name)
        default = field.default
        choices = typing.get_args(field.annotation) if typing.get_origin(field.annotation) is typing.Literal else ()
        if choices:
            return gui.add_dropdown(label, tuple(choices), initial_value=default)
        if isinstance(default, bool):
            return gui.add_checkbox(label, default)
        if name == "seed":  # empty by default: every run, every pupil's, breeds its own players
            hint = "Empty: a new random seed each run (shown once it starts). The same seed replays a run bit for bit."
            return NumberField(gui, label, None, minimum=0, maximum=SEED_BOUND, open_maximum=True, integer=True,
                               hint=hint, optional=True)
        number = NumberField.for_field(gui, label, field, hint=field.description)  # with the field's bounds
        if name == "workers":
            number.value = default_workers()  # as the CLI: every core
        return number

    def config(self) -> dict[str, Any]:
        """The GA parameters shown (no seed when Run seed is empty: the run draws one); FieldError naming a
        field that holds no usable number."""
        values = {name: handle.value for name, handle in self.inputs.items()}
        return {name: value for name, value in values.items() if value is not None}

    def game_config(self) -> dict[str, Any]:
        return {name: handle.value for name, handle in self.game_inputs.items()}

    def _status_html(self, text: str, *, error: bool = False, kind: str = "evolve-status") -> str:
        colour = style.ERROR if error else style.INK
        return (
            f'<div class="{kind}" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{colour}">{escape(text)}</div>'
        )

    # ---- actions ----------------------------------------------------------------------------
    def start(self) -> None:
        try:
            ga, game, where = self.config(), self.game_config(), self.opponent_settings()
            if self.where.value == RCSSSERVER:  # the GA evaluates in this process, trials over the servers
                where = {"env": RCSS, "start_servers": int(self.servers.value), "trial": {"skills": game["skills"]}}
                ga, game = {**ga, "workers": RCSS_WORKERS}, None  # the server has its own noise and kick count
            record = self.runs.start(self.name.value.strip() or None, ga=ga, game=game,
                                     algorithm=ALGORITHMS[self.algorithm.value], **where)
        except (ValueError, RunStateError) as exc:  # pydantic's ValidationError and FieldError are ValueErrors
            self.status.content = self._status_html(f"Not started: {_first_line(exc)}", error=True)
            return
        self.run_id = record.id
        self.total_generations = int(ga["max_generations"])
        self.generations, self.best, self.best_so_far, self.mean = [], [], [], []
        self.diversity.reset(int(ga["population_size"]), int(ga["max_generations"]), int(ga["behaviour_seeds"]))
        self.progress.value = 0.0
        self.progress.animated = True
        self.plot.scales = self._plot_scales()
        self._redraw_plot()
        self._show_started(record.id, record.status)
        seed = record.config["ga"]["seed"]
        self.seed_line.content = self._status_html(
            f"Run #{record.id}'s seed: {seed} (type it in Run seed to breed the same players again)", kind="evolve-seed")
        self.on_runs_changed()

    def _show_started(self, run_id: int, status: RunStatus) -> None:
        if status is RunStatus.QUEUED:
            place = describe_place(self.runs.queue_place(run_id))
            self.status.content = self._status_html(
                f"Run #{run_id} is queued: {place}. Every core is busy with the class's runs; Stop leaves the "
                "queue.", kind="evolve-status evolve-queued")
            self.viewer.content = ""  # no recording until it starts: the viewer would open on a 404
        else:
            self.status.content = self._status_html(f"Run #{run_id} started: evaluating generation 0 …")
            self.viewer.content = run_viewer_link(self.api_url, run_id, self.viewer_problem)

    def stop(self) -> None:
        if self.run_id is None or not self.runs.is_pending(self.run_id):
            self.status.content = self._status_html("No evolution of this tab is running.", error=True)
            return
        self.status.content = self._status_html(f"Stopping run #{self.run_id} …")
        try:
            self.runs.stop(self.run_id, wait=0.0)
        except (RunStateError, NotFound) as exc:
            self.status.content = self._status_html(str(exc), error=True)

    def load_best_so_far(self) -> None:
        if self.run_id is None:
            return
        try:
            rulebase = self.runs.best_rulebase(self.run_id)
            best = self.store.best_individual(self.run_id)
        except (NotFound, ValueError) as exc:
            self.status.content = self._status_html(f"No best player yet: {exc}", error=True)
            return
        quality = run_replayed_note(self.store, self.run_id, best.fitness)
        name = f"run #{self.run_id} best (gen {best.generation}, fitness {best.fitness:.3f}{quality})"
        self.on_load(rulebase, name, self.run_id)

    def close(self) -> None:
        self._remove_listener()

    # ---- live progress (called from the run's thread) -----------------------------------------
    def _on_event(self, event: RunEvent) -> None:
        if event.run_id != self.run_id:
            return
        total = self.total_generations  # generations 0 .. total - 1
        if event.progress is not None:
            self.within.content = self._status_html(
                f"Generation {event.progress.generation}: {event.progress.evaluated:,} of "
                f"{event.progress.population:,} players evaluated", kind="evolve-within")
        elif event.stats is not None:
            stats = event.stats
            generation = int(stats["generation"])
            self.generations.append(generation)
            self.best.append(float(stats["best"]))
            self.best_so_far.append(min(self.best_so_far[-1:] + [float(stats["best"])]))
            self.mean.append(float(stats["mean"]))
            self._redraw_plot()
            self.diversity.add(stats)
            self.on_generation(event.run_id, generation, event.players)
            self.progress.value = min(100.0, 100.0 * (generation + 1) / total)
            self.load_best.disabled = False
            self.within.content = ""  # until the next generation's first chunk
            self.status.content = self._status_html(
                f"Run #{event.run_id}: generation {generation} of 0–{total - 1} done — best so far "
                f"{self.best_so_far[-1]:.3f}{run_replayed_note(self.store, event.run_id)}"
                f"; this generation: best {stats['best']:.3f}, mean {stats['mean']:.3f}; "
                f"{stats.get('evaluations', 0)} games played"
            )
        elif event.status.pending:
            self._show_started(event.run_id, event.status)
        else:
            self.progress.animated = False
            self.within.content = ""
            if event.status is RunStatus.FINISHED:
                self.progress.value = 100.0
            self.status.content = self._status_html(
                f"Run #{event.run_id} {event.status}{self._summary()}.", error=event.status is RunStatus.FAILED
            )
            self.on_run_ended(event.run_id, event.status)
            self.on_runs_changed()

    def _summary(self) -> str:
        """After which generation, the best so far (and where it was found), and the last generation's best."""
        if not self.generations:
            return ""
        found = self.generations[self.best.index(self.best_so_far[-1])]
        return (f" after generation {self.generations[-1]} — best so far {self.best_so_far[-1]:.3f} (generation "
                f"{found}); the last generation's best {self.best[-1]:.3f}")

    def _plot_data(self) -> tuple[np.ndarray, ...]:
        if not self.generations:  # uPlot needs a point to set its scales up; NaN draws nothing
            return (np.zeros(1), np.full(1, np.nan), np.full(1, np.nan), np.full(1, np.nan))
        return (
            np.array(self.generations, dtype=np.float64),
            np.array(self.best, dtype=np.float64),
            np.array(self.best_so_far, dtype=np.float64),
            np.array(self.mean, dtype=np.float64),
        )

    def _plot_scales(self) -> dict[str, viser.uplot.Scale]:
        last = max(1, self.total_generations - 1)
        return {
            "x": viser.uplot.Scale(time=False, auto=False, range=(0.0, float(last))),
            "y": viser.uplot.Scale(auto=False, range=(0.0, 1.0)),
        }

    def _plot_title(self) -> str:
        after = f", after generation {self.generations[-1]}" if self.generations else ""
        return f"Fitness (lower is better){after}"

    def _plot_series(self) -> tuple[viser.uplot.Series, ...]:
        """The legend: each series with its latest value (the x series is not shown in it)."""
        latest = lambda values: f" {values[-1]:.3f}" if values else ""
        return (
            viser.uplot.Series(label="generation"),
            viser.uplot.Series(label=f"best of the generation{latest(self.best)}", stroke=style.SELECTED, width=2,
                               dash=(6, 4)),
            viser.uplot.Series(label=f"best so far{latest(self.best_so_far)}", stroke=style.FIRED, width=3),
            viser.uplot.Series(label=f"mean{latest(self.mean)}", stroke=style.ACCENT, width=2),
        )

    def _redraw_plot(self) -> None:
        self.plot.data = self._plot_data()
        self.plot.series = self._plot_series()
        self.plot.title = self._plot_title()


def _first_line(exc: Exception) -> str:
    """One readable line: pydantic's first error as 'field: message', else the exception's first line."""
    errors = getattr(exc, "errors", None)
    if callable(errors):
        return describe_problem(errors()[0], where=lambda location: LABELS.get(dotted(location), dotted(location)))
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__
