"""What the API may serve from a folder: a regular file inside it, reached without a symbolic link.

A symbolic link in a run folder (run.rrd -> /etc/passwd) or the folder itself swapped for a link must not
make the API serve a file from elsewhere; nor may a fifo or a device stand in for a file.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path


def regular_file_inside(folder: str | Path, name: str) -> Path | None:
    """folder/name when it is a regular file (not a link) directly inside `folder` (not a link either: where
    the data folder itself lies is the user's choice); None otherwise."""
    folder = Path(folder)
    path = folder / name
    if "/" in name or name in ("", ".", ".."):
        return None
    try:
        if folder.is_symlink():
            return None
        mode = os.lstat(path).st_mode
    except (OSError, RuntimeError):
        return None
    return path if stat.S_ISREG(mode) else None
