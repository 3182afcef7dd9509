"""Trials as the chapter ran them on rcssserver (the chapter, 5.2-5.3), driven cycle by cycle in synch mode.

A trial: the trainer puts the player at a random point of its own half facing the goal it attacks
and the ball at the centre spot, then `(change_mode play_on)`. It ends after `max_ticks` cycles,
at the goal cap, after `idle_ticks` cycles in which the player neither moved more than
`idle_distance` (from the trainer's see_global) nor kicked, or when the referee takes the ball out of
play (kick-in, goal kick, corner, own goal, ...). After a goal the server freezes time; the trainer
waits `restart_wait_cycles` cycles, then puts the ball on a random point of the centre line and sets
play_on again, as the recorded trainer did (tests/rcss/transcripts/trial_goals.txt). Kicks are the server's
own count of kicks that reached the ball (sense_body's kick counter).

Two options change how a trial is played, to measure what the chapter's real-time games did differently
(docs/robocup/full-study.md, "When a finding disagrees"); both default to the trials above. `restart="server"`
leaves the restart after a goal to rcssserver, as a game without a trainer: 50 cycles with its clock stopped,
the kick-off to the other side (the player moved into its own half and kept from the ball), which nobody takes,
and a drop ball `drop_ball_time` (100) cycles later. `answer_delay` and `answer_delay_spread` make the player's
answers late, as a real-time client's can be: each decision reaches the server some cycles after the one it was
made for, drawn from the trial's seed.

A server plays thousands of trials in its life, so each trial first puts back what earlier ones changed
(`Trial.fresh_start`): the player's stamina (a server never restores it: a player that dashes used up its
stamina capacity within 6 trials of 1200 cycles and crept along at stamina 0 for the rest of the run),
the referees' counters (a play-mode change resets them; the ball-stuck count would carry over) and the
phase of the player's see (every second cycle with view width normal, counted over the server's life).
So a trial's course depends only on its rulebase, its seed and the server's noise: with the noise off
(soccer/rcss/servers.py, NOISELESS_OPTIONS; `TrialConfig.noise`) the same trial plays the same on any server, after any others.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from pydantic import Field, PositiveInt, model_validator

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import EvaluationRules, FitnessName
from soccer_lab.soccer.fitness import fitness as fitness_of
from soccer_lab.soccer.rcss.client import PlayerCycle, Session, TrainerCycle
from soccer_lab.soccer.rcss.errors import RcssConfigError
from soccer_lab.soccer.rcss.localisation import PITCH_HALF_LENGTH, PITCH_HALF_WIDTH
from soccer_lab.soccer.rcss.params import ServerParams
from soccer_lab.soccer.rcss.player import RcssPlayer
from soccer_lab.soccer.rcss.servers import NOISELESS_OPTIONS
PLAY_ON = "play_on"
BEFORE_KICK_OFF = "before_kick_off"  # the mode a new server starts in: the clock stands still, nothing moves
CONTINUING_MODES = frozenset({PLAY_ON, "drop_ball"})  # the ball stays in play
OUR_SIDE = "l"  # the player is the left team's only player: it attacks (g r)
THEIR_KICK_OFF = "kick_off_r"  # the server's restart after our goal, left alone
MAX_ANSWER_DELAY = 50  # cycles: 5 s of real time
DELAY_STREAM = 1  # SeedSequence spawn key of the answer delays' draws, apart from the placements' stream
LATER_OPTIONS = ("restart", "answer_delay", "answer_delay_spread")  # added after the first studies ran
RENAMED_FIELDS = {"max_cycles": "max_ticks", "idle_cycles": "idle_ticks"}


class TrialConfig(EvaluationRules):
    """The rules of one trial: a SimpleSoccer game's (EvaluationRules, counted in server cycles) with the
    chapter's RoboCup values where they differ, and the trainer's wait after a goal."""

    max_ticks: PositiveInt = 1200  # 120 s of server time at 100 ms per cycle, as the chapter
    fitness: FitnessName = "robocup-composite"
    restart_wait_cycles: PositiveInt = 5  # after a goal, cycles before the trainer restarts play
    # Who restarts play after a goal: the trainer (after restart_wait_cycles), or nobody ("server"): rcssserver's
    # own restart, 50 frozen cycles, the other side's kick-off, a drop ball 100 cycles later. The player plays on
    # throughout (the chapter's player ignores what it hears), and its idleness is not counted till play_on.
    restart: Literal["trainer", "server"] = "trainer"
    # Late answers: each decision reaches the server answer_delay cycles after the cycle it was made for, plus 0 to
    # answer_delay_spread more (uniform, drawn per decision from the trial's seed). Answers keep their order; of
    # several arriving in one cycle only the first is sent (rcssserver executes one body command a cycle, the
    # first), and a cycle in which none arrives has none. 0 and 0: the answer in the same cycle.
    answer_delay: int = Field(0, ge=0, le=MAX_ANSWER_DELAY)
    answer_delay_spread: int = Field(0, ge=0, le=MAX_ANSWER_DELAY)
    # The server's own noise (movement, turns, kicks), on as in the chapter. Off, a trial plays the same every
    # time (rcssserver seeds its noise from the clock): servers soccer-lab starts get NOISELESS_OPTIONS
    # (soccer/rcss/servers.py), and a server you run must match (its server_param says).
    noise: bool = True

    def unset_later_options(self) -> set[str]:
        """The options added after the first studies ran that keep their defaults: left out of a setting's key
        (app/experiment/presets.py, Setting.key), so those studies' trial files keep their names."""
        return {name for name in LATER_OPTIONS if getattr(self, name) == type(self).model_fields[name].default}

    @model_validator(mode="before")
    @classmethod
    def _earlier_names(cls, values: Any) -> Any:
        """Runs stored before the shared rules named the limits max_cycles and idle_cycles."""
        if isinstance(values, dict):
            values = {RENAMED_FIELDS.get(name, name): value for name, value in values.items()}
        return values


@dataclass(frozen=True)
class TrialTrace:
    """A trial cycle by cycle: where the trainer's see_global put player and ball, the action the player
    chose on that cycle, and the goals before it; the fields a replay draws (app/runs/recording.py, log_replay),
    named as soccer_lab.soccer.engine.GameTrace's."""

    player_x: np.ndarray
    player_y: np.ndarray
    facing: np.ndarray  # degrees: the body's global angle
    ball_x: np.ndarray
    ball_y: np.ndarray
    action: np.ndarray  # int: the vocabulary's action index of the latest decision, NO_ACTION (-1) the hunt
    goals: np.ndarray  # goals scored before this cycle
    vocabulary: Vocabulary
    command: np.ndarray  # int: the body command the latest decision's skill sent (soccer/skills.py NONE...KICK)
    command_value: np.ndarray  # float: its moment or power (before the server's clamping)
    command_direction: np.ndarray  # float: a kick's direction
    outcome: np.ndarray  # int: why the skill gave that command (soccer/outcome.py); -1 before the first decision

    def __len__(self) -> int:
        return len(self.action)


@dataclass(frozen=True)
class TrialResult:
    fitness: float
    goals: int
    kicks: int
    ticks: int
    end: str  # why the trial ended: "time", "goal cap", "idle", "out of play (MODE)", "no rules"
    seed: int
    trace: TrialTrace | None = field(default=None, compare=False, repr=False)  # when the trial was traced
    # Cycles the client read too late to answer (a busy machine): the server stepped on without the player's
    # commands. Not part of the result; a measure of how far the machine kept up.
    late_cycles: int = field(default=0, compare=False)


def start_position(rng: np.random.Generator) -> tuple[float, float]:
    """Uniform in the player's own half."""
    return float(rng.uniform(-PITCH_HALF_LENGTH, 0.0)), float(rng.uniform(-PITCH_HALF_WIDTH, PITCH_HALF_WIDTH))


def centre_line_point(rng: np.random.Generator) -> tuple[float, float]:
    return 0.0, float(rng.uniform(-PITCH_HALF_WIDTH, PITCH_HALF_WIDTH))


class Trial:
    """One trial's bookkeeping: goals, kicks, idleness, the restart after a goal, and the end."""

    def __init__(self, session: Session, rulebase: Rulebase, seed: int, config: TrialConfig = TrialConfig(),
                 trace: bool = False):
        self.session = session
        self.config = config
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.player = RcssPlayer(rulebase, session.params, skills=config.skills)
        self.goals = self.kicks = self.ticks = self.idle = 0
        self.cycles_since_goal: int | None = None  # None: no goal freeze under way
        self.end: str | None = None
        self.kick_count = 0  # the server's count when the trial starts (fresh_start)
        self.position: tuple[float, float] | None = None
        # with `trace`: per cycle player x, y, body angle, ball x, y (see_global), action, goals before, and the
        # latest decision's command (kind, value, direction, outcome)
        self.rows: list[tuple] | None = [] if trace else None
        # late answers: (cycle due, commands) in the order decided, and the due cycle of the latest
        self.late = config.answer_delay > 0 or config.answer_delay_spread > 0
        self.delay_rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(DELAY_STREAM,)))
        self.in_flight: deque[tuple[int, list[str]]] = deque()
        self.last_due = 0

    def run(self) -> TrialResult:
        """Start fresh, place ball and player, then play until the trial ends."""
        self.fresh_start()
        trainer = self.session.trainer
        player_x, player_y = start_position(self.rng)
        trainer.move_ball(0.0, 0.0)
        trainer.move_player(self.session.player.team, self.session.player.unum, player_x, player_y, 0.0)
        trainer.change_mode(PLAY_ON)
        commands: list[str] = []
        late_before = self.session.late_cycles
        while self.end is None:
            player_cycle, trainer_cycle = self.session.step(commands)
            goals_before = self.goals
            self.ticks += 1
            self.observe(player_cycle, trainer_cycle)
            commands = self.respond(player_cycle) if self.end is None else []
            if self.late:
                commands = self.arriving(commands)
            if self.rows is not None:
                self._note_row(trainer_cycle, goals_before)
        return TrialResult(self.score(), self.goals, self.kicks, self.ticks, self.end, self.seed, self._trace(),
                           self.session.late_cycles - late_before)

    def fresh_start(self) -> None:
        """Put the server back as a new one starts a trial: full stamina (the trainer's `(recover)`), the
        referees' counters reset (a change of play mode; before_kick_off stops the clock) with the ball already
        on the centre spot (the ball-stuck referee counts from where it last saw the ball), and the cycle in
        which ball and player are placed one without a see, so that the trial's first cycle has one, as on a
        new server. Answers the cycle we are in and leaves the one in which placing happens unanswered."""
        trainer = self.session.trainer
        trainer.command("(recover)")
        trainer.change_mode(BEFORE_KICK_OFF)
        trainer.move_ball(0.0, 0.0)
        player_cycle, _ = self.session.step([])
        if player_cycle.see is not None:  # the player sees every second cycle: the next one has none
            player_cycle, _ = self.session.step([])
        self.kick_count = player_cycle.sense_body.kick_count

    def _note_row(self, trainer_cycle: TrainerCycle, goals_before: int) -> None:
        seen = trainer_cycle.see_global
        me = seen.player(self.session.player.team, self.session.player.unum) if seen else None
        ball = seen.ball if seen else None
        if me is not None and ball is not None:
            places = (me.x, me.y, me.body, ball.x, ball.y)
        elif self.rows:
            places = self.rows[-1][:5]  # nothing seen this cycle: where they were
        else:
            return
        self.rows.append(places + (self.player.last_action, goals_before) + self.player.last_command)

    def _trace(self) -> TrialTrace | None:
        if self.rows is None:
            return None
        columns = list(zip(*self.rows)) if self.rows else [()] * 11
        floats = [np.array(column, dtype=np.float64) for column in columns[:5]]
        action, goals = (np.array(column, dtype=np.int64) for column in columns[5:7])
        kind, value, direction, outcome = columns[7:]
        return TrialTrace(*floats, action, goals, self.player.vocabulary, np.array(kind, dtype=np.int64),
                          np.array(value, dtype=np.float64), np.array(direction, dtype=np.float64),
                          np.array(outcome, dtype=np.int64))

    def observe(self, player_cycle: PlayerCycle, trainer_cycle: TrainerCycle) -> None:
        config = self.config
        for hear in trainer_cycle.hears:
            if not hear.from_referee:
                continue
            goal = hear.goal
            if goal is not None and goal[0] == OUR_SIDE:
                self.goals += 1
                self.cycles_since_goal = 0
            elif self.config.restart == "server" and self.cycles_since_goal is not None:
                if hear.message in CONTINUING_MODES:  # the server's drop ball: the ball is in play again
                    self.cycles_since_goal = None
                elif hear.message != THEIR_KICK_OFF:
                    self.end = f"out of play ({hear.message})"
            elif hear.message not in CONTINUING_MODES:
                self.end = f"out of play ({hear.message})"
        kick_count = player_cycle.sense_body.kick_count
        kicked = kick_count > self.kick_count
        self.kicks += max(kick_count - self.kick_count, 0)
        self.kick_count = kick_count
        self._note_movement(trainer_cycle, kicked)
        if self.end is not None:
            return
        if self.goals >= config.goal_cap:
            self.end = "goal cap"
        elif self.idle >= config.idle_ticks:
            self.end = "idle"
        elif self.ticks >= config.max_ticks:
            self.end = "time"

    def _note_movement(self, trainer_cycle: TrainerCycle, kicked: bool) -> None:
        seen = trainer_cycle.see_global
        me = seen.player(self.session.player.team, self.session.player.unum) if seen else None
        if me is None:
            return
        if self.config.restart == "server" and self.cycles_since_goal is not None:  # the ball out of play
            self.idle, self.position = 0, (me.x, me.y)
            return
        moved = self.position is None or math.dist(self.position, (me.x, me.y)) > self.config.idle_distance
        self.idle = 0 if (moved or kicked) else self.idle + 1
        self.position = (me.x, me.y)

    def respond(self, player_cycle: PlayerCycle) -> list[str]:
        """The player's commands for this cycle; during a goal freeze the trainer restarts play instead (unless
        the restart is left to the server: then the player plays on)."""
        if self.cycles_since_goal is None or self.config.restart == "server":
            return self.player.decide(player_cycle)
        self.cycles_since_goal += 1
        if self.cycles_since_goal >= self.config.restart_wait_cycles:
            self.session.trainer.move_ball(*centre_line_point(self.rng))
            self.session.trainer.change_mode(PLAY_ON)
            self.cycles_since_goal = None
        return []

    def arriving(self, commands: list[str]) -> list[str]:
        """Late answers: this cycle's decision joins those in flight, due some cycles on; returns what arrives
        now (the first of what is due: the server would execute only that)."""
        config = self.config
        if commands:
            spread = int(self.delay_rng.integers(0, config.answer_delay_spread + 1)) if config.answer_delay_spread else 0
            self.last_due = max(self.ticks + config.answer_delay + spread, self.last_due)  # answers keep their order
            self.in_flight.append((self.last_due, commands))
        arrived: list[str] = []
        while self.in_flight and self.in_flight[0][0] <= self.ticks:
            due = self.in_flight.popleft()[1]
            arrived = arrived or due
        return arrived

    def score(self) -> float:
        return fitness_of(self.config.fitness, self.goals, self.kicks, max(self.ticks, 1), math.inf, 2 * PITCH_HALF_LENGTH)


def run_trial(session: Session, rulebase: Rulebase, seed: int, config: TrialConfig = TrialConfig(),
              trace: bool = False) -> TrialResult:
    """Play one trial on an open session (with `trace`, its TrialTrace too). A rulebase without rules
    scores the worst fitness unplayed. A server whose noise is not the trial's is refused (RcssConfigError)."""
    if len(rulebase) == 0:
        return TrialResult(fitness_of(config.fitness, 0, 0, 1, math.inf, 2 * PITCH_HALF_LENGTH), 0, 0, 0, "no rules", seed)
    check_noise(session.server, session.params, config.noise)
    return Trial(session, rulebase, seed, config, trace).run()


def check_noise(server: str, params: ServerParams, noise: bool, wanting: str = "the trials want") -> None:
    """RcssConfigError unless the server (its `params`) adds noise exactly when `noise` says (a match's too)."""
    if params.noise == noise:
        return
    if noise:
        raise RcssConfigError(f"rcssserver at {server} runs without noise, but {wanting} the server's "
                              "noise: start it with its default player_rand, ball_rand and kick_rand")
    raise RcssConfigError(f"rcssserver at {server} adds noise, but {wanting} none: start it with "
                          + " ".join(f"{name}={value}" for name, value in NOISELESS_OPTIONS.items()))
