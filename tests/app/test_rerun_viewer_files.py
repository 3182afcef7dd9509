"""rerun's web viewer as the app serves it (app/web/rerun_viewer.py): its files given once by the installed rerun
CLI, kept per rerun version, the page without its links to a font service."""

from __future__ import annotations

import socket

import pytest

from soccer_lab.app.web.rerun_viewer import (FILES, OFFLINE_SCRIPT, RerunViewerError, offline_page, rerun_version,
                                             viewer_files)


def test_the_viewer_files_are_fetched_once_and_need_no_internet(tmp_path, monkeypatch):
    folder = viewer_files(tmp_path)
    assert folder.parent == tmp_path and folder.name.startswith(rerun_version())
    assert all((folder / name).stat().st_size > 0 for name in FILES)
    page = (folder / "index.html").read_text()
    assert "re_viewer.js" in page and "fonts.googleapis" not in page and "fonts.gstatic" not in page
    assert page.index(OFFLINE_SCRIPT) < page.index("<script", page.index(OFFLINE_SCRIPT) + 1)  # before rerun's own
    assert [path.name for path in tmp_path.iterdir()] == [folder.name]  # no leftover scratch folder
    monkeypatch.setenv("RERUN_CLI_PATH", str(tmp_path / "no-such-rerun"))  # cached: the CLI is not asked again
    assert viewer_files(tmp_path) == folder


def test_a_page_without_a_head_is_refused_not_served_online():
    with pytest.raises(RerunViewerError, match="no <head>"):
        offline_page("<html><body>a page of some other rerun</body></html>")


def test_without_the_rerun_cli_the_error_says_what_to_do(tmp_path, monkeypatch):
    monkeypatch.setenv("RERUN_CLI_PATH", str(tmp_path / "no-such-rerun"))
    with pytest.raises(RerunViewerError, match="reinstall rerun-sdk"):
        viewer_files(tmp_path / "cache")


def test_the_cli_listens_only_on_this_machine_while_it_gives_the_files(tmp_path, monkeypatch):
    """rerun-sdk's own serve_web_viewer would listen on 0.0.0.0; the CLI is told 127.0.0.1."""
    import soccer_lab.app.web.rerun_viewer as viewer

    bound = []
    real = viewer._wait_until_served

    def watching(process, port):
        real(process, port)
        with socket.socket() as probe:  # the port is taken on 127.0.0.1 ...
            bound.append(probe.connect_ex(("127.0.0.1", port)) == 0)
        for address in _other_addresses():  # ... and nowhere else
            with socket.socket() as probe:
                probe.settimeout(1)
                bound.append(probe.connect_ex((address, port)) != 0)

    monkeypatch.setattr(viewer, "_wait_until_served", watching)
    viewer_files(tmp_path)
    assert bound and all(bound)


def _other_addresses() -> list[str]:
    try:
        names = {info[4][0] for info in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)}
    except OSError:
        return []
    return sorted(name for name in names if not name.startswith("127."))


def test_a_cache_that_cannot_be_written_is_one_clear_error(tmp_path):
    blocker = tmp_path / "cache"
    blocker.write_text("a file where the cache folder should be")
    with pytest.raises(RerunViewerError, match=f"cannot write rerun's viewer files into {blocker}"):
        viewer_files(blocker)


def test_serve_without_the_viewer_still_starts_and_says_why(tmp_path, monkeypatch):
    """The viewer is one page among many: serve runs on and prints why it is missing."""
    import soccer_lab.app.web.server as server

    def missing(cache):
        raise RerunViewerError("rerun's viewer program is missing at /nowhere (reinstall rerun-sdk)")

    class Stopped(Exception):
        pass

    async def stop_once_listening(self):  # after startup, where serve prints its addresses
        raise Stopped

    monkeypatch.setattr("soccer_lab.app.web.rerun_viewer.viewer_files", missing)
    monkeypatch.setattr("uvicorn.Server.main_loop", stop_once_listening)
    printed = []
    options = server.ServeOptions(port=_free_port(), ui_port=_free_port(), data_dir=tmp_path / "data")
    with pytest.raises(Stopped):
        server.serve(options, echo=printed.append)
    assert ("  rerun viewer  not available: rerun's viewer program is missing at /nowhere (reinstall rerun-sdk)"
            in printed)


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]
