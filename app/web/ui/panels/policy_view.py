"""The policy map's controls: goal inputs (or follow the player's), the output shown, live marker."""

from __future__ import annotations

import time
from typing import Callable, Mapping

import viser

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.policy import (DIRECTION_INPUT, DISTANCE_INPUT, GOAL_DIRECTION_INPUT,
                                                 GOAL_DISTANCE_INPUT, policy_cells_html, policy_grid, policy_map_html)
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

INITIAL_GOAL_DISTANCE = 30.0
INITIAL_GOAL_DIRECTION = 0.0


class PolicyPanel:
    """The map of `show_rulebase`'s rules, marked at the inputs `show_current` gets each frame.
    `on_change()` asks for a redraw when the user changes a control (also while the game is paused)."""

    def __init__(self, gui: viser.GuiApi, vocabulary: Vocabulary, rulebase: Rulebase, view_half_angle: float,
                 *, on_change: Callable[[], None]):
        self.vocabulary = vocabulary
        self.rulebase = rulebase
        self.view_half_angle = view_half_angle
        distance = vocabulary.variables[vocabulary.inputs[GOAL_DISTANCE_INPUT]]
        direction = vocabulary.variables[vocabulary.inputs[GOAL_DIRECTION_INPUT]]
        self.follow = gui.add_checkbox("Goal inputs follow the player", True)
        self.goal_visible = gui.add_checkbox("Goal in view", True)
        self.goal_distance = gui.add_slider(
            "Goal distance (m)", min=distance.minimum, max=distance.maximum, step=0.5, initial_value=INITIAL_GOAL_DISTANCE
        )
        self.goal_direction = gui.add_slider(
            "Goal direction (°)", min=direction.minimum, max=direction.maximum, step=1.0,
            initial_value=INITIAL_GOAL_DIRECTION,
        )
        self.output = gui.add_dropdown("Parameter shown", vocabulary.output_names, initial_value=vocabulary.output_names[-1])
        self.cells = gui.add_html("")
        self.map = gui.add_html("")
        self._grid_key: tuple | None = None
        self._grid = None
        self._last_render = 0.0
        self._last_html = ""
        self._controls_changed = False
        self._mirroring = False
        for handle in (self.follow, self.goal_visible, self.goal_distance, self.goal_direction, self.output):
            handle.on_update(lambda event: self._control_changed(event, on_change))
        self._enable_goal_controls()

    def _control_changed(self, event: viser.GuiEvent, on_change: Callable[[], None]) -> None:
        if self._mirroring:  # the panel itself showing the followed goal inputs
            return
        self._controls_changed = True
        self._enable_goal_controls()
        on_change()

    def _enable_goal_controls(self) -> None:
        """Following the player, the goal controls show its inputs and cannot be changed."""
        for handle in (self.goal_visible, self.goal_distance, self.goal_direction):
            handle.disabled = self.follow.value

    def _mirror(self, goal_visible: bool, goal_distance: float, goal_direction: float) -> None:
        """The controls show the goal inputs the map is drawn for."""
        self._mirroring = True
        try:
            self.goal_visible.value = goal_visible
            self.goal_distance.value, self.goal_direction.value = goal_distance, goal_direction
        finally:
            self._mirroring = False

    def show_rulebase(self, rulebase: Rulebase) -> None:
        self.rulebase = rulebase
        self._grid_key = None

    def show_current(self, inputs: Mapping[str, float | None]) -> None:
        now = time.perf_counter()
        if not self._controls_changed and now - self._last_render < style.POLICY_REFRESH_SECONDS:
            return
        self._last_render = now
        self._controls_changed = False
        if self.follow.value:
            goal_distance, goal_direction = inputs.get(GOAL_DISTANCE_INPUT), inputs.get(GOAL_DIRECTION_INPUT)
            goal_visible = goal_distance is not None
            if goal_visible:
                # Round so the map is recomputed when the goal inputs move noticeably, not every tick.
                goal_distance, goal_direction = round(goal_distance), round(goal_direction)
            else:
                goal_distance, goal_direction = self.goal_distance.value, self.goal_direction.value
            self._mirror(goal_visible, goal_distance, goal_direction)
        else:
            goal_distance, goal_direction = self.goal_distance.value, self.goal_direction.value
            goal_visible = self.goal_visible.value
        key = (id(self.rulebase), goal_distance, goal_direction, goal_visible, self.output.value)
        if key != self._grid_key:
            self._grid_key = key
            self._grid = policy_grid(
                self.vocabulary, self.rulebase, float(goal_distance), float(goal_direction),
                bool(goal_visible), self.view_half_angle, self.output.value,
            )
            self.cells.content = policy_cells_html(self.vocabulary, self._grid, self.output.value)
        ball = inputs.get(DISTANCE_INPUT), inputs.get(DIRECTION_INPUT)
        current = (float(ball[0]), float(ball[1])) if ball[0] is not None else None
        html = policy_map_html(self.vocabulary, self._grid, self.output.value, current)
        caption = (
            f'<div style="{style.FONT}; font-size:{style.SMALL_FONT_SIZE + 1}px; color:{style.MUTED}">'
            f"Goal {'in view at ' + format(goal_distance, 'g') + ' m, ' + format(goal_direction, 'g') + '°' if goal_visible else 'out of view'}"
            f"; the ring marks the player's ball input{'' if current else ' (ball out of view)'}.</div>"
        )
        html = caption + html
        if html != self._last_html:
            self._last_html = html
            self.map.content = html
