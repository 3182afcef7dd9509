"""Every command the README and the research and inspection guides show in ```bash blocks runs when pasted
into an environment where soccer-lab is installed from its wheel (tests/wheel_install.py: what `pip install`
gives, not the editable install, whose folders sit on the path by accident of the working directory), its
`soccer-lab` first on the PATH as the README's `source .venv/bin/activate` leaves it, in the order shown, shrunk where long: an evolution to a few small generations, an
experiment to two tiny trials per setting. Commands that need what a test machine lacks (a real
rcssserver, a Ray cluster, a server left running) and synopsis lines (FILE, [options]) are not run."""

from __future__ import annotations

import re
import shlex
import subprocess
from pathlib import Path

import pytest

from tests.wheel_install import wheel_environment

REPOSITORY = Path(__file__).resolve().parents[2]
DOCUMENTS = ["README.md", "docs/research/index.md", "docs/research/matches.md", "docs/inspecting/index.md"]
BASH_BLOCK = re.compile(r"^```bash\n(.*?)^```", re.MULTILINE | re.DOTALL)
SYNOPSIS = re.compile(r"\bFILE\b|\bPRESET\b|\[|\||\.\.\.|/path/to|~/")
NOT_HERE = ("serve", "--env rcss", "robocup", "transfer", "--executor", "./scripts/test")
# option -> shrunk value, per command: a long run shrunk to seconds, with the same meaning
SHRINK = {
    "evolve": {"--population-size": "6", "--generations": "2", "--max-ticks": "60", "--workers": "1"},
    "random-search": {"--population-size": "6", "--generations": "2", "--max-ticks": "60", "--workers": "1"},
    "experiment": {"--trials": "2", "--population": "4", "--generations": "2", "--max-ticks": "60",
                   "--replays": "2", "--workers": "1"},
    "usage": {"--games": "2", "--max-ticks": "60"},
    "simplify": {"--games": "2", "--max-ticks": "60"},
}
SHRUNK_REPLICATES = "2"


def commands(document: str) -> list[str]:
    text = (REPOSITORY / document).read_text(encoding="utf-8")
    lines = [line.split(" #")[0].strip() for block in BASH_BLOCK.findall(text) for line in block.splitlines()]
    return [line for line in lines if line.startswith("soccer-lab ") and not SYNOPSIS.search(line)
            and not any(part in line for part in NOT_HERE)]


def shrunk(command: str) -> str:
    words = shlex.split(command)
    subcommand = next((w for w in words[1:] if w in SHRINK), None)
    if subcommand is None or "--resume" in words:
        return command
    options = dict(SHRINK[subcommand])
    if "--replicates" in words:
        options["--replicates"] = SHRUNK_REPLICATES
    for option, value in options.items():
        if option in words:
            words[words.index(option) + 1] = value
        else:
            words += [option, value]
    return shlex.join(words)


def test_the_readme_set_up_puts_soccer_lab_on_the_path():
    readme = (REPOSITORY / "README.md").read_text(encoding="utf-8")
    assert "source .venv/bin/activate" in readme.split("## A 5-minute tour")[0]


@pytest.mark.parametrize("document", DOCUMENTS)
def test_every_command_shown_runs_as_written(document, tmp_path, installed_wheel):
    for entry in REPOSITORY.iterdir():  # the checkout's files, but what the commands write stays here
        if not entry.name.startswith(".") and entry.name not in ("runs", "experiments"):
            (tmp_path / entry.name).symlink_to(entry)
    environment = wheel_environment(installed_wheel, SOCCER_LAB_DATA=str(tmp_path / "data"))
    shown = commands(document)
    assert shown, f"{document} shows no command to run"
    for command in shown:
        done = subprocess.run(shrunk(command), shell=True, cwd=tmp_path, env=environment, capture_output=True,
                              text=True, timeout=900)
        assert done.returncode == 0, f"{document}: {command}\n(ran as: {shrunk(command)})\n{done.stdout}{done.stderr}"
