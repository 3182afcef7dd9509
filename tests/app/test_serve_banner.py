"""What `soccer-lab serve` prints first is an address that works: not viser's own box with the bare viser
address (its page is refused by the origin check and stays on "Connecting..." forever)."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
import time

import httpx

ADDRESS = re.compile(r"https?://[^\s]+")
LAST_LINE = "data"  # serve's address list ends with the data folder


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def serve_first_lines(data_dir) -> tuple[list[str], int, int, subprocess.Popen]:
    port, ui_port = free_port(), free_port()
    arguments = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", str(data_dir),
                 "--port", str(port), "--ui-port", str(ui_port)]
    serve = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines: list[str] = []
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        line = serve.stdout.readline()
        if not line:
            break
        lines.append(line.rstrip("\n"))
        if line.strip().startswith(LAST_LINE):
            break
    return lines, port, ui_port, serve


def test_serve_prints_no_viser_banner_and_its_first_address_works(tmp_path):
    lines, port, ui_port, serve = serve_first_lines(tmp_path)
    try:
        assert lines and lines[-1].strip().startswith(LAST_LINE), lines
        printed = "\n".join(lines)
        assert f":{ui_port}" not in printed and "Websocket" not in printed and "╭" not in printed, printed
        addresses = [address for line in lines for address in ADDRESS.findall(line)]
        assert addresses[0] == f"http://127.0.0.1:{port}/", printed
        for address in addresses:
            assert httpx.get(address, timeout=30, follow_redirects=True).status_code == 200, address
    finally:
        serve.kill()
        serve.wait(30)
