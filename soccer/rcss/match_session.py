"""A match's connections to one rcssserver: a player on each side and the offline trainer, stepping cycle by
cycle in synch mode (soccer/rcss/client.py's Session, with two players).

rcssserver gives side l to the first team that connects and side r to the second, and keeps each team on its
side for the whole game (it has no side swap): so the two connections keep their sides, and at half time the
players change connections (soccer/rcss/match.py).
"""

from __future__ import annotations

import time

from soccer_lab.soccer.rcss.client import (DEFAULT_SERVER, DEFAULT_TEAM, PlayerClient, PlayerCycle, Timeouts,
                                           TrainerClient, TrainerCycle, parse_server)
from soccer_lab.soccer.rcss.errors import RcssConfigError, RcssNoServerError, RcssRefusedError
from soccer_lab.soccer.rcss.params import ServerParams

SIDES = ("l", "r")
TEAMS = (f"{DEFAULT_TEAM}L", f"{DEFAULT_TEAM}R")  # the left and the right connection's team names
SETTLING_STEPS = 5


class MatchSession:
    """The left player, the right player and the trainer on one server."""

    def __init__(self, server: str = DEFAULT_SERVER, trainer_port: int | None = None, timeouts: Timeouts = Timeouts()):
        host, port = parse_server(server)
        self.server = server
        self.players = tuple(PlayerClient(host, port, team, timeouts) for team in TEAMS)
        self._trainer_address = (host, trainer_port)
        self.timeouts = timeouts
        self.trainer: TrainerClient | None = None
        self.time = 0
        self.late_cycles = 0  # cycles read too late to answer (the server stepped on without our commands)

    @property
    def params(self) -> ServerParams:
        if self.players[0].params is None:
            raise RcssConfigError("player: rcssserver sent no server_param after init")
        return self.players[0].params

    def open(self) -> None:
        """Connect the left player, the right one, then the trainer (eye and ear on, sent with the next done).
        A server that puts a player on the other side already has a team of someone else's: refused."""
        try:
            for player, side in zip(self.players, SIDES):
                player.connect()
                if player.side != side:
                    raise RcssRefusedError(
                        f"rcssserver at {self.server} put our {'first' if side == 'l' else 'second'} player on side "
                        f"{player.side}: another team is connected to it; a match needs a server with no other players")
                player.act([])  # answer its first cycle now: the server waits for it before it lets the next one in
            host, port = self._trainer_address
            self.trainer = TrainerClient(host, port or self.params.coach_port, self.timeouts, self.server)
            self.trainer.connect()
        except BaseException:
            self.close()
            raise
        self.trainer.watch()
        self._settle()

    def _settle(self) -> None:
        """Step (before kick-off: the clock stands still) until every client reads the cycle the server is in:
        the player that connected first has cycles queued from while the others connected."""
        for _ in range(SETTLING_STEPS):
            self.step(([], []))
            if time.monotonic() <= min(player.answer_by for player in self.players):
                break
        self.late_cycles = 0

    def step(self, commands: tuple[list[str], list[str]]) -> tuple[tuple[PlayerCycle, PlayerCycle], TrainerCycle]:
        """Send each side's commands and the three (done)s; return what arrived by the next (think). Past the
        players' `answer_by` nothing is sent (the server has stepped on) and the next cycle is read instead."""
        assert self.trainer is not None, "open() the session first"
        if time.monotonic() <= min(player.answer_by for player in self.players):
            for player, sent in zip(self.players, commands):
                player.act(sent)
            self.trainer.done()
        else:
            self.late_cycles += 1
            for player in self.players:
                player.read_backlog()
            self.trainer.read_backlog()
        trainer_cycle = self.trainer.read_cycle()  # the server sends the trainer's (think) last
        cycles = (self.players[0].read_cycle(), self.players[1].read_cycle())
        self.time = cycles[0].sense_body.time
        return cycles, trainer_cycle

    def close(self) -> None:
        """Leave politely: the players' bye, then the trainer's ear and eye off (so the server does not free-run)
        and its socket closed at once. The server lets a new trainer in only once it has found this one gone (a
        reply refused by its closed port), so the trainer's last messages go right before its socket closes."""
        for player in self.players:
            try:
                if player.side:
                    player.bye()
            except RcssNoServerError:
                pass
            player.close()
        if self.trainer is not None:
            self.trainer.stop_watching()
            try:
                self.trainer.done()
            except RcssNoServerError:
                pass
            self.trainer.close()

    def __enter__(self) -> "MatchSession":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
