"""Where soccer-lab keeps its data (the SQLite store, the runs' recordings and checkpoints) and its cache (files
made again when lost, such as rerun's web viewer)."""

from __future__ import annotations

import fcntl
import json
import os
from pathlib import Path

DATA_DIR_VARIABLE = "SOCCER_LAB_DATA"
APP_FOLDER = "soccer-lab"
DATABASE_FILE = "soccer-lab.sqlite3"
RUNS_FOLDER = "runs"


def default_data_dir() -> Path:
    """$SOCCER_LAB_DATA, else $XDG_DATA_HOME/soccer-lab, else ~/.local/share/soccer-lab."""
    explicit = os.environ.get(DATA_DIR_VARIABLE)
    if explicit:
        return Path(explicit).expanduser()
    xdg = os.environ.get("XDG_DATA_HOME")
    base = Path(xdg).expanduser() if xdg else Path.home() / ".local" / "share"
    return base / APP_FOLDER


def default_cache_dir() -> Path:
    """$XDG_CACHE_HOME/soccer-lab, else ~/.cache/soccer-lab: shared by every data folder on this machine."""
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg).expanduser() if xdg else Path.home() / ".cache"
    return base / APP_FOLDER


LOCK_FILE = "soccer-lab.lock"  # in the data folder: locked (flock) by the serve using it, with its PID and address


class DataFolderInUse(RuntimeError):
    """Another process holds the data folder: one line naming it (PID, address)."""


class DataFolderLock:
    """An exclusive OS lock (flock) on the data folder's LOCK_FILE, held while this object is open: one serve
    per folder, so no second one marks the first one's running runs interrupted and runs them again. The
    kernel releases it when the process ends, however it ends (SIGKILL included): a folder whose server was
    killed is usable at once. The file says who holds it, for the refusal's message."""

    FILE = LOCK_FILE

    def __init__(self, folder: Path, address: str, command: str = "serve"):
        self.path = Path(folder) / self.FILE
        self._fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)  # not inherited by programs we start
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = self._holder()
            os.close(self._fd)
            raise DataFolderInUse(self.refusal(Path(folder).resolve(), holder)) from None
        except OSError:
            os.close(self._fd)
            raise
        os.ftruncate(self._fd, 0)
        os.pwrite(self._fd, json.dumps({"pid": os.getpid(), "address": address, "command": command}).encode(), 0)

    def refusal(self, folder: Path, holder: str) -> str:
        return f"the data folder {folder} is in use by {holder}: stop it, or choose another folder with --data-dir"

    def _holder(self) -> str:
        """Who holds the lock, as its file says (a holder still writing it is named vaguely)."""
        try:
            info = json.loads(os.pread(self._fd, 4096, 0) or b"{}")
            where = f", {info['address']}" if info["address"] else ""
            return f"soccer-lab {info['command']} (PID {int(info['pid'])}{where})"
        except (ValueError, KeyError, TypeError, OSError):
            return "another soccer-lab process"

    def release(self) -> None:
        if self._fd >= 0:
            os.close(self._fd)  # closing the only descriptor releases the lock
            self._fd = -1

    def __enter__(self) -> "DataFolderLock":
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.release()
