"""Policy map: the selected action, and one of its parameters, over ball distance x ball direction for
goal inputs the user sets, with the player's current input marked (like fuzzy toolboxes' surface views)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import Axis, escape, svg_open
from soccer_lab.fuzzy.batched import NO_ACTION, compile_rulebases, infer_batch
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

COLUMNS = 60  # ball direction samples
ROWS = 36  # ball distance samples
WIDTH = 520
MAP_HEIGHT = 200
PAD_LEFT = 40
PAD_RIGHT = 18  # half of the last tick's label ("180°") lies right of the map's edge
PAD_BOTTOM = 22
PAD_TOP = 20
RAMP_STEPS = 20  # colour levels of the parameter map
DISTANCE_INPUT, DIRECTION_INPUT = "ball_distance", "ball_direction"
GOAL_DISTANCE_INPUT, GOAL_DIRECTION_INPUT = "goal_distance", "goal_direction"


@dataclass(frozen=True)
class PolicyGrid:
    distances: np.ndarray  # float[ROWS], ascending
    directions: np.ndarray  # float[COLUMNS], ascending
    actions: np.ndarray  # int[ROWS, COLUMNS], NO_ACTION where the player hunts
    values: np.ndarray  # float[ROWS, COLUMNS]: the chosen output's value (NaN where the action does not use it)


def policy_grid(
    vocabulary: Vocabulary,
    rulebase: Rulebase,
    goal_distance: float,
    goal_direction: float,
    goal_visible: bool,
    view_half_angle: float,
    output: str,
) -> PolicyGrid:
    """Evaluate the rulebase on every grid cell in one batched call. The ball is visible only within
    the view angle, as on the pitch."""
    distance_variable = vocabulary.variables[vocabulary.inputs[DISTANCE_INPUT]]
    direction_variable = vocabulary.variables[vocabulary.inputs[DIRECTION_INPUT]]
    distance_axis = Axis(distance_variable, 0.0, 1.0)
    distances = _warped_samples(distance_axis, ROWS)
    directions = np.linspace(direction_variable.minimum, direction_variable.maximum, COLUMNS)
    dist_grid, dir_grid = np.meshgrid(distances, directions, indexing="ij")
    inputs = np.empty((ROWS * COLUMNS, len(vocabulary.input_names)))
    names = vocabulary.input_names
    inputs[:, names.index(DISTANCE_INPUT)] = dist_grid.ravel()
    inputs[:, names.index(DIRECTION_INPUT)] = dir_grid.ravel()
    inputs[:, names.index(GOAL_DISTANCE_INPUT)] = goal_distance
    inputs[:, names.index(GOAL_DIRECTION_INPUT)] = goal_direction
    visible = np.empty((ROWS * COLUMNS, len(vocabulary.object_names)), dtype=bool)
    ball, goal = _object_of(vocabulary, DISTANCE_INPUT), _object_of(vocabulary, GOAL_DISTANCE_INPUT)
    visible[:, vocabulary.object_names.index(ball)] = np.abs(dir_grid.ravel()) <= view_half_angle
    visible[:, vocabulary.object_names.index(goal)] = goal_visible
    compiled = compile_rulebases([rulebase], vocabulary)
    result = infer_batch(compiled, inputs, visible, np.zeros(ROWS * COLUMNS, dtype=np.int64))
    selected = result.selected
    k = vocabulary.output_names.index(output)
    rows = np.arange(selected.shape[0])
    values = np.where(selected == NO_ACTION, np.nan, result.values[rows, np.maximum(selected, 0), k])
    return PolicyGrid(distances, directions, selected.reshape(ROWS, COLUMNS), values.reshape(ROWS, COLUMNS))


def _object_of(vocabulary: Vocabulary, input_name: str) -> str:
    return next(obj for obj, kinds in vocabulary.objects.items() if input_name in kinds.values())


def _warped_samples(axis: Axis, count: int) -> np.ndarray:
    """`count` values evenly spaced on the axis as drawn (cell centres), so every cell has the same size."""
    variable = axis.variable
    targets = (np.arange(count) + 0.5) / count
    fine = np.linspace(variable.minimum, variable.maximum, 4096)
    drawn = np.array([axis(x) for x in fine])
    return np.interp(targets, drawn, fine)


ACTION_MAP, VALUE_MAP = "policy-actions", "policy-values"  # ids of the drawn maps


def policy_cells_html(vocabulary: Vocabulary, grid: PolicyGrid, output: str) -> str:
    """The two maps' cells and axes, drawn when the grid changes, as SVG definitions that
    `policy_map_html` shows: the marker moves every few ticks, the cells much less often."""
    variable = vocabulary.output_variable(output)
    action_colours = [_action_colour(int(a)) for a in grid.actions.ravel()]
    lo, hi = variable.minimum, variable.maximum
    value_colours = [
        _ramp((v - lo) / (hi - lo)) if ok else style.HUNT_COLOUR
        for v, ok in zip(grid.values.ravel(), np.isfinite(grid.values).ravel())
    ]
    return (
        f'<svg class="policy-cells" width="0" height="0" style="position:absolute" aria-hidden="true"><defs>'
        f'<g id="{ACTION_MAP}">{_cells(vocabulary, action_colours)}</g>'
        f'<g id="{VALUE_MAP}">{_cells(vocabulary, value_colours)}</g></defs></svg>'
    )


def policy_map_html(
    vocabulary: Vocabulary, grid: PolicyGrid, output: str, current: tuple[float, float] | None
) -> str:
    """Two maps (action, then `output`'s value; their cells from `policy_cells_html`) with a legend and
    the current (distance, direction) marked."""
    variable = vocabulary.output_variable(output)
    present = sorted({int(a) for a in np.unique(grid.actions)})
    legend = "".join(
        f'<span style="display:inline-flex; align-items:center; gap:4px; margin-right:10px">'
        f'<span style="width:14px; height:14px; border-radius:3px; background:{_action_colour(a)}"></span>'
        f'{escape("hunt (no rule)" if a == NO_ACTION else vocabulary.display(vocabulary.action_names[a]))}</span>'
        for a in present
    )
    return (
        f'<div class="policy-map" style="{style.FONT}; font-size:{style.SMALL_FONT_SIZE + 1}px; color:{style.INK}">'
        f'<div style="font-weight:600">Selected action</div>'
        f"{_map_svg(vocabulary, ACTION_MAP, current)}"
        f'<div style="margin:4px 0 10px 0">{legend}</div>'
        f'<div style="font-weight:600">{escape(output)} ({variable.minimum:g} '
        f'<span style="background:linear-gradient(90deg,{_ramp(0)},{_ramp(1)}); padding:0 30px; margin:0 6px"></span>'
        f"{variable.maximum:g}; grey: not used)</div>"
        f"{_map_svg(vocabulary, VALUE_MAP, current)}</div>"
    )


def _action_colour(action: int) -> str:
    return style.HUNT_COLOUR if action == NO_ACTION else style.ACTION_COLOURS[action % len(style.ACTION_COLOURS)]


def _ramp(t: float) -> str:
    """Light yellow to deep blue: readable on a projector and for most colour-blind viewers."""
    t = round(min(max(t, 0.0), 1.0) * RAMP_STEPS) / RAMP_STEPS
    start, end = (255, 241, 118), (13, 71, 161)
    r, g, b = (round(s + (e - s) * t) for s, e in zip(start, end))
    return f"rgb({r},{g},{b})"


def _axes(vocabulary: Vocabulary) -> tuple[Axis, Axis]:
    distance_axis = Axis(vocabulary.variables[vocabulary.inputs[DISTANCE_INPUT]], PAD_TOP + MAP_HEIGHT, PAD_TOP)
    direction_axis = Axis(vocabulary.variables[vocabulary.inputs[DIRECTION_INPUT]], PAD_LEFT, WIDTH - PAD_RIGHT)
    return distance_axis, direction_axis


def _cells(vocabulary: Vocabulary, colours: list[str]) -> str:
    cell_w = (WIDTH - PAD_LEFT - PAD_RIGHT) / COLUMNS
    cell_h = MAP_HEIGHT / ROWS
    parts = []
    for i in range(ROWS):
        y = PAD_TOP + MAP_HEIGHT - (i + 1) * cell_h  # near at the bottom
        row = colours[i * COLUMNS : (i + 1) * COLUMNS]
        start = 0
        for j in range(1, COLUMNS + 1):  # one rect per run of equal colour keeps the SVG small
            if j == COLUMNS or row[j] != row[start]:
                x = PAD_LEFT + start * cell_w
                parts.append(
                    f'<rect x="{x:.1f}" y="{y:.1f}" width="{(j - start) * cell_w + 0.4:.1f}" '
                    f'height="{cell_h + 0.4:.1f}" fill="{row[start]}"/>'
                )
                start = j
    distance_axis, direction_axis = _axes(vocabulary)
    for tick in (1, 4, 15, 40, 130):
        parts.append(
            f'<text x="{PAD_LEFT - 4}" y="{distance_axis(tick) + 4:.1f}" font-size="{style.SMALL_FONT_SIZE}" '
            f'text-anchor="end" fill="{style.INK}">{tick}</text>'
        )
    for tick in (-180, -90, -45, 0, 45, 90, 180):
        parts.append(
            f'<text x="{direction_axis(tick):.1f}" y="{PAD_TOP + MAP_HEIGHT + 15}" font-size="{style.SMALL_FONT_SIZE}" '
            f'text-anchor="middle" fill="{style.INK}">{tick}°</text>'
        )
    parts.append(
        f'<text x="{PAD_LEFT}" y="{PAD_TOP - 6}" font-size="{style.SMALL_FONT_SIZE}" fill="{style.MUTED}">'
        f"ball distance (m, up) × ball direction (°, across; left is negative)</text>"
    )
    return "".join(parts)


def _map_svg(vocabulary: Vocabulary, cells: str, current: tuple[float, float] | None) -> str:
    parts = [svg_open(WIDTH, MAP_HEIGHT + PAD_TOP + PAD_BOTTOM), f'<use href="#{cells}"/>']
    if current is not None:
        distance_axis, direction_axis = _axes(vocabulary)
        x, y = direction_axis(current[1]), distance_axis(current[0])
        parts.append(
            f'<g class="current"><circle cx="{x:.1f}" cy="{y:.1f}" r="7" fill="none" stroke="white" stroke-width="4"/>'
            f'<circle cx="{x:.1f}" cy="{y:.1f}" r="7" fill="none" stroke="{style.INK}" stroke-width="2"/></g>'
        )
    parts.append("</svg>")
    return "".join(parts)
