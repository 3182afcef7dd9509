"""Files leave the API only as regular files inside their folder (issue 25): a run's recording linked to a
file elsewhere, or a run folder swapped for a link, is refused (404) and not listed; no response carries a
filesystem path."""

from __future__ import annotations

import os
from pathlib import Path

from soccer_lab.app.web.served_files import regular_file_inside
from tests.app.api_client import SHORT_GAMES, TINY_GA, api_client, wait_for


def finished_run(client) -> dict:
    run = client.post("/api/runs", json={"ga": TINY_GA, "game": SHORT_GAMES}).json()
    return wait_for(lambda: (r := client.get(f"/api/runs/{run['id']}").json())["status"] == "finished" and r,
                    what="the run to finish")


def test_a_recording_linked_out_of_its_run_folder_is_refused(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("not for the web")
    with api_client(tmp_path / "data") as client:
        run = finished_run(client)
        assert client.get(run["recording"]).status_code == 200
        folder = tmp_path / "data" / "runs" / str(run["id"])
        (folder / "run.rrd").unlink()
        (folder / "run.rrd").symlink_to(secret)
        response = client.get(f"/api/runs/{run['id']}/recording.rrd")
        assert response.status_code == 404 and "not for the web" not in response.text
        assert client.get(f"/api/runs/{run['id']}").json()["recording"] is None


def test_a_run_folder_swapped_for_a_link_is_refused(tmp_path):
    elsewhere = tmp_path / "elsewhere"
    with api_client(tmp_path / "data") as client:
        run = finished_run(client)
        folder = tmp_path / "data" / "runs" / str(run["id"])
        folder.rename(elsewhere)
        folder.symlink_to(elsewhere, target_is_directory=True)
        assert client.get(f"/api/runs/{run['id']}/recording.rrd").status_code == 404


def test_only_regular_files_directly_inside(tmp_path):
    (tmp_path / "file").write_text("x")
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "sub").mkdir()
    assert regular_file_inside(tmp_path, "file") == tmp_path / "file"
    for name in ("fifo", "sub", "missing", "../file", ".", ""):
        assert regular_file_inside(tmp_path, name) is None, name


def test_no_run_response_carries_a_filesystem_path(tmp_path):
    # (experiments: tests/app/test_api_experiments.py)
    with api_client(tmp_path / "data") as client:
        finished_run(client)
        root = str(Path(tmp_path).resolve())
        for path in ("/api/runs", "/api/runs/1", "/api/runs/1/statistics", "/api/server"):
            assert root not in client.get(path).text, path
