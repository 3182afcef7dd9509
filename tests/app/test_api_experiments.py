"""Experiments in the app's library through the API: listed, read, their report, statistics, figures and
trial recordings served, and nothing outside the recorded folder ever served."""

from __future__ import annotations

import shutil

import pytest

from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.library import library_summary
from soccer_lab.app.experiment.presets import ExperimentOptions
from soccer_lab.app.experiment.runner import run_experiment
from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.store import Store
from tests.app.api_client import api_client

TINY = ExperimentOptions(trials=2, population=6, generations=2, max_ticks=40, seed=3)


@pytest.fixture(scope="module")
def experiment(tmp_path_factory):
    """A real shrunken `initial` experiment, recorded in the library as the CLI records it."""
    root = tmp_path_factory.mktemp("experiment")
    folder = root / "initial-seed3"
    outcome = run_experiment("initial", TINY, folder, LocalExecutor(1))
    (root / "secret.png").write_bytes(b"\x89PNG not for the API")
    data = root / "data"
    data.mkdir()
    store = Store(data / DATABASE_FILE)
    store.record_experiment("initial", folder.resolve(), library_summary(TINY, outcome))
    store.close()
    return data, folder, outcome


@pytest.fixture
def client(experiment):
    with api_client(experiment[0]) as opened:
        yield opened


def test_list_and_read_give_the_summary_and_links_to_every_file(client, experiment):
    _, folder, outcome = experiment
    (listed,) = client.get("/api/experiments").json()
    read = client.get(f"/api/experiments/{listed['id']}").json()
    assert read == listed
    assert read["preset"] == "initial" and read["presets"] == ["initial"] and read["available"]
    assert read["folder"] == "initial-seed3"  # its name: no filesystem path leaves the API
    assert str(folder.resolve().parent) not in client.get("/api/experiments").text
    assert read["trials"] == 2 and read["options"]["population"] == 6
    assert read["verdicts"] == outcome.report.verdicts()
    assert [f["name"] for f in read["figures"]] == [f.path.name for f in outcome.report.figures]
    assert [f["caption"] for f in read["figures"]] == [f.caption for f in outcome.report.figures]
    for figure in read["figures"]:
        response = client.get(figure["url"])
        assert response.status_code == 200 and response.headers["content-type"] == "image/png"
        assert response.content == (folder / "figures" / figure["name"]).read_bytes()
    report = client.get(read["report"])
    assert report.status_code == 200 and report.headers["content-type"].startswith("text/html")
    assert "default-src 'none'" in report.headers["content-security-policy"]
    assert "data:image/png;base64," in report.text
    assert client.get(read["report_markdown"]).text == (folder / "report.md").read_text()
    assert client.get(read["statistics"]).text.splitlines()[0].startswith("preset,setting,trial")
    assert [r["trial"] for r in read["recordings"]] == [p.stem for p in sorted((folder / "trials").glob("*.rrd"))]
    assert len(read["recordings"]) == 2
    assert client.get(read["recordings"][0]["url"]).content[:4] == b"RRF2"


@pytest.mark.parametrize("path", [
    "figures/..%2Fsecret.png",  # the decoded name carries a separator
    "figures/%2E%2E",
    "figures/.hidden.png",
    "figures/secret.png",  # exists one level up, not in figures/
    "figures/missing.png",
    "figures/manifest.json",  # a file of the folder, but not a figure
    "figures/link.png",  # a symbolic link out of the folder
    "trials/..%2F..%2Fsecret.png",
    "trials/initial-0.csv",  # trial statistics are served through statistics.csv only
])
def test_nothing_outside_the_folder_or_of_another_kind_is_served(client, experiment, path):
    _, folder, _ = experiment
    link = folder / "figures" / "link.png"
    if not link.is_symlink():
        link.symlink_to(folder.parent / "secret.png")
    experiment_id = client.get("/api/experiments").json()[0]["id"]
    response = client.get(f"/api/experiments/{experiment_id}/{path}")
    assert response.status_code == 404, response.text
    assert b"not for the API" not in response.content
    assert "link.png" not in [f["name"] for f in client.get(f"/api/experiments/{experiment_id}").json()["figures"]]


def test_unknown_ids_and_a_vanished_folder_are_404s_not_500s(tmp_path):
    folder = tmp_path / "gone"
    (folder / "figures").mkdir(parents=True)
    (folder / "report.html").write_text("<html></html>")
    (folder / "figures" / "a.png").write_bytes(b"\x89PNG")
    store = Store(tmp_path / DATABASE_FILE)
    record = store.record_experiment("long", folder, {"figures": ["figures/a.png"], "trials": 1})
    store.close()
    with api_client(tmp_path) as client:
        assert client.get(f"/api/experiments/{record.id}/figures/a.png").status_code == 200
        shutil.rmtree(folder)
        read = client.get(f"/api/experiments/{record.id}").json()
        assert not read["available"] and read["report"] is None and read["figures"] == []
        assert client.get(f"/api/experiments/{record.id}/report.html").status_code == 404
        missing = client.get(f"/api/experiments/{record.id + 1}")
        assert missing.status_code == 404 and missing.json()["detail"] == f"no experiment with id {record.id + 1}"
        assert client.get("/api/experiments/abc").status_code == 422
