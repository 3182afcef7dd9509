"""The docs site builds with `mkdocs build --strict` (a broken link, a missing page or a page left out of the
nav fails), its generated reference pages hold what they are generated from, it fetches nothing from the
internet, the commands its ```console examples show give the output they show, and its ```pycon (Python)
examples too."""

from __future__ import annotations

import doctest
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from tests.wheel_install import wheel_environment

REPOSITORY = Path(__file__).resolve().parents[2]
DOCUMENTS = sorted((REPOSITORY / "docs").rglob("*.md")) + [REPOSITORY / "README.md"]
CONSOLE_BLOCK = re.compile(r"^```console\n(.*?)^```", re.MULTILINE | re.DOTALL)
# A reference page's generated block (docs/hooks/generated_block.py) shows usage lines, not examples to run
GENERATED_BLOCK = re.compile(r"<!-- generated: (\w+) -->.*?<!-- end of generated: \1 -->", re.DOTALL)
PYCON_BLOCK = re.compile(r"^```pycon\n(.*?)^```", re.MULTILINE | re.DOTALL)
EXTERNAL_ASSET = re.compile(r"<(?:script|link|img)\b[^>]*\b(?:src|href)=\"(?:https?:)?//", re.IGNORECASE)
pytest.importorskip("mkdocs", reason="mkdocs is not installed: pip install -e '.[test]' (scripts/test does)")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("site")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(folder)],
                          cwd=REPOSITORY, capture_output=True, text=True, timeout=900,
                          env=dict(os.environ, NO_MKDOCS_2_WARNING="1"))  # material's notice about its successor
    assert done.returncode == 0, done.stdout + done.stderr
    return folder


def page(site: Path, path: str) -> str:
    return (site / path / "index.html").read_text(encoding="utf-8")


def test_the_cli_reference_lists_every_command_and_option(site):
    import typer.main

    from soccer_lab.app.cli import COMMANDS, app

    shown = page(site, "reference/cli")
    root = typer.main.get_command(app)
    for name in COMMANDS:
        assert f"soccer-lab {name}" in shown
        command = root.get_command(None, name)
        for param in command.params:
            for option in param.opts:
                if option.startswith("--"):
                    assert option in shown, f"{option} of {name} is missing"


def test_the_api_reference_lists_every_route_of_the_app(site):
    from soccer_lab.app.web.api import create_app

    shown = page(site, "reference/api")
    for path in create_app(None, None).openapi()["paths"]:
        assert path in shown, path


def test_the_vocabulary_reference_has_every_term_with_its_parameters(site):
    from soccer_lab.fuzzy.vocabulary import Vocabulary

    shown = page(site, "reference/vocabulary")
    vocabulary = Vocabulary.default()
    for variable in vocabulary.variables.values():
        for term in variable.terms:
            assert f"<td>{vocabulary.display(term.name)}</td>" in shown, term.name


def test_the_site_fetches_nothing_from_the_internet(site):
    for html in site.rglob("*.html"):
        text = html.read_text(encoding="utf-8")
        assert not EXTERNAL_ASSET.search(text), f"{html.relative_to(site)} loads {EXTERNAL_ASSET.search(text)[0]}"
        assert "fonts.googleapis" not in text


# ---- the console examples -------------------------------------------------------------------------------------
def console_examples() -> list:
    examples = []
    for document in DOCUMENTS:
        text = GENERATED_BLOCK.sub("", document.read_text(encoding="utf-8"))
        for number, block in enumerate(CONSOLE_BLOCK.findall(text), start=1):
            name = f"{document.relative_to(REPOSITORY)}#{number}"
            examples.append(pytest.param(block, id=name))
    return examples


def steps(block: str) -> list[tuple[str, list[str]]]:
    """`$ command` lines and the output lines shown after each."""
    found: list[tuple[str, list[str]]] = []
    for line in block.splitlines():
        if line.startswith("$ "):
            found.append((line[2:], []))
        elif found:
            found[-1][1].append(line)
    return found


def matches(expected: list[str], actual: str) -> bool:
    """The output shown, where a line `...` stands for any lines (none included)."""
    pattern = "".join(r"(?:.*\n)*?" if line == "..." else re.escape(line.rstrip()) + r"\n" for line in expected)
    text = "".join(line.rstrip() + "\n" for line in actual.splitlines())
    return re.fullmatch(pattern, text) is not None


@pytest.fixture
def scratch(tmp_path) -> Path:
    """A folder that looks like the repository's (its files are there) but keeps what the commands write."""
    for entry in REPOSITORY.iterdir():
        # not the folders commands write into (git ignores them): a run of the checkout's must not be in the way
        if not entry.name.startswith(".") and entry.name not in ("runs", "experiments"):
            (tmp_path / entry.name).symlink_to(entry)
    return tmp_path


@pytest.mark.parametrize("block", console_examples())
def test_console_example_prints_what_it_shows(block, scratch, installed_wheel):
    """Run against the installed wheel (tests/wheel_install.py), as a user who installed soccer-lab runs them."""
    environment = wheel_environment(installed_wheel, COLUMNS="80", SOCCER_LAB_DATA=str(scratch / "data"))
    for command, expected in steps(block):
        program = command.split()[0]
        if program not in ("printf", "echo", "cat") and shutil.which(program, path=environment["PATH"]) is None:
            pytest.skip(f"{program} is not installed (scripts/test installs fuzzylite with apt)")
        done = subprocess.run(command, shell=True, cwd=scratch, env=environment, capture_output=True, text=True,
                              timeout=600)
        shown = done.stdout + done.stderr
        assert matches(expected, shown), f"$ {command}\nshown in the docs:\n" + "\n".join(expected) + \
            f"\nprinted:\n{shown}"


# ---- the Python examples --------------------------------------------------------------------------------------
def pycon_pages() -> list:
    return [pytest.param(document, id=str(document.relative_to(REPOSITORY))) for document in DOCUMENTS
            if PYCON_BLOCK.search(document.read_text(encoding="utf-8"))]


def pycon_only(page: str) -> str:
    """The page with every line outside its ```pycon blocks blanked: a failure names the page's own line."""
    inside, lines = False, []
    for line in page.splitlines():
        fence = line.startswith("```")
        lines.append(line if inside and not fence else "")
        if fence:
            inside = line.strip() == "```pycon"
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("document", pycon_pages())
def test_python_examples_print_what_they_show(document, scratch, monkeypatch):
    """A page's ```pycon blocks run in order, in one namespace, as doctests (`...` in an output stands for
    any text), in a scratch copy of the repository's folder (a command they run is the venv's)."""
    monkeypatch.chdir(scratch)
    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    monkeypatch.setenv("SOCCER_LAB_DATA", str(scratch / "data"))
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))  # the runs made without a folder
    name = str(document.relative_to(REPOSITORY))
    test = doctest.DocTestParser().get_doctest(pycon_only(document.read_text(encoding="utf-8")), {}, name, name, 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    report: list[str] = []
    runner.run(test, out=report.append)
    assert runner.failures == 0, "".join(report)


def test_no_page_speaks_of_the_projects_issues():
    """A reader of the docs has never seen the project's issue tracker: a page says what and why, not which issue
    asked for it (issue 37 found "the issue this answers" on the replicates page)."""
    spoken = [f"{document.relative_to(REPOSITORY)}: {line.strip()[:80]}" for document in DOCUMENTS
              for line in document.read_text(encoding="utf-8").splitlines()
              if re.search(r"\b(?:the )?issues? (?:\d+|this answers)\b", line, re.IGNORECASE)]
    assert spoken == []
