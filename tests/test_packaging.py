"""Installed, soccer-lab is one package, `soccer_lab`: no generic top-level name (`app`, `fuzzy`, `ga`, `soccer`,
`static`) lands in site-packages, so it installs beside the package index's `fuzzy` (phonetic algorithms) and
both import. The wheel is built from this checkout and installed into a folder of its own
(tests/wheel_install.py); the docs' console examples run against the same install (tests/docs)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import PurePosixPath

import pytest

from tests.wheel_install import REPOSITORY, wheel_environment


def test_the_wheel_holds_one_top_level_package_with_every_part_inside(installed_wheel):
    with zipfile.ZipFile(installed_wheel.wheel) as archive:
        files = set(archive.namelist())
    top = {PurePosixPath(name).parts[0] for name in files}
    assert {name for name in top if not name.endswith(".dist-info")} == {"soccer_lab"}
    for inside in ("soccer_lab/__init__.py", "soccer_lab/fuzzy/data/soccer_vocabulary.json",
                   "soccer_lab/ga/algorithms.py", "soccer_lab/soccer/data/examples/demo.rules",
                   "soccer_lab/soccer/gym/env.py", "soccer_lab/app/cli/__init__.py",
                   "soccer_lab/app/web/server.py", "soccer_lab/static/index.html", "soccer_lab/static/join.html"):
        assert inside in files, inside


def test_soccer_lab_installs_beside_the_package_index_fuzzy_and_both_import(installed_wheel):
    if installed_wheel.index_fuzzy is not None:
        pytest.skip(f"the package index's fuzzy did not install here ({installed_wheel.index_fuzzy}): it is built "
                    "from source and needs a C compiler and the package index")
    script = ("import fuzzy, soccer_lab as sl\n"
              "print(fuzzy.__file__); print(sl.__file__)\n"
              "print(fuzzy.DMetaphone()('soccer')[0].decode())\n"
              "print(len(sl.parse_rules('if Ball is Near then Dash High')))\n")
    done = subprocess.run([sys.executable, "-c", script], env=wheel_environment(installed_wheel),
                          capture_output=True, text=True, timeout=300, cwd=installed_wheel.folder.parent)
    assert done.returncode == 0, done.stderr
    index_fuzzy, ours, metaphone, rules = done.stdout.split()
    assert index_fuzzy.startswith(str(installed_wheel.folder)) and index_fuzzy.endswith(".so")
    assert ours == str(installed_wheel.folder / "soccer_lab" / "__init__.py")
    assert (metaphone, rules) == ("SXR", "1")  # its Double Metaphone of 'soccer'


def test_the_installed_command_plays_evolves_and_exports_from_the_wheel(installed_wheel, tmp_path):
    environment = wheel_environment(installed_wheel, SOCCER_LAB_DATA=str(tmp_path / "data"))
    demo = installed_wheel.folder / "soccer_lab" / "soccer" / "data" / "examples" / "demo.rules"

    def soccer_lab(*arguments: str) -> str:
        done = subprocess.run([str(installed_wheel.command), *arguments], env=environment, capture_output=True,
                              text=True, timeout=600, cwd=tmp_path)
        assert done.returncode == 0, f"soccer-lab {' '.join(arguments)}\n{done.stdout}\n{done.stderr}"
        return done.stdout

    assert "Evolve, inspect and teach" in soccer_lab("--help")
    assert "goal" in soccer_lab("play", str(demo), "--games", "2", "--seed", "3")
    soccer_lab("evolve", "--population-size", "6", "--generations", "2", "--max-ticks", "200", "--seed", "1",
               "--workers", "1", "--out", str(tmp_path / "run"))
    assert (tmp_path / "run" / "best.rules").is_file()
    assert "FUNCTION_BLOCK" in soccer_lab("rules", "export", str(demo), "--format", "fcl")
    where = subprocess.run([sys.executable, "-c", "import soccer_lab.app.cli as cli; print(cli.__file__)"],
                           env=environment, capture_output=True, text=True, timeout=120, cwd=tmp_path).stdout.strip()
    assert where.startswith(str(installed_wheel.folder)), where


def test_the_editable_install_puts_no_generic_name_on_the_path(tmp_path):
    """`pip install -e .` (the tests' own install) maps the folders into soccer_lab too: outside the checkout,
    `import fuzzy` or `import app` finds nothing of ours (the probe: five generic names, `import app` meaning
    whatever came first on the path)."""
    script = ("import importlib.util, json\n"
              "found = {name: importlib.util.find_spec(name) for name in ('app', 'fuzzy', 'ga', 'soccer', 'static')}\n"
              "print(json.dumps({name: spec and spec.origin for name, spec in found.items()}))\n"
              "import soccer_lab.fuzzy.engine, soccer_lab.app.cli; print(soccer_lab.fuzzy.engine.__file__)\n")
    environment = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    done = subprocess.run([sys.executable, "-c", script], env=environment, capture_output=True, text=True,
                          timeout=120, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    generic, engine = done.stdout.splitlines()
    ours = [name for name, origin in json.loads(generic).items() if origin and origin.startswith(str(REPOSITORY))]
    assert not ours, ours
    assert engine == str(REPOSITORY / "fuzzy" / "engine.py")
