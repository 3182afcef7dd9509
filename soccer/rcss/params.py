"""The server's own physical parameters, read from its `server_param` message.

Our player is heterogeneous type 0, whose values are the server_param ones. Commands are scaled
with these (never with SimpleSoccer's constants), so a server run with other settings is honoured.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Mapping

from soccer.rcss.errors import RcssConfigError

# Half-width of the view cone per view width with synch_see (protocol >= 18): narrow 60, normal 120,
# wide 180 degrees in total. Objects at -59 and +57 degrees were seen with normal width (NOTES.md).
VIEW_HALF_ANGLE = {"narrow": 30.0, "normal": 60.0, "wide": 90.0}


@dataclass(frozen=True)
class ServerParams:
    dash_power_rate: float = 0.006
    kick_power_rate: float = 0.027
    player_decay: float = 0.4
    ball_decay: float = 0.94
    inertia_moment: float = 5.0
    kickable_margin: float = 0.7
    player_size: float = 0.3
    ball_size: float = 0.085
    player_speed_max: float = 1.05
    ball_speed_max: float = 3.0
    ball_accel_max: float = 2.7
    maxpower: float = 100.0
    minpower: float = -100.0
    maxmoment: float = 180.0
    minmoment: float = -180.0
    goal_width: float = 14.02
    visible_distance: float = 3.0
    simulator_step: int = 100
    synch_mode: bool = True
    coach: bool = False
    coach_w_referee: bool = False
    coach_port: int = 6001

    @property
    def kickable_distance(self) -> float:
        """Ball centre to player centre distance within which a kick reaches the ball."""
        return self.player_size + self.ball_size + self.kickable_margin

    @classmethod
    def from_message(cls, values: Mapping[str, object]) -> "ServerParams":
        """Take every field we know from the message; the rest keep rcssserver's defaults."""
        chosen = {}
        for spec in fields(cls):
            if spec.name in values:
                value = values[spec.name]
                kind = {"bool": bool, "int": int, "float": float}[spec.type]
                chosen[spec.name] = kind(value)
        return cls(**chosen)

    def check_usable(self) -> None:
        """Raise RcssConfigError when the server runs with options trials cannot use."""
        if not self.synch_mode:
            raise RcssConfigError(
                "rcssserver is not in synch mode: start it with server::synch_mode=true (see README)"
            )
        if self.coach and not self.coach_w_referee:
            raise RcssConfigError(
                "rcssserver runs with coach=true but without referees, so goals are never announced: "
                "add server::coach_w_referee=true"
            )
