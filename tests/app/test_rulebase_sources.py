"""One rulebase file for every tool: a run's best (rule text and JSON), an experiment trial's best (and one
written before it carried the rulebase JSON), a library export and a lineage ancestor each open in
`rules usage|simplify|export|check|infer` and `play` (an experiment's best once failed with "format:
expected 'soccer-lab-rulebase', found null")."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.presets import ExperimentOptions
from soccer_lab.app.experiment.runner import run_experiment
from soccer_lab.app.rulebase_files import load_rulebase
from tests.app.api_client import api_client

GAME = ["--max-ticks", "60"]
TOOLS = {
    "usage": ["rules", "usage", "{file}", "--games", "2", *GAME],
    "simplify": ["rules", "simplify", "{file}", "-o", "{out}.rules"],
    "export": ["rules", "export", "{file}", "--format", "fll", "-o", "{out}.fll"],
    "check": ["rules", "check", "{file}"],
    "infer": ["rules", "infer", "{file}", "--input", "ball_distance=3.5", "--input", "ball_direction=-20"],
    "play": ["play", "{file}", "--games", "1", *GAME],
}


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture(scope="module")
def sources(tmp_path_factory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("sources")
    evolved = run("evolve", "--population-size", "6", "--generations", "2", *GAME, "--workers", "1", "--seed", "3",
                  "--out", root / "run")
    assert evolved.exit_code == 0, evolved.output
    assert run("lineage", root / "run", "--generation", "0", "--index", "1", "--rules", root / "ancestor.rules",
               ).exit_code == 0
    assert run("lineage", root / "run", "--rules", root / "ancestor.json").exit_code == 0
    options = ExperimentOptions(trials=2, population=6, generations=2, max_ticks=60, replays=3, seed=7)
    run_experiment("initial", options, root / "experiment", LocalExecutor(1))
    trial_best = sorted((root / "experiment" / "trials").glob("*.best.json"))[0]
    legacy = root / "legacy.best.json"  # an experiment folder from before: the rules as text, no format
    record = json.loads(trial_best.read_text())
    legacy.write_text(json.dumps({"generation": record["generation"], "fitness_seen": record["fitness_seen"],
                                  "chromosome": record["chromosome"], "rules": record["rule_text"]}))
    with api_client(root / "app") as client:
        saved = client.post("/api/rulebases", json={"name": "best", "text": (root / "run" / "best.rules").read_text()})
        exported = client.get(f"/api/rulebases/{saved.json()['id']}/export", params={"format": "json"})
    (root / "library.json").write_text(exported.text)
    return {"run best.rules": root / "run" / "best.rules", "run best.json": root / "run" / "best.json",
            "experiment best": trial_best, "experiment best, older folder": legacy,
            "library export": root / "library.json", "lineage ancestor": root / "ancestor.rules",
            "lineage ancestor as JSON": root / "ancestor.json"}


@pytest.mark.parametrize("tool", TOOLS)
def test_every_saved_player_opens_in_every_tool(sources, tool, tmp_path):
    for name, path in sources.items():
        args = [part.format(file=path, out=tmp_path / name.replace(" ", "_")) for part in TOOLS[tool]]
        result = run(*args)
        assert result.exit_code == 0, f"{name}: soccer-lab {' '.join(args)}\n{result.output}"


def test_an_experiments_best_is_the_player_its_figures_describe(sources):
    record = json.loads(sources["experiment best"].read_text())
    from soccer_lab.fuzzy.printer import format_rulebase
    from soccer_lab.soccer.config import SOCCER_VOCABULARY

    assert format_rulebase(load_rulebase(sources["experiment best"]), SOCCER_VOCABULARY) == record["rule_text"]
    assert load_rulebase(sources["experiment best, older folder"]) == load_rulebase(sources["experiment best"])
    assert {"fitness_seen", "replays", "replay_fitness", "replay_fitness_std"} <= set(record)
