"""The address students open: this machine's address on the local network (the interface of its default
route), read from the kernel without sending anything (Linux: /proc/net/route, then the interface's IPv4
address); elsewhere, or with no default route, the first non-loopback address of the host name. `serve
--address` names it instead (a name the school's network resolves, another interface)."""

from __future__ import annotations

import fcntl
import ipaddress
import socket
import struct

PROC_ROUTE = "/proc/net/route"
SIOCGIFADDR = 0x8915


def default_route_interface(route_table: str) -> str | None:
    """The interface of the default route in /proc/net/route's text."""
    for line in route_table.splitlines()[1:]:
        fields = line.split()
        if len(fields) > 2 and fields[1] == "00000000":
            return fields[0]
    return None


def interface_address(interface: str) -> str | None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            packed = fcntl.ioctl(probe.fileno(), SIOCGIFADDR, struct.pack("256s", interface[:15].encode()))
        except OSError:
            return None
    return socket.inet_ntoa(packed[20:24])


def lan_address() -> str:
    """This machine's address on the local network; 127.0.0.1 when it has none."""
    try:
        with open(PROC_ROUTE) as table:
            interface = default_route_interface(table.read())
    except OSError:
        interface = None
    if interface is not None and (address := interface_address(interface)) is not None:
        return address
    try:
        for info in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET):
            if not ipaddress.ip_address(info[4][0]).is_loopback:
                return info[4][0]
    except OSError:
        pass
    return "127.0.0.1"
