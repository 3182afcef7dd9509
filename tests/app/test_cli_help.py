"""Every command's --help: shown whole at 80 columns (wrapped, never cut), naming only options the command has,
and cheap (none imports the engine, the app or the plotting: the time itself is benchmarks/cli_help.py's)."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest
import typer.main
from typer.testing import CliRunner

from soccer_lab.app.cli import COMMANDS, app

WIDTH = 80
OPTION = re.compile(r"(?:\b([a-z][a-z-]*) )?(?<![\w-])(--[a-z][a-z0-9-]*)")
HEAVY_MODULES = ("numpy", "numba", "pymunk", "scipy", "matplotlib", "fastapi", "uvicorn", "viser", "rerun", "rich")


def commands() -> dict[tuple[str, ...], object]:
    """Every command of the CLI by its path, the root first: (), ("evolve",), ("rules",), ("rules", "check"), ..."""
    found = {}

    def walk(command, path: tuple[str, ...]) -> None:
        found[path] = command
        context = command.context_class(command, info_name=" ".join(("soccer-lab", *path)))
        for name in getattr(command, "list_commands", lambda _: [])(context):
            walk(command.get_command(context, name), (*path, name))

    walk(typer.main.get_command(app), ())
    return found


COMMAND_PATHS = list(commands())


def options_of(command) -> set[str]:
    return {name for param in command.params for name in (*param.opts, *param.secondary_opts) if name.startswith("--")}


def help_of(path: tuple[str, ...]) -> str:
    result = CliRunner().invoke(app, [*path, "--help"], terminal_width=WIDTH, env={"COLUMNS": str(WIDTH)})
    assert result.exit_code == 0, result.output
    return result.output


def unbroken(text: str) -> str:
    """The text without any whitespace: a wrapped line and the unwrapped one read the same."""
    return "".join(text.split())


def own_texts(command) -> list[str]:
    """Every piece of help a command shows that is its own: its help, its summary, its parameters' help."""
    return [text for text in (command.help, command.short_help, *(getattr(p, "help", None) for p in command.params))
            if text]


@pytest.mark.parametrize("path", COMMAND_PATHS, ids=lambda path: " ".join(path) or "soccer-lab")
def test_help_is_wrapped_to_80_columns_and_never_cut(path):
    command = commands()[path]
    shown = help_of(path)
    too_wide = [line for line in shown.splitlines() if len(line) > WIDTH]
    assert not too_wide, f"lines wider than {WIDTH} columns: {too_wide}"
    assert "…" not in shown
    whole = unbroken(shown)
    for param in command.params:
        shown_names = [param.metavar or param.name] if param.param_type_name == "argument" else param.opts
        for name in (*shown_names, *param.secondary_opts):
            assert re.search(rf"(?<![\w-]){re.escape(name)}(?![\w-])", shown), f"{name} is not shown whole"
        if getattr(param, "help", None):
            assert unbroken(param.help) in whole, f"the help of {param.opts[0]} is cut: {param.help!r}"
    for name in getattr(command, "list_commands", lambda _: [])(None):
        summary = COMMANDS[name].summary if not path else command.get_command(None, name).help.split("\n\n")[0]
        assert unbroken(summary) in whole, f"the summary of {name} is cut"


@pytest.mark.parametrize("path", COMMAND_PATHS, ids=lambda path: " ".join(path) or "soccer-lab")
def test_help_names_only_options_the_command_has(path):
    """An option named in a command's help is its own, or another command's named with it (`evolve --resume`)."""
    everything = commands()
    command = everything[path]
    by_name = {path[-1]: c for path, c in everything.items() if path}
    foreign = []
    for text in own_texts(command):
        for other, option in OPTION.findall(" ".join(text.split())):
            owner = by_name[other] if other in by_name else command
            if option not in options_of(owner) | {"--help"}:
                foreign.append(f"{other} {option}".strip())
    assert not foreign, f"`soccer-lab {' '.join(path)} --help` names options it does not have: {foreign}"


def test_the_root_lists_every_command_with_its_summary():
    shown = help_of(())
    for name, entry in COMMANDS.items():
        assert re.search(rf"^  {re.escape(name)} ", shown, re.MULTILINE), f"{name} is not listed"
        assert commands()[(name,)].short_help == entry.summary


@pytest.mark.parametrize("path", COMMAND_PATHS, ids=lambda path: " ".join(path) or "soccer-lab")
def test_help_imports_none_of_the_heavy_modules(path):
    """A fresh process showing the help: neither numpy nor the engine, app, plotting or progress bars."""
    code = ("import sys\n"
            f"sys.argv = {['soccer-lab', *path, '--help']!r}\n"
            "from soccer_lab.app.cli import main\n"
            "try:\n    main()\nexcept SystemExit:\n    pass\n"
            f"print(' '.join(m for m in {HEAVY_MODULES!r} if m in sys.modules), file=sys.stderr)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stderr.strip() == "", f"--help imported {done.stderr.strip()}"
