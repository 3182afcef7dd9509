"""`soccer-lab serve`: the browser app (UI, JSON API, rerun viewer) on this machine."""

from __future__ import annotations

import ipaddress
import os
import sys
from pathlib import Path
from typing import Optional

import typer

from soccer_lab.app.cli.common import fail
from soccer_lab.app.experiment.executors import EXECUTOR_NAMES, LOCAL, RAY
from soccer_lab.app.paths import default_data_dir
from soccer_lab.app.web.server import DEFAULT_HOST, DEFAULT_PORT, DEFAULT_UI_PORT, ServeError, ServeOptions, serve
from soccer_lab.app.store import StoreError

PORT_RANGE = {"min": 1, "max": 65535}
CLASS_HOST = "0.0.0.0"  # classroom mode listens on every interface unless --host says which


def serve_command(
    host: Optional[str] = typer.Option(
        None, help="Address to listen on: without --class a loopback address (this machine only), with --class "
        "any. (default: 127.0.0.1; with --class 0.0.0.0, every interface)", show_default=False),
    classroom: bool = typer.Option(
        False, "--class", help="Classroom mode: serve the class on the local network. Prints the address students "
        "open, a join code and a teacher token; every page, API route and the UI need the code, teacher actions "
        "the token (docs/teaching/classroom.md)."),
    address: Optional[str] = typer.Option(
        None, help="With --class: the address students open, printed and in the home page's QR code. (default: "
        "this machine's address on the local network)", show_default=False),
    join_code: Optional[str] = typer.Option(
        None, help="With --class: the join code (4 to 32 letters and digits), to keep a class's code across "
        "restarts. (default: a new random 6-character code)", show_default=False),
    executor: Optional[str] = typer.Option(
        None, "--executor", help="With --class: where the queue's runs play their games: local (this machine, one "
        "run per core) or ray (a Ray cluster, one run per CPU; the lab's machines need soccer-lab installed). "
        "(default: local)", show_default=False),
    ray_address: Optional[str] = typer.Option(
        None, "--ray-address", help="With --executor ray: the cluster's address (e.g. 10.0.0.5:6379; --address is "
        "the class's). (default: start Ray here)", show_default=False),
    port: int = typer.Option(DEFAULT_PORT, help="Port of the app: the home page, the UI's page, the JSON API, "
                             "its docs and rerun's web viewer.", **PORT_RANGE),
    ui_port: int = typer.Option(DEFAULT_UI_PORT, help="Port of the UI's websocket (viser).", **PORT_RANGE),
    data_dir: Optional[Path] = typer.Option(
        None, help="Folder of the database and the runs' files. (default: $SOCCER_LAB_DATA, else "
        "$XDG_DATA_HOME/soccer-lab, else ~/.local/share/soccer-lab)", show_default=False
    ),
    trusted_proxy: Optional[str] = typer.Option(
        None, help="The address of a reverse proxy in front of the app: its X-Forwarded-For header then names the "
        "visitor (rate limits are per visitor). (default: none; the header is ignored)", show_default=False),
    rcssserver: Optional[Path] = typer.Option(
        None, help="The rcssserver executable that runs on rcssserver start their servers from (each run its "
        "own, stopped when it ends). (default: $RCSSSERVER, else rcssserver on PATH)", show_default=False
    ),
) -> None:
    """Start the UI, the JSON API and the rerun viewer, and print their addresses (with --class: for a class on
    the local network)."""
    if not classroom and (address is not None or join_code is not None):
        fail("--address and --join-code are for classroom mode: add --class")
    if join_code is not None and not (4 <= len(join_code) <= 32 and join_code.isascii() and join_code.isalnum()):
        fail("--join-code: 4 to 32 letters and digits")
    if not classroom and host is not None and not _loopback(host):
        fail(f"--host {host}: without --class the app serves this machine only (127.0.0.1, ::1 or localhost); on "
             "the network it needs classroom mode's join code and teacher token: add --class")
    if executor not in (None, LOCAL, RAY):
        fail(f"--executor: unknown executor {executor!r}; choose one of {', '.join(EXECUTOR_NAMES)}")
    if executor is not None and not classroom:
        fail("--executor places classroom mode's queue of runs: add --class")
    if ray_address is not None and executor != RAY:
        fail("--ray-address needs --executor ray")
    host = host if host is not None else (CLASS_HOST if classroom else DEFAULT_HOST)
    if trusted_proxy is not None and not _ip_address(trusted_proxy):
        fail(f"--trusted-proxy {trusted_proxy}: an IP address (the proxy's, e.g. 127.0.0.1)")
    if rcssserver is not None:
        from soccer_lab.soccer.rcss.servers import RcssLaunchError, find_rcssserver

        try:
            rcssserver = find_rcssserver(rcssserver)
        except RcssLaunchError as exc:
            fail(f"--rcssserver: {exc}")
    options = ServeOptions(host, port, ui_port, data_dir or default_data_dir(), rcssserver,
                           classroom=classroom, address=address,
                           join_code=join_code.upper() if join_code is not None else None,
                           ray=executor == RAY, ray_address=ray_address, trusted_proxy=trusted_proxy)
    try:
        serve(options, echo=typer.echo)
    except (ServeError, StoreError) as exc:
        fail(str(exc))
    except KeyboardInterrupt:
        typer.echo("stopped")
    _exit_now()


def _ip_address(text: str) -> bool:
    try:
        ipaddress.ip_address(text)
        return True
    except ValueError:
        return False


def _loopback(host: str) -> bool:
    """Whether `host` is this machine only: a loopback address or the name localhost."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:  # another name: it may resolve to a network interface
        return False


def _exit_now() -> None:
    """End the process now: serve has closed all it opened (runs marked interrupted, the store, the UI, the
    viewer), and the interpreter's own teardown of the loaded libraries (numba's kernels, rerun's runtime)
    took 2-3 s more, past the 3 s within which serve must exit."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
