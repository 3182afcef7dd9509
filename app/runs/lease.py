"""A run's lease: one process plays a run at a time, whichever plays it (a serve, `soccer-lab evolve`, the
Python API). Without it `evolve --resume` on a run a serve was playing ran it a second time, both writing
its folder."""

from __future__ import annotations

import sys
from pathlib import Path

from soccer_lab.app.paths import DataFolderLock

LEASE_FILE = "run.lock"  # in the run folder: locked (flock) while a process plays the run, with its PID


class RunLease(DataFolderLock):
    """The run folder's LEASE_FILE locked while the run plays (DataFolderInUse when another process plays it).
    The kernel releases it when the process ends, SIGKILL included: a killed run is resumable at once."""

    FILE = LEASE_FILE

    def __init__(self, folder: Path):
        super().__init__(folder, address="", command=_command())

    def refusal(self, folder: Path, holder: str) -> str:
        return f"the run in {folder} is being played by {holder}: stop it there first"


def _command() -> str:
    """What plays the run, for the refusal: "serve", "evolve" (the CLI's subcommand), else "Python"."""
    named = [argument for argument in sys.argv[1:] if argument in ("serve", "evolve", "experiment")]
    return named[0] if named else "Python"
