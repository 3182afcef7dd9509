"""Matches on a real rcssserver (docs/research/matches.md, "On rcssserver"): SimpleSoccer's match (soccer/match.py) played by two of our clients on
one server, one per side, set up by the trainer as trials are (soccer/rcss/trial.py; docs/research/matches.md,
"On rcssserver").

A match is two halves from one start, drawn from the match's seed exactly as SimpleSoccer's (match_starts): each
player uniform in its own half facing the goal it attacks, the ball at rest on the centre line. Player A plays the
left connection (attacking +x) in the first half and the right one in the second; rcssserver keeps its teams on
their sides, so the players change connections at half time (soccer/rcss/match_session.py). Goals are the
referee's `goal_l_N` / `goal_r_N`; kicks each player's own count (sense_body); the ball's closest approach to each
goal and the players' idleness come from the trainer's see_global. After a goal the trainer waits
`restart_wait_cycles`, then puts the ball on a point of the centre line drawn from the match's stream (as
SimpleSoccer's restart); a ball the referee takes out of play (kick-in, goal kick, corner) is put back in play at
once where the referee placed it, as SimpleSoccer's walls keep it on the pitch. A half ends at max ticks (server
cycles), when either side reaches the goal cap, or when both players have been idle for the idle limit at once.

Each half starts fresh (stamina, the referees' counters, the see phase: Trial.fresh_start's reasons), so a
match's course depends on its rulebases, its seed and the server's noise only. rcssserver 19 takes no seed for
its noise (it seeds from the clock; `server::random_seed` is not an option it accepts, and `player::random_seed`
draws only the heterogeneous player types, which our type-0 players do not use): with the noise on a match
differs from run to run, with it off (`noise=False`, servers with NOISELESS_OPTIONS) it plays the same on any
server, as a trial does.
"""

from __future__ import annotations

import math
import sys
from typing import Sequence

from pydantic import PositiveInt

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.soccer.config import EvaluationRules, WorldConfig
from soccer_lab.soccer.engine import END_REASONS, GOAL_CAP, IDLE, MAX_TICKS
from soccer_lab.soccer.match import HalfResult, MatchResult, match_starts
from soccer_lab.soccer.random_stream import seed_states, uniform
from soccer_lab.soccer.rcss.client import PlayerCycle, TrainerCycle
from soccer_lab.soccer.rcss.localisation import PITCH_HALF_LENGTH
from soccer_lab.soccer.rcss.match_session import SIDES, MatchSession
from soccer_lab.soccer.rcss.player import RcssPlayer
from soccer_lab.soccer.rcss.trial import BEFORE_KICK_OFF, CONTINUING_MODES, PLAY_ON, check_noise

NO_NEWS = ([], [])  # neither side sends a command this cycle
NARROW_VIEW = (["(change_view narrow)"], ["(change_view narrow)"])
NORMAL_VIEW = (["(change_view normal)"], ["(change_view normal)"])
FACING = (0.0, 180.0)  # each side's body at the start, global degrees: facing the goal it attacks
GOAL_CENTRES = ((PITCH_HALF_LENGTH, 0.0), (-PITCH_HALF_LENGTH, 0.0))  # the goal each side attacks


class RcssMatchConfig(EvaluationRules):
    """The rules of a match's half on rcssserver: SimpleSoccer's (max_ticks, goal_cap, idle_ticks, idle_distance,
    skills; their defaults too), counted in server cycles, the trainer's wait after a goal, and whether the
    server adds its noise (on by default, as in trials)."""

    restart_wait_cycles: PositiveInt = 5
    noise: bool = True


class RcssHalf:
    """One half's bookkeeping: the start, goals and kicks per side, closest approaches, idleness, restarts, the end."""

    def __init__(self, session: MatchSession, rulebases: tuple[Rulebase, Rulebase], seed: int,
                 config: RcssMatchConfig):
        self.session = session
        self.config = config
        self.players = tuple(RcssPlayer(rulebase, session.params, skills=config.skills, side=side)
                             for rulebase, side in zip(rulebases, SIDES))
        self.stream = seed_states([seed])
        constants = WorldConfig().constants()  # SimpleSoccer's pitch, rcssserver's too
        first, second, ball_y = match_starts(self.stream, constants)
        self.half_width = constants.half_width
        self.starts = ((float(first[0, 0]), float(first[0, 1])), (-float(second[0, 0]), -float(second[0, 1])))
        self.ball_y = float(ball_y[0])
        self.goals, self.kicks, self.idle = [0, 0], [0, 0], [0, 0]
        self.closest = [math.hypot(PITCH_HALF_LENGTH, self.ball_y)] * 2
        self.kick_counts = [0, 0]
        self.positions: list[tuple[float, float] | None] = [None, None]
        self.ticks = 0
        self.cycles_since_goal: int | None = None  # None: no goal freeze under way
        self.end: int | None = None  # an index into END_REASONS
        self.late_cycles = 0  # cycles of play the clients read too late to answer (a busy machine)

    def run(self) -> HalfResult:
        self.fresh_start()
        trainer = self.session.trainer
        trainer.move_ball(0.0, self.ball_y)
        for player, (x, y), facing in zip(self.session.players, self.starts, FACING):
            trainer.move_player(player.team, player.unum, x, y, facing)
        trainer.change_mode(PLAY_ON)
        commands, late_before = NO_NEWS, self.session.late_cycles
        while self.end is None:
            cycles, trainer_cycle = self.session.step(commands)
            self.ticks += 1
            self.observe(cycles, trainer_cycle)
            commands = self.respond(cycles) if self.end is None else NO_NEWS
        self.late_cycles = self.session.late_cycles - late_before
        return HalfResult(tuple(self.goals), tuple(self.kicks), tuple(self.closest), self.ticks, END_REASONS[self.end])

    def fresh_start(self) -> None:
        """As Trial.fresh_start, for both players: full stamina, the referees' counters reset with the ball on
        the centre spot, and the placing cycle one without a see for both. Each player's see comes every second
        cycle counted from when it connected, so the two may be out of step: a cycle of narrow view (a see every
        cycle, which restarts the count) puts both in the same step, the same in every match."""
        trainer = self.session.trainer
        trainer.command("(recover)")
        trainer.change_mode(BEFORE_KICK_OFF)
        trainer.move_ball(0.0, 0.0)
        self.session.step(NARROW_VIEW)
        cycles, _ = self.session.step(NORMAL_VIEW)  # a see the cycle before (narrow), so none in this one
        self.kick_counts = [cycle.sense_body.kick_count for cycle in cycles]

    def observe(self, cycles: tuple[PlayerCycle, PlayerCycle], trainer_cycle: TrainerCycle) -> None:
        for hear in trainer_cycle.hears:
            goal = hear.goal
            if goal is not None:
                self.goals[SIDES.index(goal[0])] += 1
                self.cycles_since_goal = 0
            elif hear.from_referee and hear.message not in CONTINUING_MODES and self.cycles_since_goal is None:
                self.session.trainer.change_mode(PLAY_ON)  # out of play: back in play where the referee put it
        kicked = [False, False]
        for side, cycle in enumerate(cycles):
            count = cycle.sense_body.kick_count
            kicked[side] = count > self.kick_counts[side]
            self.kicks[side] += max(count - self.kick_counts[side], 0)
            self.kick_counts[side] = count
        self._note_places(trainer_cycle, kicked)
        if max(self.goals) >= self.config.goal_cap:
            self.end = GOAL_CAP
        elif self.ticks >= self.config.max_ticks:
            self.end = MAX_TICKS
        elif min(self.idle) >= self.config.idle_ticks:
            self.end = IDLE

    def _note_places(self, trainer_cycle: TrainerCycle, kicked: list[bool]) -> None:
        seen = trainer_cycle.see_global
        if seen is None:
            return
        if seen.ball is not None:
            for side, goal in enumerate(GOAL_CENTRES):
                self.closest[side] = min(self.closest[side], math.dist((seen.ball.x, seen.ball.y), goal))
        for side, player in enumerate(self.session.players):
            me = seen.player(player.team, player.unum)
            if me is None:
                continue
            here, before = (me.x, me.y), self.positions[side]
            moved = before is None or math.dist(before, here) > self.config.idle_distance
            self.idle[side] = 0 if (moved or kicked[side]) else self.idle[side] + 1
            self.positions[side] = here

    def respond(self, cycles: tuple[PlayerCycle, PlayerCycle]) -> tuple[list[str], list[str]]:
        """Each side's commands; during a goal freeze the trainer restarts play instead."""
        if self.cycles_since_goal is None:
            return self.players[0].decide(cycles[0]), self.players[1].decide(cycles[1])
        self.cycles_since_goal += 1
        if self.cycles_since_goal >= self.config.restart_wait_cycles:
            self.session.trainer.move_ball(0.0, float(uniform(self.stream, 0, -self.half_width, self.half_width)))
            self.session.trainer.change_mode(PLAY_ON)
            self.cycles_since_goal = None
        return NO_NEWS


def play_rcss_match(session: MatchSession, a: Rulebase, b: Rulebase, seed: int,
                    config: RcssMatchConfig = RcssMatchConfig()) -> tuple[MatchResult, int]:
    """One match of A against B from `seed` on an open session (A on the left in the first half, on the right in
    the second), and the cycles of play its clients answered too late."""
    halves = [RcssHalf(session, pair, seed, config) for pair in ((a, b), (b, a))]
    first, second = (half.run() for half in halves)
    return MatchResult(seed, (first, second)), sum(half.late_cycles for half in halves)


def play_rcss_matches(session: MatchSession, a: Rulebase, b: Rulebase, seeds: Sequence[int],
                      config: RcssMatchConfig = RcssMatchConfig()) -> list[MatchResult]:
    """One match per seed, one after another on the session's server; results in seed order. A server whose
    noise is not the config's is refused (RcssConfigError). Cycles answered too late (the server stepped on
    without the players' commands) are reported on stderr, as trials' are."""
    check_noise(session.server, session.params, config.noise, "the match wants")
    played = [play_rcss_match(session, a, b, seed, config) for seed in seeds]
    late = sum(late for _, late in played)
    if late:
        cycles = sum(half.ticks for result, _ in played for half in result.halves)
        print(f"warning: the players answered {late} of {cycles} rcssserver cycles too late (a busy machine): "
              "the server stepped on without their commands", file=sys.stderr, flush=True)
    return [result for result, _ in played]
