"""Where soccer-lab keeps its data (the SQLite store, the runs' recordings and checkpoints) and its cache (files
made again when lost, such as rerun's web viewer)."""

from __future__ import annotations

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
