"""Rerun's web viewer on the address `serve` was told (127.0.0.1, this machine only, unless told otherwise).

rerun-sdk 0.41's `rr.serve_web_viewer` has no host parameter and listens on 0.0.0.0, so the viewer is
the rerun CLI that the same wheel ships (`rerun_cli/rerun`, or $RERUN_CLI_PATH as rerun itself honours),
run as a child process with `--serve-web --bind HOST`: its web server and the gRPC proxy it always
starts (on a port the system picks) both listen on HOST only.

The viewer's welcome screen links to rerun's online examples, which a machine without internet cannot
load. The CLI's `--hide-welcome-screen` only reaches the native viewer; the web viewer takes it from its
own address, so the app links to `viewer_home(...)`, whose `?hide_welcome_screen` turns that screen off.

The viewer dies with the process that started it, `kill -9` included: the kernel sends it SIGKILL when
its parent thread ends (prctl PR_SET_PDEATHSIG, as the rcssservers the app starts), so a restart finds
its ports free. Start it from a thread that lives as long as the app (serve's main thread).
"""

from __future__ import annotations

import os
import socket
import subprocess
import time
from pathlib import Path

from soccer.rcss.servers import die_with_parent

CLI_PATH_VARIABLE = "RERUN_CLI_PATH"
START_TIMEOUT_SECONDS = 15.0
STOP_TIMEOUT_SECONDS = 5.0
POLL_SECONDS = 0.05
ANY_FREE_PORT = 0
WITHOUT_WELCOME_SCREEN = "hide_welcome_screen"  # the web viewer's own query parameter


class RerunViewerError(RuntimeError):
    """The viewer cannot start: one line for the user."""


def rerun_cli_path() -> Path:
    explicit = os.environ.get(CLI_PATH_VARIABLE)
    if explicit:
        return Path(explicit)
    import rerun_cli

    return Path(rerun_cli.__file__).parent / "rerun"


def viewer_home(viewer_url: str) -> str:
    """Where to open the viewer: its address without the welcome screen and its example links."""
    return f"{viewer_url.rstrip('/')}/?{WITHOUT_WELCOME_SCREEN}"


def viewer_command(host: str, port: int) -> list[str]:
    return [str(rerun_cli_path()), "--serve-web", "--bind", host, "--web-viewer-port", str(port),
            "--port", str(ANY_FREE_PORT)]


class RerunViewer:
    """The viewer process; `start` returns once it answers on host:port, `stop` ends it."""

    def __init__(self, host: str, port: int, log_path: Path):
        self.host = host
        self.port = port
        self.log_path = log_path
        self.process: subprocess.Popen | None = None

    def start(self) -> None:
        command = viewer_command(self.host, self.port)
        if not Path(command[0]).is_file():
            raise RerunViewerError(f"rerun's viewer program is missing at {command[0]} (reinstall rerun-sdk)")
        with self.log_path.open("ab") as log:
            self.process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=log, stderr=log,
                                            preexec_fn=die_with_parent(os.getpid()))
        deadline = time.monotonic() + START_TIMEOUT_SECONDS
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise RerunViewerError(f"rerun's viewer ended at start (exit status {self.process.returncode}); "
                                       f"see {self.log_path}")
            if _answers(self.host, self.port):
                return
            time.sleep(POLL_SECONDS)
        self.stop()
        raise RerunViewerError(f"rerun's viewer did not answer on {self.host}:{self.port} within "
                               f"{START_TIMEOUT_SECONDS:.0f} s; see {self.log_path}")

    def stop(self) -> None:
        process, self.process = self.process, None
        if process is None or process.poll() is not None:
            return
        process.terminate()
        try:
            process.wait(STOP_TIMEOUT_SECONDS)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def _answers(host: str, port: int) -> bool:
    try:
        with socket.create_connection((host, port), timeout=POLL_SECONDS):
            return True
    except OSError:
        return False
