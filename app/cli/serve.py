"""`soccer-lab serve`: the browser app (UI, JSON API, rerun viewer) on this machine."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Optional

import typer

from app.cli.common import fail
from app.paths import default_data_dir
from app.server import DEFAULT_HOST, DEFAULT_PORT, DEFAULT_UI_PORT, ServeError, ServeOptions, serve
from app.store import StoreError

PORT_RANGE = {"min": 1, "max": 65535}


def serve_command(
    host: str = typer.Option(DEFAULT_HOST, help="Address to listen on (127.0.0.1: this machine only)."),
    port: int = typer.Option(DEFAULT_PORT, help="Port of the app: the home page, the UI's page, the JSON API, "
                             "its docs and rerun's web viewer.", **PORT_RANGE),
    ui_port: int = typer.Option(DEFAULT_UI_PORT, help="Port of the UI's websocket (viser).", **PORT_RANGE),
    data_dir: Optional[Path] = typer.Option(
        None, help="Folder of the database and the runs' files. (default: $SOCCER_LAB_DATA, else "
        "$XDG_DATA_HOME/soccer-lab, else ~/.local/share/soccer-lab)", show_default=False
    ),
    rcssserver: Optional[Path] = typer.Option(
        None, help="The rcssserver executable that runs on rcssserver start their servers from (each run its "
        "own, stopped when it ends). (default: $RCSSSERVER, else rcssserver on PATH)", show_default=False
    ),
) -> None:
    """Start the UI, the JSON API and the rerun viewer, and print their addresses."""
    if rcssserver is not None:
        from soccer.rcss.servers import RcssLaunchError, find_rcssserver

        try:
            rcssserver = find_rcssserver(rcssserver)
        except RcssLaunchError as exc:
            fail(f"--rcssserver: {exc}")
    options = ServeOptions(host, port, ui_port, data_dir or default_data_dir(), rcssserver)
    try:
        serve(options, echo=typer.echo)
    except (ServeError, StoreError) as exc:
        fail(str(exc))
    except KeyboardInterrupt:
        typer.echo("stopped")
    _exit_now()


def _exit_now() -> None:
    """End the process now: serve has closed all it opened (runs marked interrupted, the store, the UI, the
    viewer), and the interpreter's own teardown of the loaded libraries (numba's kernels, rerun's runtime)
    took 2-3 s more, past the 3 s within which serve must exit."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
