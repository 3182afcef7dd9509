"""`import soccer_lab as sl`: the Python API gives what the `soccer-lab` command gives for the same files,
options and seeds (the command run as a real process), refuses bad input with a ValueError or TypeError,
keeps `import soccer_lab` light, and every docstring example runs."""

from __future__ import annotations

import doctest
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import soccer_lab as sl

REPOSITORY = Path(__file__).resolve().parents[1]
STRIKER = REPOSITORY / "soccer" / "data" / "examples" / "striker.rules"
SOCCER_LAB = Path(sys.executable).parent / "soccer-lab"
GAME = {"max_ticks": 300}
# A small run that scores: the API's and the command's must agree on every deterministic figure.
RUN = {"population_size": 8, "generations": 3, "seed": 1, "max_ticks": 300, "workers": 1}


def cli(*args: object, cwd: Path = REPOSITORY) -> str:
    done = subprocess.run([str(SOCCER_LAB), *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def options(values: dict) -> list[str]:
    renamed = {"population_size": "population-size", "max_ticks": "max-ticks"}
    return [part for name, value in values.items() for part in (f"--{renamed.get(name, name)}", value)]


def without_wall_time(statistics: list[dict]) -> list[dict]:
    return [{k: v for k, v in row.items() if k != "wall_time"} for row in statistics]


# ---- import ---------------------------------------------------------------------------------------------
def test_importing_soccer_lab_loads_no_game_engine():
    probe = ("import sys, soccer_lab; print(sorted(m for m in sys.modules if m.split('.')[0] in "
             "('numpy', 'numba', 'pymunk', 'matplotlib', 'rerun')))")
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=REPOSITORY, timeout=120)
    assert done.stdout.strip() == "[]", done.stdout + done.stderr


def test_every_public_name_resolves():
    for name in sl.__all__:
        assert getattr(sl, name) is not None, name
    with pytest.raises(AttributeError):
        sl.no_such_name


# ---- rules ----------------------------------------------------------------------------------------------
def test_load_and_format_print_what_rules_check_prints():
    assert sl.format_rules(sl.load_rules(STRIKER)) + "\n" == cli("rules", "check", STRIKER)


def test_parse_rules_reads_what_format_rules_wrote():
    rules = sl.load_rules(STRIKER)
    assert sl.parse_rules(sl.format_rules(rules)) == rules


def test_load_rules_reads_our_json_as_the_same_rulebase(tmp_path):
    path = tmp_path / "striker.json"
    path.write_text(sl.export(sl.load_rules(STRIKER), "json"))
    assert sl.load_rules(path) == sl.load_rules(STRIKER)


def test_bad_rule_text_and_files_raise_value_errors(tmp_path):
    with pytest.raises(ValueError, match="line 1, column 22"):
        sl.parse_rules("if Ball is Near then Jump")
    with pytest.raises(ValueError, match="no such file"):
        sl.load_rules(tmp_path / "missing.rules")
    (tmp_path / "empty.rules").write_text("# nothing\n")
    with pytest.raises(ValueError, match="holds no rule"):
        sl.load_rules(tmp_path / "empty.rules")
    with pytest.raises(TypeError):
        sl.play(42)


@pytest.mark.parametrize("inputs", [
    {"ball_distance": 3.5, "ball_direction": -20.0},
    {"ball_distance": 0.4, "ball_direction": 0.0, "goal_distance": 20.0, "goal_direction": 5.0},
    {},
])
def test_infer_gives_the_report_rules_infer_prints(inputs):
    printed = json.loads(cli("rules", "infer", STRIKER, *[f"--input={k}={v}" for k, v in inputs.items()]))
    decision = sl.infer(STRIKER, **inputs)
    assert decision.report == printed
    selected = printed["selected"]
    assert decision.action == (selected and selected["action"])
    assert decision.parameters == (selected["parameters"] if selected else {})
    assert decision.strengths == [rule["strength"] for rule in printed["rules"]]


@pytest.mark.parametrize("inputs, problem", [
    ({"ball_speed": 1.0}, "unknown input 'ball_speed'"),
    ({"ball_distance": math.nan, "ball_direction": 0.0}, "finite number"),
    ({"ball_distance": "near", "ball_direction": 0.0}, "finite number"),
    ({"ball_distance": 3.0}, "ball_direction is missing"),
])
def test_infer_refuses_bad_inputs(inputs, problem):
    with pytest.raises(ValueError, match=problem):
        sl.infer(STRIKER, **inputs)


@pytest.mark.parametrize("fmt", sl.EXPORT_FORMATS)
def test_export_gives_the_text_rules_export_prints(fmt):
    assert sl.export(STRIKER, fmt) == cli("rules", "export", STRIKER, "--format", fmt)


def test_export_refuses_an_unknown_format():
    with pytest.raises(ValueError, match="unknown export format"):
        sl.export(STRIKER, "xml")


def test_rule_usage_counts_what_rules_usage_prints():
    from soccer_lab.app.rule_inspection import usage_document
    from soccer_lab.fuzzy.vocabulary import Vocabulary

    printed = json.loads(cli("rules", "usage", STRIKER, "--games", 3, "--seed", 2, "--max-ticks", 300, "--json"))
    usage = sl.rule_usage(STRIKER, games=3, seed=2, **GAME)
    assert usage_document(usage, Vocabulary.default()) == printed


def test_simplify_gives_the_rulebase_rules_simplify_writes(tmp_path):
    written = tmp_path / "simplified.rules"
    cli("rules", "simplify", STRIKER, "--games", 3, "--max-ticks", 300, "--output", written)
    simplified = sl.simplify(STRIKER, games=3, **GAME)
    assert sl.format_rules(simplified.rules) + "\n" == written.read_text()
    assert simplified.original == sl.load_rules(STRIKER)
    assert len(simplified.before) == len(simplified.after) == 3


# ---- play -----------------------------------------------------------------------------------------------
def test_play_gives_each_game_soccer_lab_play_prints():
    printed = cli("play", STRIKER, "--games", 4, "--seed", 7, "--max-ticks", 300).splitlines()
    rows = [line.split() for line in printed[1:-1]]  # between the header and the mean
    games = sl.play(STRIKER, games=4, seed=7, **GAME)
    assert [[str(n), str(g.seed), str(g.goals), str(g.kicks), str(g.ticks), f"{g.fitness:.4f}"]
            for n, g in enumerate(games, start=1)] == rows
    assert any(g.goals for g in games)  # the comparison covers scoring games


def test_play_takes_a_rulebase_or_the_path_of_a_file_as_text_or_path():
    games = sl.play(sl.load_rules(STRIKER), games=2, seed=3, **GAME)
    assert sl.play(str(STRIKER), games=2, seed=3, **GAME) == sl.play(STRIKER, games=2, seed=3, **GAME) == games


def test_play_gives_the_engines_results_with_their_end_reasons():
    from soccer_lab.soccer.config import GameConfig
    from soccer_lab.soccer.engine import play_games

    games = sl.play(STRIKER, games=3, seed=11, max_ticks=300, skills="strict")
    results = play_games([sl.load_rules(STRIKER)] * 3, [11, 12, 13], GameConfig(max_ticks=300, skills="strict"))
    assert [(g.goals, g.kicks, g.ticks, g.fitness, g.end_reason) for g in games] == \
        [(r.goals, r.kicks, r.ticks, r.fitness, r.end_reason) for r in results]


@pytest.mark.parametrize("arguments, error", [
    ({"games": 0}, ValueError), ({"seed": -1}, ValueError), ({"max_ticks": 0}, ValueError),
    ({"skills": "psychic"}, ValueError), ({"max_tick": 10}, TypeError),
])
def test_play_refuses_bad_options(arguments, error):
    with pytest.raises(error):
        sl.play(STRIKER, **arguments)


# ---- runs -----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict[str, tuple[Path, sl.RunRecord, str]]:
    """Per algorithm: the folder `soccer-lab` wrote, the API's run (same options and seed), and what the
    command printed."""
    root = tmp_path_factory.mktemp("runs")
    made = {}
    for command, play in (("evolve", sl.evolve), ("random-search", sl.random_search)):
        printed = cli(command, *options(RUN), "--out", root / f"cli-{command}")
        made[command] = (root / f"cli-{command}", play(**RUN, out=root / f"api-{command}"), printed)
    return made


@pytest.mark.parametrize("command", ["evolve", "random-search"])
def test_a_run_gives_the_best_and_statistics_the_command_gives(runs, command):
    folder, record, _ = runs[command]
    from_cli = sl.open_run(folder)
    assert record.best == from_cli.best  # fitness bit for bit, the same rules, goals and evaluations
    assert without_wall_time(record.statistics) == without_wall_time(from_cli.statistics)
    assert (record.folder / "best.rules").read_text() == (folder / "best.rules").read_text()
    assert record.generations == RUN["generations"]
    assert record.best.fitness == min(record.column("best"))


def test_evolve_gives_the_same_run_with_more_workers(runs, tmp_path):
    """A notebook's default is every core: the run must not depend on it."""
    record = sl.evolve(**{**RUN, "workers": 2}, out=tmp_path / "two")
    assert record.best == runs["evolve"][1].best
    assert without_wall_time(record.statistics) == without_wall_time(runs["evolve"][1].statistics)


def test_evolve_finds_a_scorer_in_the_compared_run(runs):
    """The comparison above is only worth something if the run is not all 1.0 (nobody kicking)."""
    assert runs["evolve"][1].best.fitness < 1.0


@pytest.mark.parametrize("command", ["evolve", "random-search"])
def test_the_run_summary_prints_the_api_best(runs, command):
    _, record, printed = runs[command]
    assert f"best fitness {record.best.fitness:.4f} (mean of {record.best.evaluations} evaluation" in printed


def test_open_run_reads_the_settings(runs):
    record = sl.open_run(runs["random-search"][0])
    assert record.settings.algorithm == "random-search"
    assert (record.settings.ga.population_size, record.settings.ga.max_generations) == (8, 3)
    assert record.settings.game.max_ticks == 300


@pytest.mark.parametrize("generation, index", [(None, None), (2, None), (2, 3), (1, 0)])
def test_lineage_gives_the_tree_soccer_lab_lineage_prints(runs, generation, index):
    folder = runs["evolve"][0]
    where = ([] if generation is None else ["--generation", generation]) + ([] if index is None else ["--index", index])
    printed = cli("lineage", folder, *where)
    assert sl.lineage(folder, index, generation=generation).text == printed
    assert str(sl.lineage(runs["evolve"][1], index, generation=generation)) == printed  # the same run, made by the API


def test_lineage_refuses_a_place_the_run_does_not_have(runs):
    with pytest.raises(LookupError, match="needs its generation"):
        sl.lineage(runs["evolve"][0], 0)
    with pytest.raises(LookupError):
        sl.lineage(runs["evolve"][0], 99, generation=0)
    with pytest.raises(LookupError, match="not a run folder"):
        sl.lineage(runs["evolve"][0].parent)


def test_a_run_calls_on_generation_with_each_generations_statistics(tmp_path):
    heard = []
    record = sl.evolve(population_size=4, generations=2, seed=3, max_ticks=60, workers=1, out=tmp_path / "run",
                       on_generation=heard.append)
    assert heard == record.statistics


def test_a_run_stopped_by_its_callback_resumes_to_the_uninterrupted_run(runs, tmp_path):
    def stop_after_second(statistics):
        if statistics["generation"] == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sl.evolve(**RUN, out=tmp_path / "stopped", on_generation=stop_after_second)
    assert sl.open_run(tmp_path / "stopped").generations == 2
    resumed = sl.resume(tmp_path / "stopped")
    assert resumed.best == runs["evolve"][1].best
    assert without_wall_time(resumed.statistics) == without_wall_time(runs["evolve"][1].statistics)
    assert (tmp_path / "stopped" / "best.rules").read_text() == (runs["evolve"][0] / "best.rules").read_text()
    assert sl.resume(tmp_path / "stopped") == resumed  # finished: nothing more is played


def test_evolve_without_out_writes_a_new_temporary_folder(monkeypatch, tmp_path):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    record = sl.evolve(population_size=4, generations=1, seed=3, max_ticks=60, workers=1)
    assert record.folder.parent == tmp_path and (record.folder / "best.rules").is_file()


@pytest.mark.parametrize("arguments, error", [
    ({"population_size": 1}, ValueError), ({"selection": "lottery"}, ValueError),
    ({"max_ticks": -5}, ValueError), ({"max_generations": 3}, TypeError), ({"populaton_size": 8}, TypeError),
])
def test_evolve_refuses_bad_options_and_writes_nothing(tmp_path, arguments, error):
    with pytest.raises(error):
        sl.evolve(out=tmp_path / "run", workers=1, **arguments)
    assert not (tmp_path / "run").exists()


def test_evolve_refuses_a_folder_holding_a_run_and_keeps_it(runs):
    folder = runs["evolve"][0]
    before = (folder / "statistics.csv").read_text()
    with pytest.raises(ValueError, match="already holds a run"):
        sl.evolve(**RUN, out=folder)
    assert (folder / "statistics.csv").read_text() == before


def test_open_run_refuses_a_folder_without_a_run(tmp_path):
    with pytest.raises(ValueError, match="not a run folder"):
        sl.open_run(tmp_path)


# ---- experiments ----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def experiment(tmp_path_factory) -> tuple[Path, str]:
    """A tiny `selection` experiment made by the command, and what it printed."""
    folder = tmp_path_factory.mktemp("experiments") / "selection"
    printed = cli("experiment", "selection", "--trials", 1, "--population", 4, "--generations", 2,
                  "--max-ticks", 100, "--replays", 2, "--workers", 1, "--no-library", "--out", folder)
    return folder, printed


def test_open_experiment_gives_the_verdicts_the_command_printed(experiment):
    folder, printed = experiment
    found = sl.open_experiment(folder)
    summary = ", ".join(f"{n} {v}" for v, n in found.verdicts().items() if n)
    assert f"verdicts: {summary}\n" in printed
    assert found.presets == ["selection"]
    assert {row["setting"] for row in found.statistics} == {row["setting"] for row in found.bests}
    report = found.report.read_text()
    assert all(finding.claim in report for finding in found.findings if finding.preset == "selection")


def test_open_experiment_reads_replicates_with_the_verdicts_the_command_printed(tmp_path):
    folder = tmp_path / "replicates"
    printed = cli("experiment", "selection", "--trials", 1, "--population", 4, "--generations", 2, "--max-ticks", 60,
                  "--replays", 1, "--seeds", "3,8", "--workers", 1, "--no-library", "--out", folder)
    found = sl.open_experiment(folder)
    summary = ", ".join(f"{n} {v}" for v, n in found.verdicts().items() if n)
    assert f"verdicts: {summary}\n" in printed
    assert [replicate.folder.name for replicate in found.replicates] == ["seed-3", "seed-8"]
    assert [replicate.options.seed for replicate in found.replicates] == [3, 8]
    assert len(found.statistics) == sum(len(replicate.statistics) for replicate in found.replicates) > 0


def test_open_experiment_refuses_a_folder_without_one(tmp_path):
    with pytest.raises(ValueError, match="holds no finished experiment"):
        sl.open_experiment(tmp_path)


# ---- the docstrings' examples -----------------------------------------------------------------------------
@pytest.mark.parametrize("module", ["soccer_lab", "soccer_lab.rules", "soccer_lab.games", "soccer_lab.matches",
                                    "soccer_lab.runs", "soccer_lab.experiments"])
def test_docstring_examples_run(module, experiment, monkeypatch, tmp_path):
    import importlib

    monkeypatch.chdir(REPOSITORY)  # the examples name the repository's example files
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))  # the runs they make go here
    failures, tried = doctest.testmod(importlib.import_module(module), extraglobs={"experiment_folder": experiment[0]},
                                      optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, report=True)
    assert tried > 0 and failures == 0
