"""Copy the figures of a RoboCup study's folder into the docs (docs/images/robocup/), for the RoboCup guide.

    .venv/bin/python scripts/robocup_figures.py EXPERIMENT_FOLDER

The folder is one `soccer-lab experiment robocup` (Figs. 8-10: figures/robocup-*.png) and, run into the same
folder, `soccer-lab experiment transfer` (figures/transfer-*.png) wrote. The docs show exactly these files:
they are never drawn or edited by hand. Prints what it copied; exit status 2 when the folder has neither.
"""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path

DOCS_IMAGES = Path(__file__).resolve().parent.parent / "docs" / "images" / "robocup"
PATTERNS = ("robocup-*.png", "transfer-*.png")


def copy_figures(folder: Path, target: Path = DOCS_IMAGES) -> list[Path]:
    figures = sorted(path for pattern in PATTERNS for path in (folder / "figures").glob(pattern))
    target.mkdir(parents=True, exist_ok=True)
    for figure in figures:
        shutil.copyfile(figure, target / figure.name)
    return [target / figure.name for figure in figures]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the experiment folder (its figures/ holds the PNGs)")
    args = parser.parse_args()
    copied = copy_figures(args.folder)
    if not copied:
        print(f"error: no robocup or transfer figures in {args.folder / 'figures'}", file=sys.stderr)
        raise SystemExit(2)
    for path in copied:
        print(f"copied {path.name} -> {path.parent}")


if __name__ == "__main__":
    main()
