"""SimpleSoccer's observation and action spaces in Gymnasium's terms, and the conversions between
them and the engine's arrays (soccer/engine.py `Observation`, `GameBatch.act`).

Observation, a Dict: "inputs", a float64 Box of the vocabulary's inputs in its order (ball and goal,
each a distance in metres and a direction in degrees relative to the facing, as perception gives them),
and "visible", a MultiBinary of its objects in its order (1: in the view cone). An object out of view
has its inputs at 0: the player does not perceive them, and "visible" says so.

Action, a Dict: "skill", a Discrete over the vocabulary's actions in its order plus one more, the
hunt (what the player does when no rule fired), and "parameters", a float64 Box of the vocabulary's
outputs in its order (direction, power), each bounded by its universe; a skill reads only the
parameters its action uses (soccer/skills.py).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np
from gymnasium import spaces

from soccer_lab.fuzzy.batched import NO_ACTION
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.perception import DIRECTION, DISTANCE

UNSEEN_INPUT = 0.0  # an out-of-view object's inputs in the observation ("visible" says it is unseen)


def _input_bounds(world: WorldConfig) -> dict[str, tuple[float, float]]:
    """What perception can give: no two points of the pitch with its net lie further apart than its
    diagonal; a direction is an angle in (-180, 180]."""
    diagonal = math.hypot(world.pitch_length + world.goal_depth, world.pitch_width)
    return {DISTANCE: (0.0, diagonal), DIRECTION: (-180.0, 180.0)}


class SoccerSpaces(NamedTuple):
    """A vocabulary's observation and action spaces, and where its inputs and actions sit."""

    observation: spaces.Dict
    action: spaces.Dict
    input_object: np.ndarray  # int64[n_inputs]: the object each input describes
    hunt: int  # the "skill" value of the hunt

    @classmethod
    def of(cls, vocabulary: Vocabulary, world: WorldConfig) -> "SoccerSpaces":
        inputs, objects = vocabulary.input_names, vocabulary.object_names
        bounds = _input_bounds(world)
        input_object = np.empty(len(inputs), dtype=np.int64)
        low, high = np.empty(len(inputs)), np.empty(len(inputs))
        for o, obj in enumerate(objects):
            for kind, name in vocabulary.objects[obj].items():
                i = inputs.index(name)
                input_object[i] = o
                low[i], high[i] = bounds[kind]
        observation = spaces.Dict({
            "inputs": spaces.Box(low, high, dtype=np.float64),
            "visible": spaces.MultiBinary(len(objects)),
        })
        universes = [vocabulary.variables[vocabulary.outputs[name][0]] for name in vocabulary.output_names]
        action = spaces.Dict({
            "skill": spaces.Discrete(len(vocabulary.action_names) + 1),
            "parameters": spaces.Box(np.array([u.minimum for u in universes]),
                                     np.array([u.maximum for u in universes]), dtype=np.float64),
        })
        return cls(observation, action, input_object, len(vocabulary.action_names))

    def observations(self, inputs: np.ndarray, visible: np.ndarray) -> dict[str, np.ndarray]:
        """The engine's perception rows (inputs NaN when unseen, visible bool) as observations (new arrays)."""
        seen_inputs, seen_visible = np.empty(inputs.shape), np.empty(visible.shape, dtype=np.int8)
        _observations(inputs, visible, self.input_object, seen_inputs, seen_visible)
        return {"inputs": seen_inputs, "visible": seen_visible}

    def engine_inputs(self, observation: dict) -> tuple[np.ndarray, np.ndarray]:
        """Observations (one or a batch) back as the engine's rows: inputs (NaN when unseen), visible."""
        visible = np.atleast_2d(np.asarray(observation["visible"])).astype(np.bool_)
        inputs = np.atleast_2d(np.asarray(observation["inputs"], dtype=np.float64))
        return np.where(visible[:, self.input_object], inputs, np.nan), visible

    def engine_actions(self, action: dict, games: int) -> tuple[np.ndarray, np.ndarray]:
        """Actions (one or a batch of `games`) as GameBatch.act takes them; ValueError for a skill out of
        range or a parameter that is not a number. Parameters beyond their universe act as its bound (an
        agent's raw output may overshoot; a fuzzy controller's never does)."""
        skills = np.asarray(action["skill"], dtype=np.int64).reshape(games)
        box = self.action["parameters"]
        parameters = np.asarray(action["parameters"], dtype=np.float64)
        if parameters.size != games * box.shape[0]:
            raise ValueError(f"parameters must be {box.shape[0]} numbers per game, got {parameters}")
        actions, values = np.empty(games, dtype=np.int64), np.empty((games, box.shape[0]))
        bad = _engine_actions(skills, parameters.reshape(games, box.shape[0]), self.hunt, box.low, box.high,
                              actions, values)
        if bad >= 0:
            raise ValueError(f"skill must be in 0..{self.hunt} ({self.hunt}: the hunt) and parameters numbers, "
                             f"got skill {skills[bad]} with parameters {parameters.reshape(games, -1)[bad]}")
        return actions, values

    def actions(self, engine_actions: np.ndarray, values: np.ndarray) -> dict[str, np.ndarray]:
        """The engine's decisions (action index or NO_ACTION, output values) as actions."""
        return {"skill": np.where(engine_actions == NO_ACTION, self.hunt, engine_actions), "parameters": values}


# The conversions run once a step for every sub-environment: compiled, they cost one call instead of a
# numpy operation per field (which took as long as the engine's tick for 100 games).


@numba.njit(cache=True)
def _observations(inputs, visible, input_object, seen_inputs, seen_visible):
    for g in range(inputs.shape[0]):
        for o in range(visible.shape[1]):
            seen_visible[g, o] = visible[g, o]
        for i in range(inputs.shape[1]):
            seen_inputs[g, i] = inputs[g, i] if visible[g, input_object[i]] else UNSEEN_INPUT


@numba.njit(cache=True)
def _engine_actions(skills, parameters, hunt, low, high, actions, values):
    """Fills actions and values; returns the first row with a skill out of range or a NaN, else -1."""
    for g in range(skills.shape[0]):
        skill = skills[g]
        if skill < 0 or skill > hunt:
            return g
        actions[g] = NO_ACTION if skill == hunt else skill
        for k in range(parameters.shape[1]):
            value = parameters[g, k]
            if math.isnan(value):
                return g
            values[g, k] = min(max(value, low[k]), high[k])
    return -1
