"""app/runs/recording.py (rerun) and app/runs/outputs.py (the run folder), read back with rerun's own reader."""

from __future__ import annotations

import csv
import math
import uuid
from datetime import datetime
from types import SimpleNamespace

import numpy as np
import pytest
from rerun.chunk import RrdReader

from soccer_lab.app.runs.recording import (COMPOSITION_SERIES, DISTANCE_SERIES, DIVERSITY_SERIES, FITNESS_SERIES,
                                           GENE_POOL_SERIES, GOAL_BINS, GOAL_HISTOGRAM_ENTITY, GOAL_SERIES,
                                           LEGENDS, VIEW_CONE_LENGTH, RunRecorder, goal_outline, legend_entity,
                                           log_replay, open_stream, spread_entity, statistic_entity, view_cone)
from soccer_lab.app.runs.outputs import RunFolder, RunFolderError, StatisticsFile, default_run_dir
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.statistics import GenerationStats
from soccer_lab.soccer.config import GameConfig, WorldConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import play_game


def columns(path, entity: str) -> dict[str, list]:
    merged: dict[str, list] = {}
    for chunk in RrdReader(path).stream():
        if chunk.entity_path == entity:
            for name, values in chunk.to_record_batch().to_pydict().items():
                merged.setdefault(name, []).extend(values)
    return merged


def stats(generation: int, best: float) -> GenerationStats:
    values = {name: 0.0 for name in GenerationStats.field_names()}
    values.update(generation=generation, best=best, goals_0=0.5, goals_2=0.25, goals_more=0.25)
    return GenerationStats.from_dict(values)


def test_statistics_are_grouped_one_plot_per_kind():
    assert statistic_entity("best") == "statistics/fitness/best"
    assert statistic_entity("std") == "statistics/fitness/std"
    assert statistic_entity("goals_more") == "statistics/goals/goals_more"
    assert statistic_entity("valid_rules_std") == "statistics/chromosome/valid_rules_std"
    assert statistic_entity("unique_genes") == "statistics/gene_pool/unique_genes"
    assert statistic_entity("evaluations") == "statistics/run/evaluations"
    entities = {statistic_entity(n) for n in GenerationStats.field_names()}
    assert len(entities) == len(GenerationStats.field_names())  # no two statistics share a series


def test_run_recorder_logs_history_then_new_generations(tmp_path):
    path = tmp_path / "run.rrd"
    recorder = RunRecorder(path, history=[stats(0, 0.9).to_dict(), stats(1, 0.7).to_dict()])
    recorder.on_generation(stats(2, 0.5), population=[])
    recorder.close()
    best = columns(path, "/statistics/fitness/best")
    assert best["generation"] == [0, 1, 2]
    assert [v[0] for v in best["Scalars:scalars"]] == [0.9, 0.7, 0.5]
    histogram = columns(path, "/" + GOAL_HISTOGRAM_ENTITY)["BarChart:values"]
    assert histogram[2][0]["buffer"] == [0.5, 0.0, 0.25, 0.0, 0.0, 0.25]
    assert len(GOAL_BINS) == 6


def test_diversity_is_logged_and_unmeasured_behaviours_are_not(tmp_path):
    path = tmp_path / "run.rrd"
    recorder = RunRecorder(path)
    recorder.on_generation(GenerationStats.from_dict({**stats(0, 0.9).to_dict(), "distinct_chromosomes": 40,
                                                      "rule_set_distance": 0.75, "distinct_behaviours": 0}))
    recorder.on_generation(GenerationStats.from_dict({**stats(1, 0.8).to_dict(), "distinct_chromosomes": 31,
                                                      "rule_set_distance": 0.5, "distinct_behaviours": 7}))
    recorder.close()
    assert statistic_entity("distinct_rules") == "statistics/diversity/distinct_rules"
    assert [v[0] for v in columns(path, "/statistics/diversity/distinct_chromosomes")["Scalars:scalars"]] == [40, 31]
    assert [v[0] for v in columns(path, "/statistics/diversity/rule_set_distance")["Scalars:scalars"]] == [0.75, 0.5]
    behaviours = columns(path, "/statistics/diversity/distinct_behaviours")
    assert behaviours["generation"] == [1] and [v[0] for v in behaviours["Scalars:scalars"]] == [7]  # 0: not measured


def test_best_so_far_never_rises_where_the_generation_s_best_does(tmp_path):
    """The live "best" jumped 0.25 -> 0.5 -> 0.167: the generation's best is noisy (one game each), so the
    recording names it and adds the run's best so far beside it, also over a resumed run's history."""
    path = tmp_path / "run.rrd"
    recorder = RunRecorder(path, history=[stats(0, 0.25).to_dict(), stats(1, 0.5).to_dict()])
    recorder.on_generation(stats(2, 0.167))
    recorder.on_generation(stats(3, 0.3))
    recorder.close()
    assert [v[0] for v in columns(path, "/statistics/fitness/best")["Scalars:scalars"]] == [0.25, 0.5, 0.167, 0.3]
    so_far = columns(path, "/statistics/fitness/best_so_far")
    assert so_far["generation"] == [0, 1, 2, 3]
    assert [v[0] for v in so_far["Scalars:scalars"]] == [0.25, 0.25, 0.167, 0.167]
    assert FITNESS_SERIES["best"][0] == "best of the generation" and FITNESS_SERIES["best_so_far"][0] == "best so far"


def test_two_recordings_at_once_stay_apart(tmp_path):
    first, second = RunRecorder(tmp_path / "a.rrd"), RunRecorder(tmp_path / "b.rrd")
    first.on_generation(stats(0, 0.8))
    second.on_generation(stats(0, 0.3))
    second.on_generation(stats(1, 0.2))
    first.close()
    second.close()
    assert [v[0] for v in columns(tmp_path / "a.rrd", "/statistics/fitness/best")["Scalars:scalars"]] == [0.8]
    assert [v[0] for v in columns(tmp_path / "b.rrd", "/statistics/fitness/best")["Scalars:scalars"]] == [0.3, 0.2]


def test_view_cone_edges_are_45_degrees_either_side_of_the_facing():
    cone = view_cone(1.0, 2.0, 90.0, 45.0)  # facing +y (to the player's right when it faced +x)
    np.testing.assert_allclose(cone[1], [1.0, 2.0])
    edge = VIEW_CONE_LENGTH / math.sqrt(2)
    np.testing.assert_allclose(cone[0], [1.0 + edge, 2.0 + edge])
    np.testing.assert_allclose(cone[2], [1.0 - edge, 2.0 + edge])


def test_goal_outline_runs_post_to_post_around_the_net():
    world = WorldConfig()
    outline = goal_outline(world)
    np.testing.assert_allclose(outline[[0, -1]], [[52.5, -7.01], [52.5, 7.01]])
    np.testing.assert_allclose(outline[1:3, 0], [54.5, 54.5])


def test_replay_logs_each_tick_of_a_trace(tmp_path):
    trace = SimpleNamespace(  # a three-tick trace in the engine's GameTrace layout
        player_x=np.array([-10.0, -9.5, -9.0]), player_y=np.array([1.0, 1.0, 1.5]),
        facing=np.array([0.0, 0.0, 30.0]), ball_x=np.array([0.0, 0.0, 0.5]), ball_y=np.array([3.0, 3.0, 3.0]),
        action=np.array([-1, 1, 2]), goals=np.array([0, 0, 1]), vocabulary=Vocabulary.default(),
    )
    path = tmp_path / "replay.rrd"
    stream = open_stream(path)
    log_replay(stream, trace, WorldConfig(), entity="game")
    stream.disconnect()
    player = columns(path, "/game/player")
    assert player["tick"] == [0, 1, 2]
    assert [p[0] for p in player["Points2D:positions"]] == [[-10.0, 1.0], [-9.5, 1.0], [-9.0, 1.5]]
    assert [p[0] for p in player["Points2D:labels"]] == ["Hunt", "Dash", "Kick"]  # -1 = no rule fired
    ball = columns(path, "/game/ball")
    assert [p[0] for p in ball["Points2D:positions"]] == [[0.0, 3.0], [0.0, 3.0], [0.5, 3.0]]
    assert [v[0] for v in columns(path, "/game/score/goals")["Scalars:scalars"]] == [0.0, 0.0, 1.0]
    cones = columns(path, "/game/player/view_cone")["LineStrips2D:strips"]
    np.testing.assert_allclose(cones[2][0], view_cone(-9.0, 1.5, 30.0, 45.0))


def blueprint_rows(path) -> list[dict[str, dict]]:
    """Every blueprint the recording carries (in the order it sent them), each as entity path -> its
    components, read with rerun's own reader."""
    import pyarrow as pa

    reader = RrdReader(path)
    blueprints = []
    for store in reader.blueprints():
        rows: dict[str, dict] = {}
        for chunk in reader.stream(store=store):
            batch = chunk.to_record_batch()
            for name in batch.schema.names:
                if not pa.types.is_timestamp(batch.schema.field(name).type):
                    rows.setdefault(chunk.entity_path, {})[name] = batch.column(name).to_pylist()[-1]
        blueprints.append(rows)
    return blueprints


def views(blueprint: dict[str, dict]) -> dict[str, tuple[str, list[str]]]:
    """View name -> (view class, its contents' query expressions)."""
    found = {}
    for path, row in blueprint.items():
        if path.startswith("/view/") and "ViewBlueprint:display_name" in row:
            contents = blueprint.get(f"{path}/ViewContents", {}).get("ViewContents:query", [])
            found[row["ViewBlueprint:display_name"][0]] = (row["ViewBlueprint:class_identifier"][0], contents)
    return found


def test_the_blueprint_lays_a_run_out_like_the_chapters_figures_with_a_tab_per_replay(tmp_path):
    config = GameConfig(max_ticks=30)
    path = tmp_path / "run.rrd"
    recorder = RunRecorder(path, world=config.world)
    games = []
    for generation in range(2):
        recorder.on_generation(stats(generation, 0.5))
        result, trace = play_game(demo_rulebase(), seed=generation, config=config)
        recorder.log_generation_replay(generation, trace, result)
        games.append(result)
    recorder.close()
    blueprints = blueprint_rows(path)
    latest = max(blueprints, key=lambda blueprint: len(views(blueprint)))  # the one with every replay's tab
    shown = views(latest)
    series = lambda names: [f"+ /{statistic_entity(n)}" for n in names]
    fitness = shown["Fitness: best of the generation, best so far, mean, worst (Figs. 11, 12; lower is better)"]
    assert fitness == ("TimeSeries", series(FITNESS_SERIES))
    assert shown["Share of the population scoring 0 .. more than 4 goals (Fig. 13)"] == ("TimeSeries", series(GOAL_SERIES))
    assert shown["Goal shares at this generation"][0] == "BarChart"
    composition = shown["Per chromosome: genes, premises, rules, valid rules, mean and ± std (Fig. 28)"]
    assert composition == ("TimeSeries", series(f"{c}_mean" for c in COMPOSITION_SERIES)
                           + [f"+ /{spread_entity(c)}" for c in COMPOSITION_SERIES])
    assert shown["Gene pool: unique premise, consequent and all genes (Fig. 29)"] == ("TimeSeries", series(GENE_POOL_SERIES))
    assert shown["Diversity: distinct chromosomes, rules, behaviours"] == ("TimeSeries", series(DIVERSITY_SERIES))
    assert shown["Mean distance between two players' rule sets (1: no rule shared)"] == (
        "TimeSeries", series(DISTANCE_SERIES))
    for generation, game in enumerate(games):
        tab = shown[f"generation {generation} ({game.goals} goal{'' if game.goals == 1 else 's'})"]
        assert tab == ("2D", ["+ $origin/pitch/**", "+ $origin/goal/**", f"+ /replay/generation_{generation}/**"])
    assert len(shown) == 7 + len(LEGENDS) + len(games)  # nothing else: no automatic views either
    viewport = latest["/viewport"]
    assert viewport["ViewportBlueprint:auto_views"] == [False] and viewport["ViewportBlueprint:auto_layout"] == [False]
    tabs = next(row for row in latest.values() if row.get("ContainerBlueprint:active_tab"))
    assert tabs["ContainerBlueprint:contents"][-1] == tabs["ContainerBlueprint:active_tab"][0]  # the latest replay open
    # A store per blueprint sent (the file's default, then each replay's): one store sent again would pile up
    # unreachable containers, which rerun's viewer shows as "broken references".
    assert len(blueprints) == 3
    # The replays: each under its own generation, on the tick timeline and at its generation.
    ball = columns(path, "/replay/generation_1/ball")
    assert ball["tick"] == list(range(games[1].ticks)) and set(ball["generation"]) == {1}
    assert columns(path, "/replay/pitch")["LineStrips2D:strips"]  # one pitch, drawn once for every replay


def test_no_legend_is_drawn_over_a_plot_each_plot_has_its_legend_beside_it(tmp_path):
    # rerun 0.41 draws a plot's legend in a corner inside the plot, over its lines: each plot's own legend is
    # hidden, and the view beside it (the next one in its row) lists its series' names in their colours.
    path = tmp_path / "run.rrd"
    recorder = RunRecorder(path)
    recorder.on_generation(stats(0, 0.5))
    recorder.close()
    blueprint = blueprint_rows(path)[-1]
    plots = {path: row for path, row in blueprint.items()
             if row.get("ViewBlueprint:class_identifier", [None])[0] in ("TimeSeries", "BarChart")}
    assert len(plots) == 7
    assert all(blueprint[f"{path}/PlotLegend"]["PlotLegend:visible"] == [False] for path in plots)
    beside = {}
    for row in blueprint.values():
        contents = row.get("ContainerBlueprint:contents") or []
        for left, right in zip(contents, contents[1:]):
            beside[f"/{left}"] = blueprint.get(f"/{right}", {}).get("ViewBlueprint:space_origin", [None])[0]
    legends = sorted(beside[path] for path, row in plots.items()
                     if row["ViewBlueprint:class_identifier"] == ["TimeSeries"])
    assert legends == sorted(f"/{legend_entity(legend)}" for legend in LEGENDS)  # one beside each time series
    for legend, series in LEGENDS.items():
        drawn = columns(path, f"/{legend_entity(legend)}")
        assert drawn["Points2D:labels"] == [[name for name, _ in series]] and drawn["Points2D:show_labels"] == [[True]]
        packed = [(r << 24) | (g << 16) | (b << 8) | 255 for _, (r, g, b) in series]
        assert drawn["Points2D:colors"] == [packed]  # each name in its series' colour


def unreachable_containers(blueprint: dict[str, dict]) -> set[str]:
    """The blueprint's containers that its viewport's root container does not reach."""
    (root,) = blueprint["/viewport"]["ViewportBlueprint:root_container"]  # the root's UUID, as 16 bytes
    reached, todo = set(), [f"container/{uuid.UUID(bytes=bytes(root))}"]
    while todo:
        path = "/" + todo.pop()
        if path not in reached:
            reached.add(path)
            todo += blueprint.get(path, {}).get("ContainerBlueprint:contents") or []
    return {path for path in blueprint if path.startswith("/container/") and path.count("/") == 2} - reached


def test_no_blueprint_holds_a_container_its_root_does_not_reach(tmp_path):
    # rerun's viewer greeted every UI run with "Blueprint ... has broken references: /container/...": each
    # blueprint was sent into one store, where the earlier ones' containers stayed, unreachable.
    config = GameConfig(max_ticks=30)
    path = tmp_path / "run.rrd"
    recorder = RunRecorder(path, world=config.world)
    for generation in range(5):
        recorder.on_generation(stats(generation, 0.5))
        result, trace = play_game(demo_rulebase(), seed=generation, config=config)
        recorder.log_generation_replay(generation, trace, result)
    recorder.close()
    blueprints = blueprint_rows(path)
    assert len(blueprints) >= 4
    assert [unreachable_containers(blueprint) for blueprint in blueprints] == [set()] * len(blueprints)


def test_a_recording_without_replays_sends_its_layout_active(tmp_path):
    # An experiment's trial records statistics only: its only blueprint was the file's default, which rerun's
    # web viewer set aside for its automatic grid of one small view per series.
    path = tmp_path / "trial.rrd"
    recorder = RunRecorder(path)
    recorder.on_generation(stats(0, 0.5))
    recorder.close()
    assert len(blueprint_rows(path)) == 2  # the default, then the same layout sent active


# ---- the run folder --------------------------------------------------------------------------
def test_default_run_dir_is_a_timestamp_and_never_reuses_a_folder(tmp_path):
    now = datetime(2024, 1, 31, 14, 25, 2)
    first = default_run_dir(now, root=tmp_path)
    assert first == tmp_path / "20240131-142502"
    first.mkdir()
    assert default_run_dir(now, root=tmp_path) == tmp_path / "20240131-142502-2"


def test_statistics_file_restarts_from_the_history_it_is_given(tmp_path):
    path = tmp_path / "statistics.csv"
    written = StatisticsFile(path)
    for generation in range(3):
        written.append(stats(generation, 0.9 - generation / 10).to_dict())
    rows = list(csv.DictReader(path.read_text().splitlines()))
    assert [r["generation"] for r in rows] == ["0", "1", "2"]
    # Resuming from a checkpoint holding generations 0..1: generation 2 goes, then comes back anew.
    resumed = StatisticsFile(path, [stats(0, 0.9).to_dict(), stats(1, 0.8).to_dict()])
    resumed.append(stats(2, 0.6).to_dict())
    rows = list(csv.DictReader(path.read_text().splitlines()))
    assert [(r["generation"], float(r["best"])) for r in rows] == [("0", 0.9), ("1", 0.8), ("2", 0.6)]
    assert list(rows[0]) == list(GenerationStats.field_names())


def test_run_folder_errors_name_the_problem(tmp_path):
    folder = RunFolder.create(tmp_path / "run", {"algorithm": "ga"})
    with pytest.raises(RunFolderError, match="already holds a run"):
        RunFolder.create(tmp_path / "run", {"algorithm": "ga"})
    with pytest.raises(RunFolderError, match="no checkpoint"):
        RunFolder.open(folder.path)
    with pytest.raises(RunFolderError, match="not a run folder"):
        RunFolder.open(tmp_path / "elsewhere")
    folder.manifest.write_text("[1, 2]")
    with pytest.raises(RunFolderError, match="not a run manifest"):
        folder.read_manifest()
