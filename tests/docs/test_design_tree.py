"""docs/design.md's picture of the house is the real tree: the package's parts, every folder of app/ with every
module in it named, app/'s loose modules exactly, and no name the tree does not have (the picture drawn for
issue 38 had fallen behind: app/words.py, seven modules of runs/, web/ and experiment/ were missing)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PARTS = ("fuzzy", "ga", "soccer", "app", "static")  # setup.py's FOLDERS: soccer_lab.<part> once installed
ROW = re.compile(r"^(?P<indent>(?:[│ ]   )*)[├└]── (?P<rest>.*)$")


def picture() -> list[str]:
    text = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    house = text[text.index("## The house"):]
    block = house[house.index("```\n") + 4:]
    return block[:block.index("```")].splitlines()


def rows() -> dict[tuple[int, str], str]:
    """(depth, name) -> what the row says, its continuation lines joined: depth 0 is soccer_lab/ itself. A
    folder's row says what is in it after its name; the row of app's loose modules is their list."""
    lines = picture()
    drawn = {(0, lines[0].split()[0]): lines[0].partition(" ")[2]}
    last = None
    for line in lines[1:]:
        match = ROW.match(line)
        if match:
            depth = len(match["indent"]) // 4 + 1
            name = match["rest"].split()[0]
            last = (depth, name.rstrip(","))
            drawn[last] = match["rest"].partition(" ")[2] if name.endswith("/") else match["rest"]
        else:
            drawn[last] += " " + line.strip("│ ")
    return drawn


def modules(folder: Path) -> set[str]:
    return {path.stem for path in folder.glob("*.py") if path.name != "__init__.py"}


def packages(folder: Path) -> set[str]:
    return {path.name for path in folder.iterdir() if (path / "__init__.py").is_file()}


def words(text: str) -> set[str]:
    return set(re.findall(r"[A-Za-z_]+", text))


def named(text: str, suffix: str) -> set[str]:
    return set(re.findall(r"([A-Za-z_]+)" + re.escape(suffix), text))


def test_the_picture_draws_the_package_and_its_parts():
    drawn = rows()
    assert (0, "soccer_lab/") in drawn
    assert modules(ROOT / "soccer_lab") <= words(drawn[0, "soccer_lab/"])
    assert {name for depth, name in drawn if depth == 1} == {f"{part}/" for part in PARTS}


def test_the_picture_names_each_parts_subpackages_and_only_real_ones():
    drawn = rows()
    for part in ("fuzzy", "ga", "soccer"):
        row = drawn[1, f"{part}/"]
        assert named(row, "/") == packages(ROOT / part), part


def test_the_picture_draws_every_folder_of_app_and_its_loose_modules_exactly():
    drawn = rows()
    app = ROOT / "app"
    folders = {name.rstrip("/") for depth, name in drawn if depth == 2 and name.endswith("/")}
    assert folders == packages(app)
    loose = [text for (depth, name), text in drawn.items() if depth == 2 and not name.endswith("/")]
    assert len(loose) == 1 and named(loose[0], ".py") == modules(app)


def test_each_app_folder_row_names_every_module_in_it_and_no_other():
    drawn = rows()
    for folder in packages(ROOT / "app"):
        row = drawn[2, f"{folder}/"]
        real = ROOT / "app" / folder
        assert modules(real) <= words(row), (folder, sorted(modules(real) - words(row)))
        assert named(row, ".py") <= modules(real), (folder, sorted(named(row, ".py") - modules(real)))
        assert named(row, "/") == packages(real), folder
