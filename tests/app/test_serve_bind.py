"""Every server `soccer-lab serve` starts listens on 127.0.0.1 unless told otherwise. rerun's web viewer is no
server of its own: the app serves its files (rerun-sdk's own serve_web_viewer would listen on 0.0.0.0), and the
rerun CLI that gives them once listens only on 127.0.0.1 meanwhile."""

from __future__ import annotations

import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import httpx
import pytest

PROC_TCP = (Path("/proc/net/tcp"), Path("/proc/net/tcp6"))
LISTEN = "0A"
pytestmark = pytest.mark.skipif(not PROC_TCP[0].exists(), reason="reads listening sockets from /proc/net/tcp")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def listening_addresses(port: int) -> set[str]:
    """Local addresses of the sockets listening on `port` (IPv4 dotted; IPv6 as its hex)."""
    found = set()
    for table in PROC_TCP:
        if not table.exists():
            continue
        for line in table.read_text().splitlines()[1:]:
            fields = line.split()
            address, port_hex = fields[1].split(":")
            if fields[3] == LISTEN and int(port_hex, 16) == port:
                if len(address) == 8:  # IPv4, little-endian hex
                    found.add(socket.inet_ntoa(bytes.fromhex(address)[::-1]))
                else:
                    found.add(address)
    return found


def wait_for(condition, timeout: float = 60.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if value := condition():
            return value
        time.sleep(0.1)
    raise AssertionError("timed out")


def test_serve_binds_every_server_to_127_0_0_1_by_default(tmp_path):
    ports = {"--port": free_port(), "--ui-port": free_port()}
    arguments = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", str(tmp_path)]
    for option, port in ports.items():
        arguments += [option, str(port)]
    serve = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        wait_for(lambda: all(listening_addresses(p) for p in ports.values()) or serve.poll() is not None)
        assert serve.poll() is None, serve.stdout.read()
        for port in ports.values():
            assert listening_addresses(port) == {"127.0.0.1"}, port
        api = f"http://127.0.0.1:{ports['--port']}"
        home = httpx.get(f"{api}/api/server", timeout=10).json()
        assert home["viewer"] == f"{api}/viewer/" and home["viewer_home"] == f"{api}/viewer/?hide_welcome_screen"
        page = httpx.get(home["viewer_home"], timeout=10)  # the viewer's page, from the app's own address
        assert page.status_code == 200 and "re_viewer.js" in page.text and "fonts.googleapis" not in page.text
    finally:
        serve.send_signal(signal.SIGINT)
        serve.wait(30)
    assert all(listening_addresses(p) == set() for p in ports.values())


@pytest.mark.parametrize("host", ["0.0.0.0", "::", "192.168.1.20", "my-laptop.local"])
def test_the_network_needs_classroom_mode(host, tmp_path):
    """Off this machine only classroom mode serves, behind its join code and teacher token: any other --host is
    refused in one line before anything listens."""
    from typer.testing import CliRunner

    from soccer_lab.app.cli import app

    result = CliRunner().invoke(app, ["serve", "--host", host, "--data-dir", str(tmp_path)])
    assert result.exit_code == 2 and "add --class" in result.output and "Traceback" not in result.output
    assert not any(tmp_path.iterdir())  # nothing started, nothing written


@pytest.mark.parametrize("host", ["127.0.0.1", "127.0.0.2", "::1", "localhost"])
def test_loopback_hosts_are_this_machine(host):
    from soccer_lab.app.cli.serve import _loopback

    assert _loopback(host)
