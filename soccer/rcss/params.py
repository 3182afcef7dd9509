"""The server's own parameters, read from its `server_param` message.

Our player is heterogeneous type 0, whose values are the server_param ones. The physics the skills
scale their commands with form a WorldConfig: rcssserver's defaults are WorldConfig's (soccer/config.py
is their one home) and every value the server sends replaces its default, so a server run with other
settings is honoured.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from pydantic import ValidationError

from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.rcss.errors import RcssConfigError

# Half-width of the view cone per view width with synch_see (protocol >= 18): narrow 60, normal 120,
# wide 180 degrees in total. Objects at -59 and +57 degrees were seen with normal width (NOTES.md).
VIEW_HALF_ANGLE = {"narrow": 30.0, "normal": 60.0, "wide": 90.0}
# server_param names of the fields we spell otherwise; every other WorldConfig field is read under its
# own name when the server sends it (pitch size and our own
# decisions, such as the skills' tunables, are not in server_param and keep WorldConfig's values).
SERVER_NAMES = {"max_power": "maxpower", "max_moment": "maxmoment", "min_power": "minpower",
                "min_moment": "minmoment"}
DEFAULT_WORLD = WorldConfig()
# The server's random parameters: any above 0 (or wind) makes movement, turns and kicks noisy.
NOISE_PARAMETERS = ("player_rand", "ball_rand", "kick_rand")
WIND_PARAMETERS = ("wind_force", "wind_rand")


@dataclass(frozen=True)
class ServerParams:
    """The server's physics (`world`), its command limits, and the options trials depend on."""

    world: WorldConfig = DEFAULT_WORLD
    min_power: float = -DEFAULT_WORLD.max_power  # rcssserver's ranges are symmetric by default
    min_moment: float = -DEFAULT_WORLD.max_moment
    synch_mode: bool = True
    coach: bool = True
    coach_w_referee: bool = True
    coach_port: int = 6001
    noise: bool = True  # rcssserver's defaults are noisy (NOISE_PARAMETERS)

    @classmethod
    def from_message(cls, values: Mapping[str, object]) -> "ServerParams":
        """Every value we know from the message; the rest keep their defaults."""
        physics = {name: values[SERVER_NAMES.get(name, name)] for name in WorldConfig.model_fields
                   if SERVER_NAMES.get(name, name) in values}
        try:
            world = WorldConfig(**{**DEFAULT_WORLD.model_dump(), **physics})
        except ValidationError as exc:
            problems = "; ".join(f"{SERVER_NAMES.get(str(e['loc'][0]), e['loc'][0])} {e['input']!r}: {e['msg']}"
                                 for e in exc.errors())
            raise RcssConfigError(f"rcssserver's server_param holds values the player cannot use: {problems}") from None
        options = {"min_power": float, "min_moment": float, "synch_mode": bool, "coach": bool,
                   "coach_w_referee": bool, "coach_port": int}
        return cls(world, noise=_noisy(values),
                   **{name: kind(values[SERVER_NAMES.get(name, name)]) for name, kind in options.items()
                      if SERVER_NAMES.get(name, name) in values})

    def check_usable(self) -> None:
        """Raise RcssConfigError naming the option when the server runs with options trials cannot use."""
        if not self.synch_mode:
            raise RcssConfigError(
                "rcssserver is not in synch mode: start it with server::synch_mode=true (see docs/robocup/index.md)"
            )
        if not self.coach:
            raise RcssConfigError(
                "rcssserver runs without the offline trainer: start it with server::coach=true "
                "server::coach_w_referee=true (see docs/robocup/index.md)"
            )
        if not self.coach_w_referee:
            raise RcssConfigError(
                "rcssserver runs with coach=true but without referees, so goals are never announced: "
                "add server::coach_w_referee=true"
            )


def _noisy(values: Mapping[str, object]) -> bool:
    """Whether the server adds noise (a parameter it does not send counts as its noisy default)."""
    windless = bool(values.get("wind_none", False)) or not any(float(values.get(n, 0)) > 0 for n in WIND_PARAMETERS)
    return any(float(values.get(n, 1)) > 0 for n in NOISE_PARAMETERS) or not windless
