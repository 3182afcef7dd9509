"""This checkout built into a wheel and installed, with the package index's `fuzzy`, into a folder of its own
(once per test session): what a user who runs `pip install soccer-lab` gets, not the editable install the
tests otherwise run."""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[1]
INDEX_FUZZY = "fuzzy==1.2.2"  # the package index's phonetic-algorithms `fuzzy`, whose name ours must not take


@dataclass(frozen=True)
class InstalledWheel:
    wheel: Path
    folder: Path  # what `pip install --target` filled: soccer_lab/, its dist-info, bin/soccer-lab
    index_fuzzy: str | None  # why the index's fuzzy is missing, or None when it is installed beside ours

    @property
    def command(self) -> Path:
        return self.folder / "bin" / "soccer-lab"


def pip(*arguments: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pip", *arguments], capture_output=True, text=True, timeout=900)


def install(scratch: Path) -> InstalledWheel:
    """Build the wheel (in pip's own isolated build, as a release is built) and install it, without its
    dependencies (the test environment has them), with the index's `fuzzy` beside it."""
    # setuptools builds in the checkout's build/ and never empties it: a module moved since the last build would
    # ride along in the wheel (build/ is git-ignored output, made again here)
    shutil.rmtree(REPOSITORY / "build", ignore_errors=True)
    built = pip("wheel", "--no-deps", "--wheel-dir", str(scratch / "dist"), str(REPOSITORY))
    if built.returncode:
        raise RuntimeError(f"building the wheel failed:\n{built.stdout}\n{built.stderr}")
    wheel = Path(glob.glob(str(scratch / "dist" / "soccer_lab-*.whl"))[0])
    folder = scratch / "site"
    installed = pip("install", "--no-deps", "--target", str(folder), str(wheel))
    if installed.returncode:
        raise RuntimeError(f"installing the wheel failed:\n{installed.stdout}\n{installed.stderr}")
    index = pip("install", "--no-deps", "--target", str(folder), INDEX_FUZZY)
    missing = None if index.returncode == 0 else (index.stderr.strip().splitlines() or ["pip failed"])[-1]
    return InstalledWheel(wheel, folder, missing)


def wheel_environment(installed: InstalledWheel, **extra: str) -> dict[str, str]:
    """An environment whose `soccer_lab` is the installed wheel's: its folder first on the path (before the
    editable install's finder, which Python consults after the path), its bin/ first on PATH."""
    return dict(os.environ, PYTHONPATH=str(installed.folder),
                PATH=f"{installed.folder / 'bin'}{os.pathsep}{Path(sys.executable).parent}{os.pathsep}"
                     f"{os.environ.get('PATH', '')}", **extra)
