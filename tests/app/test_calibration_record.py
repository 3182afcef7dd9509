"""The Calibration page's tables: what benchmarks/calibrate.py measures for a candidate and records, and how
docs/hooks/calibration_tables.py shows the recorded candidates (the default first, each figure from its file)."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import pytest

from soccer_lab.app.experiment.presets import ExperimentOptions

ROOT = Path(__file__).resolve().parents[2]
TINY = dict(trials=2, population=6, generations=2, max_ticks=40, seed=3, replays=2)


def load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


sys.path.insert(0, str(ROOT / "benchmarks"))  # calibrate.py imports its sibling results.py
calibrate = load(ROOT / "benchmarks" / "calibrate.py", "calibrate")
results = load(ROOT / "benchmarks" / "results.py", "results")
hook = load(ROOT / "docs" / "hooks" / "calibration_tables.py", "calibration_tables")
PAGE = "# Calibration\n\n" + "\n\n".join(hook.MARKERS.values()) + "\n"


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> Path:
    """Two candidates recorded as `--record` does: the default and touches counted, into their own folder."""
    root = tmp_path_factory.mktemp("calibration")
    for touches in (True, False):
        options = ExperimentOptions(**TINY, count_touches=touches)
        document = calibrate.calibrate(options, ["initial", "selection"], root / f"trials-{touches}", 1)
        results.record_document(root / "results" / f"{calibrate.candidate_name(options)}.json", document,
                                command="python benchmarks/calibrate.py --trials 2", load_before=[0.1, 0.2, 0.3])
    return root


def test_a_candidate_is_recorded_with_its_size_outcomes_and_verdicts(recorded):
    document = json.loads((recorded / "results" / "sighted-linear-quiet-kicks.json").read_text())
    assert document["default"] is True and document["candidate"]["count_touches"] is False
    assert document["size"]["trials"] == {"initial": 2, "selection": 2}
    assert document["trials_run"] == 6 and document["trials_reused"] == 0
    assert [(o["preset"], o["setting"]) for o in document["outcomes"]] == [
        ("initial", "Table 2"), ("selection", "roulette"), ("selection", "tournament"), ("selection", "elitist")]
    assert all(0.0 <= o["final_average_median"] <= 1.0 and o["trials"] == 2 for o in document["outcomes"])
    # a run this small is judged on nothing: each finding says so, with the size it needs
    assert len(document["verdicts"]) == 8
    assert all(v["verdict"].startswith("too small to judge (needs") for v in document["verdicts"])
    summary = document["initial"]
    assert summary["generations"] == [0, 1] and len(summary["average_median"]) == 2
    assert document["command"].startswith("python benchmarks/calibrate.py")
    assert document["load_average_before"] == [0.1, 0.2, 0.3] and len(document["load_average_after"]) == 3
    other = json.loads((recorded / "results" / "sighted-linear-quiet-touches.json").read_text())
    assert other["default"] is False and other["candidate"]["count_touches"] is True


def test_calibrating_again_into_the_same_folder_reuses_every_trial(recorded):
    again = calibrate.calibrate(ExperimentOptions(**TINY), ["initial", "selection"], recorded / "trials-False", 1)
    first = json.loads((recorded / "results" / "sighted-linear-quiet-kicks.json").read_text())
    assert (again["trials_run"], again["trials_reused"]) == (0, 6)
    assert again["outcomes"] == first["outcomes"] and again["initial"] == first["initial"]


def test_the_page_shows_every_candidate_the_default_first(recorded):
    page = hook.render(PAGE, results=recorded / "results")
    assert "<!-- generated" not in page
    rows = [line for line in page.splitlines() if line.startswith("| sighted")]
    assert rows[0].startswith("| sighted, linear, no noise, kicks only (**default**)")
    assert any(row.startswith("| sighted, linear, no noise, touches counted |") for row in rows)
    assert "| candidate | roulette | tournament | elitist | `initial` plateau |" in page
    assert "**0 of 8 findings agree, 0 disagree, 0 inconclusive**, 8 too small to judge" in page
    assert "| selection | 0 of 3 | 6.4.3, Fig. 20:" in page
    assert "`python benchmarks/calibrate.py --trials 2`" in page and "0.1/0.2/0.3" in page


def test_a_page_without_recorded_candidates_says_how_to_record_them(tmp_path):
    page = hook.render(PAGE, results=tmp_path)
    assert page.count(hook.NOT_RECORDED) == len(hook.MARKERS)


def test_the_verdict_summary_counts_each_verdict_as_the_report_writes_it(recorded, tmp_path):
    document = json.loads((recorded / "results" / "sighted-linear-quiet-kicks.json").read_text())
    shown = ["agrees", "DISAGREES", "inconclusive", "DISAGREES", "agrees", "agrees", "agrees", "agrees"]
    for verdict, word in zip(document["verdicts"], shown):
        verdict["verdict"] = word
    (tmp_path / "default.json").write_text(json.dumps(document))
    page = hook.render(hook.MARKERS["verdicts"], results=tmp_path)
    assert "**5 of 8 findings agree, 2 disagree, 1 inconclusive**" in page
    assert "| initial | 2 of 5 |" in page and "| selection | 3 of 3 |  |" in page


def test_the_calibration_page_says_why_each_finding_disagrees_and_what_no_difference_could_detect(recorded, tmp_path):
    """The page once gave a DISAGREES with its figures only, and a "no difference" agreement without what
    its test could have detected."""
    document = json.loads((recorded / "results" / "sighted-linear-quiet-kicks.json").read_text())
    assert all(verdict["test"] for verdict in document["verdicts"])  # what each verdict tested is recorded
    assert all("reason" in verdict and "no_difference_found" in verdict for verdict in document["verdicts"])
    first, selection = document["verdicts"][0], document["verdicts"][5]
    first.update(verdict="DISAGREES", reason="falls by generation 3, then regrows")
    selection.update(verdict="agrees", no_difference_found=True,
                     test="Kruskal-Wallis; with 2 trials per setting it could have detected a difference of about 0.4")
    (tmp_path / "default.json").write_text(json.dumps(document))
    page = hook.render(hook.MARKERS["verdicts"], results=tmp_path)
    assert "why (this run's data)" in page and "| falls by generation 3, then regrows |" in page
    assert 'of the agreements are "no significant difference found"' in page
    assert f"| {selection['where']}: {selection['claim']} | {selection['test']} |" in page
