"""rerun recordings (.rrd) of evolution runs and games (rerun-sdk 0.41).

Each recording is its own `rr.RecordingStream` writing to a file, never the global stream, so the
server can record several runs at once.

- `RunRecorder(path)`: the per-generation callback. Every statistic becomes a scalar time series on the
  `generation` timeline (entity `statistics/<group>/<name>`), the share of the population per goal count
  also a bar chart (`statistics/goal_histogram`), and each chromosome count's mean - std and mean + std
  a pair of thin lines (`statistics/chromosome_spread/<count>`). `log_generation_replay` adds a
  generation's best player's game (`replay/generation_<g>/...`) on the `tick` timeline.
- The recording carries a blueprint laid out like the chapter's figures (`run_blueprint`): one tab per
  replayed generation (the latest open) beside best/mean/worst fitness (Figs. 11, 12), goal shares
  (Fig. 13), chromosome composition with its standard deviation (Fig. 28), the gene pool (Fig. 29) and
  the population's diversity (distinct chromosomes, rules and behaviours; mean rule-set distance). Each plot's
  legend is a view beside it (`legend/<plot>`: the series' names in their colours), never over its lines.
- `log_replay(stream, trace, world)`: one game on the `tick` timeline: pitch lines and goal (static),
  player with its facing and view cone, ball, the action chosen and the score.

Recordings carry no wall-clock timeline, so the same run gives the same data.

No thread outlives its recording: rerun-sdk 0.41 keeps every stream it made (two threads each: its
batcher and its sender) until a sweep drops the ones nothing refers to, and a blueprint stream (one per
blueprint sent) is never dropped at all. So every blueprint goes through one blueprint stream made once
for the process (`send_blueprint`), and closing a recording sweeps its stream away
(tests/app/test_recording_threads.py counts the threads).
"""

from __future__ import annotations

import math
import threading
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import rerun as rr
import rerun.blueprint as rrb
import rerun_bindings

from soccer_lab.app.words import plural
from soccer_lab.app.pitch_markings import CENTRE_CIRCLE_RADIUS
from soccer_lab.ga.statistics import NOT_MEASURED
from soccer_lab.soccer.config import WorldConfig

APPLICATION_ID = "soccer-lab"
GENERATION_TIMELINE = "generation"
TICK_TIMELINE = "tick"
STATISTICS_ENTITY = "statistics"
GOAL_HISTOGRAM_ENTITY = f"{STATISTICS_ENTITY}/goal_histogram"
SPREAD_ENTITY = f"{STATISTICS_ENTITY}/chromosome_spread"
REPLAY_ENTITY = "replay"
BEST_SO_FAR = "best_so_far"  # not a GenerationStats field: the recorder derives it from the generations' bests
GOAL_BINS = ("goals_0", "goals_1", "goals_2", "goals_3", "goals_4", "goals_more")
# Statistic name prefix -> the group (one plot in the viewer) its series joins; the rest go to "run".
STATISTIC_GROUPS = (
    (("best", BEST_SO_FAR, "mean", "worst", "std"), "fitness"),
    (GOAL_BINS, "goals"),
    (("genes_", "premises_", "rules_", "valid_rules_"), "chromosome"),
    (("unique_",), "gene_pool"),
    (("distinct_", "rule_set_distance"), "diversity"),
)
NOT_A_SERIES = ("generation",)

# What each figure of the blueprint plots: statistic -> (legend name, colour). The generation's best is what
# the chapter's Figs. 9 and 12 plot; the best so far (the run's running minimum) is what a class watches fall.
FITNESS_SERIES = {"best": ("best of the generation", (0, 150, 60)), BEST_SO_FAR: ("best so far", (0, 90, 40)),
                  "mean": ("mean", (30, 120, 255)), "worst": ("worst", (220, 60, 50))}
GOAL_SERIES = {"goals_0": ("0 goals", (150, 150, 150)), "goals_1": ("1 goal", (70, 130, 180)),
               "goals_2": ("2 goals", (60, 170, 110)), "goals_3": ("3 goals", (230, 170, 30)),
               "goals_4": ("4 goals", (230, 110, 40)), "goals_more": ("more than 4", (200, 40, 40))}
COMPOSITION_SERIES = {"genes": ("genes", (30, 120, 255)), "premises": ("premises", (0, 150, 60)),
                      "rules": ("rules", (230, 140, 20)), "valid_rules": ("valid rules", (200, 40, 40))}
GENE_POOL_SERIES = {"unique_premise_genes": ("premise genes", (0, 150, 60)),
                    "unique_consequent_genes": ("consequent genes", (230, 140, 20)),
                    "unique_genes": ("all genes", (30, 120, 255))}
DIVERSITY_SERIES = {"distinct_chromosomes": ("distinct chromosomes", (30, 120, 255)),
                    "distinct_rules": ("distinct rules", (230, 140, 20)),
                    "distinct_behaviours": ("distinct behaviours", (150, 60, 200))}
DISTANCE_SERIES = {"rule_set_distance": ("mean rule-set distance", (0, 150, 60))}
# Each plot's legend (the legend view beside it): legend -> its series' (name, colour), in the plot's order. The
# diversity row's two plots share a row, so their legends say only what their titles do not.
LEGENDS = {"fitness": list(FITNESS_SERIES.values()), "goals": list(GOAL_SERIES.values()),
           "chromosome": list(COMPOSITION_SERIES.values()), "gene_pool": list(GENE_POOL_SERIES.values()),
           "diversity": [(name.removeprefix("distinct "), colour) for name, colour in DIVERSITY_SERIES.values()],
           "distance": [("mean distance", colour) for _, colour in DISTANCE_SERIES.values()]}
SERIES_WIDTH = 2.0
SPREAD_WIDTH = 0.75
BAR_CHART_SHARE = 0.5  # of the goal-shares plot's width
# Legends: rerun 0.41 can only draw a plot's legend in a corner inside the plot, over its lines, so each plot's
# own legend is hidden and a legend view beside it lists the series' names, each in its colour.
LEGEND_ENTITY = "legend"
LEGEND_SHARE = 0.35  # of a plot's width

# Drawing (display only; the world's geometry comes from WorldConfig).
VIEW_CONE_LENGTH = 20.0  # metres drawn along each edge of the view cone
FACING_LENGTH = 1.5
CIRCLE_SEGMENTS = 48
PITCH_MARGIN = 3.0  # metres around the pitch (and the goal behind it) in the replay views
PITCH_COLOUR = (230, 230, 230)
GRASS_COLOUR = (40, 110, 60)  # the replay views' background
GOAL_COLOUR = (255, 215, 0)
PLAYER_COLOUR = (30, 120, 255)
OPPONENT_COLOUR = (230, 81, 0)  # a match's other player (the opponent, on the right in the replayed half)
BALL_COLOUR = (255, 255, 255)
VIEW_CONE_COLOUR = (30, 120, 255, 90)
LINE_RADIUS = 0.12
# The player and the ball are drawn with these radii in UI points whatever the zoom (rerun reads a negative radius
# as UI points): at their true sizes (0.3 m, 0.085 m) on a 105 m pitch they were a pixel or two at the
# default zoom, and the replay looked empty.
PLAYER_MARKER_POINTS = 10.0
BALL_MARKER_POINTS = 6.0
CONE_RADIUS = 0.05
HUNT = "HUNT"  # the label of ticks where no rule fired and the player hunted


# rerun's bindings make, close and sweep streams one at a time in the process: two runs' threads doing so at once
# deadlocked (a new blueprint stream made while the other thread swept orphaned recordings, as it sent a blueprint
# or closed its recording: two API runs hung for good)
_RERUN_LOCK = threading.RLock()


def send_blueprint(stream: rr.RecordingStream, blueprint: rrb.Blueprint, *, make_active: bool = True) -> None:
    """What `stream.send_blueprint` does, without leaving threads behind. Each blueprint gets a blueprint store
    of its own, as rerun's own helper makes it: blueprints sent into one store (a recording sends one as it
    opens and more as its replays come) pile up there, and the viewer warns, in a toast over the views, that
    the earlier ones' containers are "broken references" no longer reachable from the root."""
    with _RERUN_LOCK:
        blueprint_stream = rr.RecordingStream._from_native(rerun_bindings.new_blueprint(
            application_id=APPLICATION_ID, make_default=False, make_thread_default=False, default_enabled=True))
        storage = blueprint_stream.memory_recording()  # only this blueprint's messages
        blueprint_stream.set_time("blueprint", sequence=0)
        blueprint._log_to_stream(blueprint_stream)
        rerun_bindings.send_blueprint(storage.storage, make_active=make_active, make_default=True,
                                      recording=stream.to_native())
        blueprint_stream.disconnect()
        del blueprint_stream, storage  # the last references: the sweep ends the stream's threads
        rerun_bindings.flush_and_cleanup_orphaned_recordings()


def open_stream(path: str | Path, recording_id: str | None = None,
                blueprint: rrb.Blueprint | None = None) -> rr.RecordingStream:
    """A recording stream writing to `path` (overwritten), without wall-clock or log-tick timelines."""
    with _RERUN_LOCK:
        stream = rr.RecordingStream(APPLICATION_ID, recording_id=recording_id, send_properties=False)
        stream.set_log_time_enabled(False)
        stream.set_log_tick_enabled(False)
        stream.save(str(path))
    if blueprint is not None:  # the file's default blueprint, as rerun's save(default_blueprint=...) makes it
        send_blueprint(stream, blueprint, make_active=False)
    return stream


def close_stream(stream: rr.RecordingStream) -> None:
    """Write out and close a recording stream; the sweep ends the threads of streams no longer referenced
    (tests/app/test_recording_threads.py counts them)."""
    with _RERUN_LOCK:
        stream.flush()
        stream.disconnect()
        rerun_bindings.flush_and_cleanup_orphaned_recordings()


def statistic_entity(name: str) -> str:
    """The entity path of one statistic's series, e.g. best -> statistics/fitness/best."""
    for prefixes, group in STATISTIC_GROUPS:
        if any(name == p or (p.endswith("_") and name.startswith(p)) for p in prefixes):
            return f"{STATISTICS_ENTITY}/{group}/{name}"
    return f"{STATISTICS_ENTITY}/run/{name}"


def spread_entity(count: str) -> str:
    """mean - std and mean + std of one chromosome count (genes, premises, rules, valid_rules)."""
    return f"{SPREAD_ENTITY}/{count}"


def replay_entity(generation: int) -> str:
    return f"{REPLAY_ENTITY}/generation_{generation}"


def log_series_styles(stream: rr.RecordingStream) -> None:
    """Legend names, colours and widths of the plotted series, and the legends beside the plots (static: they
    hold on every timeline)."""
    for legend, series in LEGENDS.items():
        log_legend(stream, legend, series)
    for group in (FITNESS_SERIES, GOAL_SERIES, GENE_POOL_SERIES, DIVERSITY_SERIES, DISTANCE_SERIES):
        for statistic, (name, colour) in group.items():
            stream.log(statistic_entity(statistic), rr.SeriesLines(colors=colour, widths=SERIES_WIDTH, names=name),
                       static=True)
    for count, (name, colour) in COMPOSITION_SERIES.items():
        stream.log(statistic_entity(f"{count}_mean"),
                   rr.SeriesLines(colors=colour, widths=SERIES_WIDTH, names=name), static=True)
        stream.log(spread_entity(count), rr.SeriesLines(colors=[colour, colour], widths=[SPREAD_WIDTH, SPREAD_WIDTH],
                                                        names=[f"{name} - std", f"{name} + std"]), static=True)


def log_statistics(stream: rr.RecordingStream, row: Mapping[str, Any]) -> None:
    """One generation's statistics (GenerationStats.to_dict()) at its place on the generation timeline."""
    stream.set_time(GENERATION_TIMELINE, sequence=int(row["generation"]))
    for name, value in row.items():
        if name not in NOT_A_SERIES and not (name == "distinct_behaviours" and value == NOT_MEASURED):
            stream.log(statistic_entity(name), rr.Scalars(float(value)))
    for count in COMPOSITION_SERIES:
        mean, std = float(row[f"{count}_mean"]), float(row[f"{count}_std"])
        stream.log(spread_entity(count), rr.Scalars([mean - std, mean + std]))
    stream.log(GOAL_HISTOGRAM_ENTITY, rr.BarChart(np.array([float(row[b]) for b in GOAL_BINS])))


def legend_entity(legend: str) -> str:
    return f"{LEGEND_ENTITY}/{legend}"


def log_legend(stream: rr.RecordingStream, legend: str, series: Sequence[tuple[str, tuple[int, ...]]]) -> None:
    """One plot's legend: its series' names top down in the plot's order, each in its colour (the labels of
    points too small to draw: the names alone fit the short plots)."""
    stream.log(legend_entity(legend), rr.Points2D(
        [[0.0, float(row)] for row in range(len(series))], colors=[colour for _, colour in series], radii=0.0,
        labels=[name for name, _ in series], show_labels=True), static=True)


def _legend_view(legend: str) -> rrb.Spatial2DView:
    bounds = rrb.VisualBounds2D(x_range=(-1.0, 1.0), y_range=(-0.25, float(len(LEGENDS[legend]))))  # names hang below
    return rrb.Spatial2DView(name=f"Legend of {legend.replace('_', ' ')}", origin=f"/{legend_entity(legend)}",
                             visual_bounds=bounds, titlebar=False)


def _series_view(name: str, series: Sequence[str], legend: str, *, unit_range: bool = False) -> rrb.Horizontal:
    """A plot without rerun's in-plot legend, and its legend view beside it."""
    plot = rrb.TimeSeriesView(name=name, origin="/", contents=[f"+ /{entity}" for entity in series],
                              axis_y=rrb.ScalarAxis(range=(0.0, 1.0)) if unit_range else None,
                              plot_legend=rrb.PlotLegend(visible=False))
    return rrb.Horizontal(plot, _legend_view(legend), column_shares=[1.0, LEGEND_SHARE])


def run_blueprint(replays: Sequence[tuple[int, str]] = (), world: WorldConfig | None = None) -> rrb.Blueprint:
    """The viewer's layout for a run: the chapter's figures and, when there are replays, one tab per
    replayed generation ((generation, tab name), the last one open). No automatic views are added."""
    figures = rrb.Vertical(
        _series_view("Fitness: best of the generation, best so far, mean, worst (Figs. 11, 12; lower is better)",
                     [statistic_entity(s) for s in FITNESS_SERIES], "fitness", unit_range=True),
        rrb.Horizontal(
            _series_view("Share of the population scoring 0 .. more than 4 goals (Fig. 13)",
                         [statistic_entity(s) for s in GOAL_SERIES], "goals", unit_range=True),
            rrb.BarChartView(name="Goal shares at this generation", origin=GOAL_HISTOGRAM_ENTITY,
                             plot_legend=rrb.PlotLegend(visible=False)),
            column_shares=[1.0, BAR_CHART_SHARE]),
        _series_view("Per chromosome: genes, premises, rules, valid rules, mean and ± std (Fig. 28)",
                     [statistic_entity(f"{count}_mean") for count in COMPOSITION_SERIES]
                     + [spread_entity(count) for count in COMPOSITION_SERIES], "chromosome"),
        _series_view("Gene pool: unique premise, consequent and all genes (Fig. 29)",
                     [statistic_entity(s) for s in GENE_POOL_SERIES], "gene_pool"),
        rrb.Horizontal(
            _series_view("Diversity: distinct chromosomes, rules, behaviours",
                         [statistic_entity(s) for s in DIVERSITY_SERIES], "diversity"),
            _series_view("Mean distance between two players' rule sets (1: no rule shared)",
                         [statistic_entity(s) for s in DISTANCE_SERIES], "distance", unit_range=True)),
    )
    layout: rrb.Container = figures
    if replays:
        bounds = None
        if world is not None:
            half_length = world.pitch_length / 2 + world.goal_depth + PITCH_MARGIN
            half_width = world.pitch_width / 2 + PITCH_MARGIN
            bounds = rrb.VisualBounds2D(x_range=(-half_length, half_length), y_range=(-half_width, half_width))
        tabs = rrb.Tabs(*(rrb.Spatial2DView(name=name, origin=f"/{REPLAY_ENTITY}", visual_bounds=bounds,
                                            background=rrb.Background(color=GRASS_COLOUR),
                                            contents=["+ $origin/pitch/**", "+ $origin/goal/**",
                                                      f"+ /{replay_entity(generation)}/**"])
                          for generation, name in replays), active_tab=len(replays) - 1)
        layout = rrb.Horizontal(tabs, figures, column_shares=[1.0, 1.0])
    return rrb.Blueprint(layout, rrb.BlueprintPanel(state="collapsed"), rrb.SelectionPanel(state="collapsed"),
                         rrb.TimePanel(state="collapsed", timeline=GENERATION_TIMELINE, play_state="following"),
                         auto_layout=False, auto_views=False)


class RunRecorder:
    """Callback for `soccer_lab.ga.algorithms.evolve`: logs every generation to `path`.

    When resuming, pass the statistics rows of the generations already finished as `history`:
    they are logged again first, so the recording is whole (a killed run's .rrd may be cut short).
    `world` (SimpleSoccer's) is where replays are drawn; without it the recording has no replays.
    """

    def __init__(self, path: str | Path, *, history: Sequence[Mapping[str, Any]] = (),
                 world: WorldConfig | None = None, recording_id: str | None = None):
        self.path = Path(path)
        self.world = world
        self.replays: list[tuple[int, str]] = []  # (generation, tab name) of each replay logged
        self.best_so_far = math.inf
        self._blueprint_sent: int | None = None  # replay tabs in the last blueprint sent active (None: none yet)
        self.stream = open_stream(self.path, recording_id, run_blueprint())
        log_series_styles(self.stream)
        if world is not None:
            log_pitch(self.stream, world, REPLAY_ENTITY)
        for row in history:
            self._log(row)
        self.stream.flush()

    def on_generation(self, stats: Any, population: Any = None) -> None:
        self._log(stats.to_dict())
        self.stream.flush()  # a killed run keeps what it logged

    def _log(self, row: Mapping[str, Any]) -> None:
        """A generation's statistics, and the run's best so far after it."""
        log_statistics(self.stream, row)
        self.best_so_far = min(self.best_so_far, float(row["best"]))
        self.stream.log(statistic_entity(BEST_SO_FAR), rr.Scalars(self.best_so_far))

    def log_generation_replay(self, generation: int, trace: Any, result: Any) -> None:
        """A generation's best player's game (`result` its GameResult) under replay/generation_<g>; its tab
        joins the blueprint (sent when the tabs double, and when the recording closes)."""
        if self.world is None:
            raise ValueError("this recording has no world to draw replays in")
        if hasattr(trace, "right"):  # a match's half (soccer/match.py MatchTrace): the player and its opponent
            log_match_replay(self.stream, trace, self.world, entity=replay_entity(generation), generation=generation)
            title = f"generation {generation} (a match's first half, {int(trace.goals[-1][0])}-{int(trace.goals[-1][1])})"
        else:
            log_replay(self.stream, trace, self.world, entity=replay_entity(generation), generation=generation,
                       pitch=False)
            title = f"generation {generation} ({plural(result.goals, 'goal')})"
        self.replays.append((generation, title))
        if len(self.replays) & (len(self.replays) - 1) == 0:  # 1, 2, 4, 8 ... tabs: see _blueprint_sent
            self._send_blueprint()
        self.stream.flush()

    def _send_blueprint(self) -> None:
        """The blueprint with a tab per replay so far. A blueprint grows by a tab a replay, so sending it
        after each would make a recording grow with the square of its generations (a 117-generation run
        wrote 82 MB, most of it blueprints); sent when the tabs double and when the recording closes, its
        share stays about twice the last one's (docs/reference/limits.md)."""
        send_blueprint(self.stream, run_blueprint(self.replays, self.world))
        self._blueprint_sent = len(self.replays)

    def close(self) -> None:
        stream = self.stream
        if stream is not None and self._blueprint_sent != len(self.replays):
            # every replay's tab, at the end; and sent active at least once: rerun's web viewer lays a recording
            # whose only blueprint is the file's default (open_stream's) out in its automatic grid instead
            self._send_blueprint()
        self.stream = None
        if stream is not None:
            close_stream(stream)


# ---- replays ---------------------------------------------------------------------------------
def pitch_lines(world: WorldConfig) -> list[np.ndarray]:
    """Touch and end lines, halfway line, centre circle (metres, centre origin, y to the right)."""
    half_length, half_width = world.pitch_length / 2, world.pitch_width / 2
    angles = np.linspace(0.0, 2 * math.pi, CIRCLE_SEGMENTS + 1)
    return [
        np.array([[-half_length, -half_width], [half_length, -half_width], [half_length, half_width],
                  [-half_length, half_width], [-half_length, -half_width]]),
        np.array([[0.0, -half_width], [0.0, half_width]]),
        np.column_stack([CENTRE_CIRCLE_RADIUS * np.cos(angles), CENTRE_CIRCLE_RADIUS * np.sin(angles)]),
    ]


def goal_outline(world: WorldConfig) -> np.ndarray:
    """The attacked goal: from post to post around the net behind the end line."""
    x, half = world.pitch_length / 2, world.goal_width / 2
    depth = x + world.goal_depth
    return np.array([[x, -half], [depth, -half], [depth, half], [x, half]])


def log_match_replay(stream: rr.RecordingStream, trace: Any, world: WorldConfig, *, entity: str,
                     generation: int) -> None:
    """A match's half (soccer_lab.soccer.match MatchTrace) on the tick timeline under `entity`: the player (blue,
    attacking +x) and its opponent, their facings, the ball and the player's goals, as columns."""
    stream.reset_time()
    ticks = len(trace)
    if ticks == 0:
        return
    timeline = [rr.TimeColumn(TICK_TIMELINE, sequence=np.arange(ticks)),
                rr.TimeColumn(GENERATION_TIMELINE, sequence=np.full(ticks, generation))]

    def send(path: str, columns: Any) -> None:
        stream.send_columns(f"{entity}/{path}", indexes=timeline, columns=columns)

    for name, body, colour in (("player", trace.left, PLAYER_COLOUR), ("opponent", trace.right, OPPONENT_COLOUR)):
        facing = np.radians(body[:, 2])
        send(name, rr.Points2D.columns(positions=body[:, :2], radii=np.full(ticks, rr.Radius.ui_points(
            PLAYER_MARKER_POINTS)), colors=np.tile(colour, (ticks, 1))))
        send(f"{name}/facing", rr.Arrows2D.columns(
            origins=body[:, :2], vectors=FACING_LENGTH * np.column_stack([np.cos(facing), np.sin(facing)]),
            colors=np.tile(colour, (ticks, 1))))
    send("ball", rr.Points2D.columns(positions=trace.ball, radii=np.full(ticks, rr.Radius.ui_points(BALL_MARKER_POINTS)),
                                     colors=np.tile(BALL_COLOUR, (ticks, 1))))
    send("score/goals", rr.Scalars.columns(scalars=trace.goals[:, 0].astype(float)))


def view_cone(x: float, y: float, facing: float, half_angle: float) -> np.ndarray:
    """Two edges of the view cone from the player, angles in degrees (y to the right, as rcssserver)."""
    left, right = math.radians(facing - half_angle), math.radians(facing + half_angle)
    return np.array([
        [x + VIEW_CONE_LENGTH * math.cos(left), y + VIEW_CONE_LENGTH * math.sin(left)],
        [x, y],
        [x + VIEW_CONE_LENGTH * math.cos(right), y + VIEW_CONE_LENGTH * math.sin(right)],
    ])


def log_pitch(stream: rr.RecordingStream, world: WorldConfig, entity: str = REPLAY_ENTITY) -> None:
    stream.log(f"{entity}/pitch", rr.LineStrips2D(pitch_lines(world), colors=PITCH_COLOUR, radii=LINE_RADIUS),
               static=True)
    stream.log(f"{entity}/goal", rr.LineStrips2D([goal_outline(world)], colors=GOAL_COLOUR, radii=LINE_RADIUS),
               static=True)


def log_replay(stream: rr.RecordingStream, trace: Any, world: WorldConfig, *, entity: str = REPLAY_ENTITY,
               generation: int | None = None, pitch: bool = True) -> None:
    """One game's trace (soccer_lab.soccer.engine GameTrace) on the tick timeline under `entity`, sent as columns, its
    actions labelled in the vocabulary the game was played in, with its pitch (`pitch`) under the same
    entity. A generation's replay also sits at `generation` on the generation timeline, so that timeline
    shows where each generation's game ended."""
    vocabulary = trace.vocabulary
    labels = [vocabulary.display(name) for name in (HUNT,) + vocabulary.action_names]  # action -1 = hunt
    stream.reset_time()  # a replay's times are its own columns, not the stream's current generation
    if pitch:
        log_pitch(stream, world, entity)
    ticks = len(trace.action)
    if ticks == 0:
        return
    timeline = [rr.TimeColumn(TICK_TIMELINE, sequence=np.arange(ticks))]
    if generation is not None:
        timeline.append(rr.TimeColumn(GENERATION_TIMELINE, sequence=np.full(ticks, generation)))
    player = np.column_stack([trace.player_x, trace.player_y]).astype(float)
    facing = np.radians(np.asarray(trace.facing, dtype=float))
    cones = np.stack([view_cone(x, y, f, world.view_width / 2)
                      for x, y, f in zip(player[:, 0], player[:, 1], trace.facing)])

    def send(path: str, columns: Any) -> None:
        stream.send_columns(f"{entity}/{path}", indexes=timeline, columns=columns)

    send("player", rr.Points2D.columns(
        positions=player, radii=np.full(ticks, rr.Radius.ui_points(PLAYER_MARKER_POINTS)),
        colors=np.tile(PLAYER_COLOUR, (ticks, 1)),
        labels=[labels[a + 1] for a in np.asarray(trace.action).tolist()]))
    send("player/facing", rr.Arrows2D.columns(
        origins=player, vectors=FACING_LENGTH * np.column_stack([np.cos(facing), np.sin(facing)]),
        colors=np.tile(PLAYER_COLOUR, (ticks, 1))))
    send("player/view_cone", rr.LineStrips2D.columns(
        strips=list(cones), colors=np.tile(VIEW_CONE_COLOUR, (ticks, 1)), radii=np.full(ticks, CONE_RADIUS)))
    send("ball", rr.Points2D.columns(
        positions=np.column_stack([trace.ball_x, trace.ball_y]).astype(float),
        radii=np.full(ticks, rr.Radius.ui_points(BALL_MARKER_POINTS)), colors=np.tile(BALL_COLOUR, (ticks, 1))))
    send("score/goals", rr.Scalars.columns(scalars=np.asarray(trace.goals, dtype=float)))
