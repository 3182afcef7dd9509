"""Typed failures of the rcssserver client. Every message is one line a user can act on."""

from __future__ import annotations


class RcssError(Exception):
    """Base class: anything that went wrong talking to rcssserver."""


class RcssParseError(RcssError):
    """A datagram that is not a well-formed s-expression or not a message of a known shape."""


class RcssNoServerError(RcssError):
    """Nobody answered the init message (no server, wrong host or port, firewall)."""


class RcssTimeoutError(RcssError):
    """The server went silent in the middle of a session (it quit, or someone missed cycles)."""


class RcssRefusedError(RcssError):
    """The server answered init with an error (e.g. the trainer was refused)."""


class RcssCommandError(RcssError):
    """The server answered one of our commands with (error ...)."""


class RcssConfigError(RcssError):
    """The server runs with options we cannot work with (not in synch mode, referees off)."""
