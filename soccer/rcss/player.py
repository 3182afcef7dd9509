"""The fuzzy player on rcssserver: a world model built from see/sense_body, the fuzzy controller,
and the shared skills (soccer/skills.py) turned into `(turn M)`, `(dash P)`, `(kick P D)`.

With the normal view width a see arrives every second cycle. In between, the world model predicts:
the body turns by the moment actually made (moment / (1 + inertia_moment x speed)), the player moves
by its last velocity, and the ball stays where it was last seen. An object is visible when it lies
in the view cone (and, for the ball, was in the last see); premises about an invisible object have
degree 0, exactly as in SimpleSoccer.

The controller and the skill run as one numba kernel (`_command`), on the compiled rulebase of the
batched inference SimpleSoccer uses (fuzzy/batched.py, bit for bit the scalar engine's result): the
server waits for the decision every cycle.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from soccer_lab.fuzzy.batched import NO_ACTION, CompiledRulebases, Scratch, VocabularyTables, compile_rulebases, decide
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig, WorldConstants
from soccer_lab.soccer.engine import NO_OUTCOME, VocabularyLayout, plain
from soccer_lab.soccer.rcss.client import PlayerCycle
from soccer_lab.soccer.rcss.localisation import Pose, goal_relative, localise, normalise_angle
from soccer_lab.soccer.rcss.messages import SenseBody, parse_message
from soccer_lab.soccer.outcome import Outcome
from soccer_lab.soccer.rcss.params import VIEW_HALF_ANGLE, ServerParams
from soccer_lab.soccer.skills import (DASH, HUNT, KICK, LEFT, NONE, RIGHT, TURN, goal_direction_for_skills,
                                      skill_command, skill_set_flags)


def world_constants(params: ServerParams, view_width: str = "normal") -> WorldConstants:
    """The skills' constants: the server's own physics (our skill tunables keep WorldConfig's values)."""
    return params.world.model_copy(update={"view_width": 2 * VIEW_HALF_ANGLE[view_width]}).constants()


class Perception(NamedTuple):
    """The controller's inputs this cycle (None = not visible) plus what the skills need."""

    ball_distance: float | None
    ball_direction: float | None
    goal_distance: float | None
    goal_direction: float | None
    goal_direction_known: float  # from the pose, even out of view: `strict` and `assisted` skills steer by it
    kickable: bool
    speed: float


class WorldModel:
    """Own pose and the ball's position, from see messages and prediction in between, in the player's own
    frame: side l's (the server's global one), or for side r the pitch turned half a turn, so that either side
    attacks +x (as a right-side player in SimpleSoccer's matches, soccer/match.py)."""

    def __init__(self, params: ServerParams, side: str = "l"):
        self.params = params
        self.right_side = side == "r"
        self.pose: Pose | None = None
        self.ball: tuple[float, float] | None = None  # global, where last seen
        self.ball_in_last_see = False
        self.near_ball_distance: float | None = None  # from (b) or (B) in the last see
        self.last_ball_side = LEFT
        self.pending_turn = 0.0  # moment sent last cycle, applied in the step just made
        self.previous_speed = 0.0  # the speed when that turn was applied

    def update(self, cycle: PlayerCycle) -> None:
        body = cycle.sense_body
        head = body.head_angle
        if self.pose is not None:
            self.pose = self._predicted(self.pose, body)
        self.pending_turn = 0.0
        see = cycle.see
        if see is None:
            return
        seen_from = localise(see, head)
        if seen_from is not None and self.right_side:
            seen_from = seen_from.turned_half()
        self.pose = seen_from or self.pose
        ball = see.ball
        near = ball or see.near_ball
        self.near_ball_distance = near.distance if near is not None else None
        self.ball_in_last_see = ball is not None
        if ball is not None:
            direction = normalise_angle(ball.direction + head)
            self.last_ball_side = LEFT if direction < 0 else RIGHT
            if self.pose is not None:
                self.ball = self.pose.to_global(ball.distance, direction)

    def _predicted(self, pose: Pose, body) -> Pose:
        """The pose one step on: the turn actually made, and the move the player's velocity made."""
        turned = self.pending_turn / (1.0 + self.params.world.inertia_moment * self.previous_speed)
        facing = normalise_angle(pose.body + turned)
        moved = body.speed / self.params.world.player_decay  # sense_body reports the velocity after decay
        angle = math.radians(facing + body.head_angle + body.speed_direction)
        return Pose(pose.x + moved * math.cos(angle), pose.y + moved * math.sin(angle), facing)

    def note_command(self, kind: int, value: float, speed: float) -> None:
        if kind == TURN:
            self.pending_turn = value
        self.previous_speed = speed

    def perceive(self, speed: float, view_half_angle: float) -> Perception:
        ball_distance = ball_direction = goal_distance = goal_direction = None
        goal_known = 0.0
        reach = self.params.world.kickable_distance
        kickable = self.near_ball_distance is not None and self.near_ball_distance <= reach
        if self.pose is not None:
            distance, goal_known = goal_relative(self.pose)
            if abs(goal_known) <= view_half_angle:
                goal_distance, goal_direction = distance, goal_known
            if self.ball is not None and self.ball_in_last_see:
                distance, direction = self.pose.relative(*self.ball)
                if abs(direction) <= view_half_angle:
                    ball_distance, ball_direction = distance, direction
                    kickable = kickable or distance <= reach
        return Perception(ball_distance, ball_direction, goal_distance, goal_direction, goal_known, kickable, speed)


class RcssPlayer:
    """One fuzzy player: `decide(cycle)` returns this cycle's body command(s) as text."""

    def __init__(self, rulebase: Rulebase, params: ServerParams, vocabulary: Vocabulary = SOCCER_VOCABULARY,
                 skills: str = GameConfig.model_fields["skills"].default, side: str = "l"):
        """`side`: the server's side of the player's connection ("l" or "r"); it attacks the other side's goal."""
        layout = VocabularyLayout.from_vocabulary(vocabulary)  # refuses a vocabulary the skills cannot play
        compiled = compile_rulebases([rulebase], vocabulary)
        self.skill_set = skill_set_flags(skills)  # (assisted, goal_in_view_only)
        self.vocabulary = vocabulary
        self.last_action = NO_ACTION  # the vocabulary's action index of the last decision (NO_ACTION: the hunt)
        # What the last decision's skill did (soccer/outcome.py words it) and the command text sent, if any.
        self.last_command: tuple[int, float, float, int] = (NONE, 0.0, 0.0, NO_OUTCOME)  # kind, value, direction, why
        self.last_sent: str | None = None
        self.params = params
        self.world = WorldModel(params, side)
        self.constants = world_constants(params)
        self.view_half_angle = VIEW_HALF_ANGLE["normal"]
        # the kernel's first arguments, made once: its work arrays (inputs, visible, strengths, outputs)
        # and the rulebase, scratch, layout and constants as plain tuples (numba types those in C)
        self._kernel_arguments = (np.zeros(len(vocabulary.input_names)), np.zeros(len(vocabulary.object_names), np.bool_),
                                  plain(compiled), plain(Scratch.for_rulebases(compiled)),
                                  np.empty(max(compiled.max_rules, 1)), np.empty(compiled.tables.outputs),
                                  plain(layout), plain(self.constants))

    def decide(self, cycle: PlayerCycle) -> list[str]:
        self.world.update(cycle)
        if self.world.pose is None:  # nothing seen yet this trial: wait for the first see
            return []
        self.view_half_angle = VIEW_HALF_ANGLE.get(cycle.sense_body.view_width, self.view_half_angle)
        perception = self.world.perceive(cycle.sense_body.speed, self.view_half_angle)
        ball_seen, goal_seen = perception.ball_distance is not None, perception.goal_distance is not None
        seen = (ball_seen, perception.ball_distance if ball_seen else 0.0,
                perception.ball_direction if ball_seen else 0.0,
                goal_seen, perception.goal_distance if goal_seen else 0.0, perception.goal_direction if goal_seen else 0.0,
                perception.goal_direction_known, perception.kickable, self.world.last_ball_side, perception.speed)
        kind, value, kick_direction, self.last_action, outcome = _command(*self._kernel_arguments, seen,
                                                                          self.skill_set)
        self.world.note_command(kind, value, perception.speed)
        self.last_command = (kind, value, kick_direction, outcome)
        self.last_sent = command_text(kind, value, kick_direction, self.params) if kind in (TURN, DASH, KICK) else None
        return [self.last_sent] if self.last_sent else []

    def last_outcome(self) -> Outcome | None:
        """What the player did on its last decision, as soccer/outcome.py words it (None before the first)."""
        kind, value, direction, why = self.last_command
        if why == NO_OUTCOME:
            return None
        action = self.vocabulary.action_names[self.last_action] if self.last_action != NO_ACTION else None
        return Outcome(action, kind, value, direction, why)


@numba.njit(cache=True)
def _command(inputs, visible, rulebases, scratch, strengths, outputs, layout, constants, seen, skill_set):
    """The body command (kind, value, direction) of the skill the fuzzy controller selects on what is
    perceived (HUNT when no rule fires), the selected action (NO_ACTION: none fired, the hunt) and why the
    skill gave that command (soccer/skills.py's outcome code);
    `inputs` and `visible` are its work arrays. The named tuples
    arrive plain (soccer_lab.soccer.engine.plain) and are named here. `seen`: this cycle's perception (ball seen, distance,
    direction; goal seen, distance, direction, direction known; kickable, the ball's last side, speed);
    `skill_set`: (assisted, goal in view only)."""
    (ball_seen, ball_distance, ball_direction, goal_seen, goal_distance, goal_direction, goal_direction_known,
     kickable, last_ball_side, speed) = seen
    assisted, goal_in_view_only = skill_set
    rulebases = CompiledRulebases(*(rulebases[:-1] + (VocabularyTables(*rulebases[-1]),)))
    scratch, layout, constants = Scratch(*scratch), VocabularyLayout(*layout), WorldConstants(*constants)
    inputs[layout.ball_distance], inputs[layout.ball_direction] = ball_distance, ball_direction
    inputs[layout.goal_distance], inputs[layout.goal_direction] = goal_distance, goal_direction
    visible[layout.ball], visible[layout.goal] = ball_seen, goal_seen
    action, _ = decide(0, inputs, visible, rulebases, scratch, strengths, outputs)
    skill = HUNT if action == NO_ACTION else layout.skills[action]
    steer_by = goal_direction_for_skills(goal_direction_known, goal_seen, goal_in_view_only)
    kind, value, direction, outcome = skill_command(skill, outputs[layout.direction], outputs[layout.power],
                                                    ball_seen, ball_distance, ball_direction, steer_by, kickable,
                                                    last_ball_side, speed, assisted, constants)
    return kind, value, direction, action, outcome


def load_compiled_skills() -> None:
    """One decision on a made-up view, so that numba loads the compiled kernels now: the first call takes
    seconds, and a server waits only 1.25 s for a cycle's (done) before it steps on without the player."""
    view = parse_message("(see 0 ((f c) 10 0) ((g r) 60 5) ((b) 5 0))")
    body = SenseBody(0, "high", "normal", 0.0, 0.0, 0.0)
    RcssPlayer(Rulebase(()), ServerParams()).decide(PlayerCycle(body, view))


def command_text(kind: int, value: float, direction: float, params: ServerParams) -> str:
    """A skill's body command as rcssserver text, clamped to the server's own limits."""
    if kind == TURN:
        return f"(turn {min(max(value, params.min_moment), params.world.max_moment):.2f})"
    if kind == DASH:
        return f"(dash {min(max(value, params.min_power), params.world.max_power):.2f})"
    if kind == KICK:
        power = min(max(value, params.min_power), params.world.max_power)
        return f"(kick {power:.2f} {normalise_angle(direction):.2f})"
    raise ValueError(f"not a body command: {kind}")
