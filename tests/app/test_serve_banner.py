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


def test_serve_s_ctrl_c_says_stopped_and_nothing_of_viser_s(tmp_path):
    # Ctrl+C printed "(viser) Server stopped" above serve's own "stopped": viser's voice, which the teacher is
    # never otherwise shown.
    import signal

    lines, _, _, serve = serve_first_lines(tmp_path)
    try:
        assert lines and lines[-1].strip().startswith(LAST_LINE), lines
        time.sleep(1.0)  # past the address list: what serve says once it listens
        serve.send_signal(signal.SIGINT)
        rest = serve.communicate(timeout=120)[0]
        assert serve.returncode == 0, rest
        assert rest.strip() == "stopped", rest
    finally:
        if serve.poll() is None:
            serve.kill()
            serve.wait(30)
