"""rerun recordings (.rrd) of evolution runs and games (rerun-sdk 0.41).

Each recording is its own `rr.RecordingStream` writing to a file, never the global stream, so the
server can record several runs at once.

- `RunRecorder(path)`: the per-generation callback. Every statistic of spec 3.3 becomes a scalar time
  series on the `generation` timeline (entity `statistics/<group>/<name>`), and the share of the
  population per goal count a bar chart (`statistics/goal_histogram`).
- `log_replay(stream, trace, world)`: one game on the `tick` timeline: pitch lines and goal (static),
  player with its facing and view cone, ball, the action chosen and the score.

Recordings carry no wall-clock timeline, so the same run gives the same data.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import rerun as rr

from app.pitch_markings import CENTRE_CIRCLE_RADIUS
from soccer.config import WorldConfig

APPLICATION_ID = "soccer-lab"
GENERATION_TIMELINE = "generation"
TICK_TIMELINE = "tick"
STATISTICS_ENTITY = "statistics"
GOAL_HISTOGRAM_ENTITY = f"{STATISTICS_ENTITY}/goal_histogram"
REPLAY_ENTITY = "replay"
GOAL_BINS = ("goals_0", "goals_1", "goals_2", "goals_3", "goals_4", "goals_more")
# Statistic name prefix -> the group (one plot in the viewer) its series joins; the rest go to "run".
STATISTIC_GROUPS = (
    (("best", "mean", "worst", "std"), "fitness"),
    (GOAL_BINS, "goals"),
    (("genes_", "premises_", "rules_", "valid_rules_"), "chromosome"),
    (("unique_",), "gene_pool"),
)
NOT_A_SERIES = ("generation",)

# Drawing (display only; the world's geometry comes from WorldConfig).
VIEW_CONE_LENGTH = 20.0  # metres drawn along each edge of the view cone
FACING_LENGTH = 1.5
CIRCLE_SEGMENTS = 48
PITCH_COLOUR = (230, 230, 230)
GOAL_COLOUR = (255, 215, 0)
PLAYER_COLOUR = (30, 120, 255)
BALL_COLOUR = (255, 255, 255)
VIEW_CONE_COLOUR = (30, 120, 255, 90)
LINE_RADIUS = 0.12
CONE_RADIUS = 0.05
HUNT = "HUNT"  # the label of ticks where no rule fired and the player hunted (spec 4.3)


def open_stream(path: str | Path, recording_id: str | None = None) -> rr.RecordingStream:
    """A recording stream writing to `path` (overwritten), without wall-clock or log-tick timelines."""
    stream = rr.RecordingStream(APPLICATION_ID, recording_id=recording_id, send_properties=False)
    stream.set_log_time_enabled(False)
    stream.set_log_tick_enabled(False)
    stream.save(str(path))
    return stream


def statistic_entity(name: str) -> str:
    """The entity path of one statistic's series, e.g. best -> statistics/fitness/best."""
    for prefixes, group in STATISTIC_GROUPS:
        if any(name == p or (p.endswith("_") and name.startswith(p)) for p in prefixes):
            return f"{STATISTICS_ENTITY}/{group}/{name}"
    return f"{STATISTICS_ENTITY}/run/{name}"


def log_statistics(stream: rr.RecordingStream, row: Mapping[str, Any]) -> None:
    """One generation's statistics (GenerationStats.to_dict()) at its place on the generation timeline."""
    stream.set_time(GENERATION_TIMELINE, sequence=int(row["generation"]))
    for name, value in row.items():
        if name not in NOT_A_SERIES:
            stream.log(statistic_entity(name), rr.Scalars(float(value)))
    stream.log(GOAL_HISTOGRAM_ENTITY, rr.BarChart(np.array([float(row[b]) for b in GOAL_BINS])))


class RunRecorder:
    """Callback for `ga.algorithms.evolve`: logs every generation to `path`.

    When resuming, pass the statistics rows of the generations already finished as `history`:
    they are logged again first, so the recording is whole (a killed run's .rrd may be cut short).
    """

    def __init__(self, path: str | Path, *, history: list[Mapping[str, Any]] = (), recording_id: str | None = None):
        self.path = Path(path)
        self.stream = open_stream(self.path, recording_id)
        for row in history:
            log_statistics(self.stream, row)
        self.stream.flush()

    def on_generation(self, stats: Any, population: Any = None) -> None:
        log_statistics(self.stream, stats.to_dict())
        self.stream.flush()  # a killed run keeps what it logged

    def log_replay(self, trace: Any, world: WorldConfig, *, entity: str = REPLAY_ENTITY) -> None:
        log_replay(self.stream, trace, world, entity=entity)
        self.stream.flush()

    def close(self) -> None:
        self.stream.flush()
        self.stream.disconnect()


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


def log_replay(stream: rr.RecordingStream, trace: Any, world: WorldConfig, *, entity: str = REPLAY_ENTITY) -> None:
    """One game's trace (soccer.engine GameTrace) on the tick timeline under `entity`, sent as columns; its
    actions are labelled in the vocabulary the game was played in."""
    vocabulary = trace.vocabulary
    labels = [vocabulary.display(name) for name in (HUNT,) + vocabulary.action_names]  # action -1 = hunt
    stream.reset_time()  # the replay lives on the tick timeline only, not at some generation
    log_pitch(stream, world, entity)
    ticks = len(trace.action)
    if ticks == 0:
        return
    timeline = [rr.TimeColumn(TICK_TIMELINE, sequence=np.arange(ticks))]
    player = np.column_stack([trace.player_x, trace.player_y]).astype(float)
    facing = np.radians(np.asarray(trace.facing, dtype=float))
    cones = np.stack([view_cone(x, y, f, world.view_width / 2)
                      for x, y, f in zip(player[:, 0], player[:, 1], trace.facing)])

    def send(path: str, columns: Any) -> None:
        stream.send_columns(f"{entity}/{path}", indexes=timeline, columns=columns)

    send("player", rr.Points2D.columns(
        positions=player, radii=np.full(ticks, world.player_size), colors=np.tile(PLAYER_COLOUR, (ticks, 1)),
        labels=[labels[a + 1] for a in np.asarray(trace.action).tolist()]))
    send("player/facing", rr.Arrows2D.columns(
        origins=player, vectors=FACING_LENGTH * np.column_stack([np.cos(facing), np.sin(facing)]),
        colors=np.tile(PLAYER_COLOUR, (ticks, 1))))
    send("player/view_cone", rr.LineStrips2D.columns(
        strips=list(cones), colors=np.tile(VIEW_CONE_COLOUR, (ticks, 1)), radii=np.full(ticks, CONE_RADIUS)))
    send("ball", rr.Points2D.columns(
        positions=np.column_stack([trace.ball_x, trace.ball_y]).astype(float),
        radii=np.full(ticks, world.ball_size), colors=np.tile(BALL_COLOUR, (ticks, 1))))
    send("score/goals", rr.Scalars.columns(scalars=np.asarray(trace.goals, dtype=float)))
