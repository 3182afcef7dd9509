"""Which requests come from this app's own pages: the addresses it serves (Host headers) and its own origins.

A web page the user opens elsewhere can make the browser send requests to 127.0.0.1 (a form, a script's
fetch, a websocket), and a DNS-rebinding page can do so under a name of its own. Every server of the app
checks, with one `SiteAddresses`, that the Host header names the address it serves (not some other name)
and, where a page's origin matters (state-changing HTTP requests, the UI's websocket), that the Origin is
one of the app's own. docs/design.md, "Security", says how the pieces fit.
"""

from __future__ import annotations

import socket
from dataclasses import dataclass
from urllib.parse import urlsplit

LOOPBACK_NAMES = frozenset({"127.0.0.1", "localhost", "::1"})
WILDCARD_HOSTS = frozenset({"0.0.0.0", "::", ""})


def _names_for(host: str) -> frozenset[str]:
    """The names a browser may use for `host`: its loopback aliases, or for a wildcard address this
    machine's name and addresses."""
    host = host.strip("[]").lower()
    if host in LOOPBACK_NAMES:
        return LOOPBACK_NAMES
    if host in WILDCARD_HOSTS:
        names = set(LOOPBACK_NAMES) | {socket.gethostname().lower()}
        try:
            names |= {info[4][0] for info in socket.getaddrinfo(socket.gethostname(), None)}
        except OSError:
            pass
        return frozenset(names)
    return frozenset({host})


NOT_IN_AUTHORITY = frozenset("@/?#\\ \t")  # userinfo (evil@host), a path or a query: not a plain host[:port]


def _split(authority: str) -> tuple[str, int | None] | None:
    """(name, port) of 'name[:port]' (IPv6 in brackets); None when it cannot be read or is more than that."""
    if NOT_IN_AUTHORITY.intersection(authority):
        return None
    try:
        parts = urlsplit(f"//{authority}")
        return (parts.hostname or "").lower(), parts.port
    except ValueError:
        return None


@dataclass(frozen=True)
class SiteAddresses:
    """Host names (with the address's aliases) and ports this app serves; `origin_ports` are the ports whose
    pages are the app's own (the address of the API and the pages)."""

    names: frozenset[str]
    ports: frozenset[int]
    origin_ports: frozenset[int]

    @classmethod
    def of(cls, host: str, ports: set[int] | frozenset[int], origin_ports: set[int] | frozenset[int],
           also: tuple[str, ...] = ()) -> "SiteAddresses":
        """`also`: more names of the address (classroom mode: the address printed and in the QR code)."""
        names = _names_for(host) | {name.strip("[]").lower() for name in also}
        return cls(names, frozenset(ports), frozenset(origin_ports))

    def host_refusal(self, host_header: str | None) -> str | None:
        """Why a request's Host header is not this app's address (DNS rebinding), or None when it is."""
        split = _split(host_header or "")
        if split is None or split[0] not in self.names or (split[1] or 80) not in self.ports:
            return (f"Host {host_header!r} is not this app's address: a page under another name is refused "
                    "(open the app at the address `soccer-lab serve` printed)")
        return None

    def origin_refusal(self, origin: str | None) -> str | None:
        """Why a request's Origin is not one of the app's own pages, or None when it is."""
        try:
            parts = urlsplit(origin or "")
            scheme, name, port = parts.scheme, (parts.hostname or "").lower(), parts.port or 80
        except ValueError:
            scheme, name, port = "", "", 0
        if scheme != "http" or name not in self.names or port not in self.origin_ports:
            return f"Origin {origin!r} is not this app's own page: requests from other sites are refused"
        return None
