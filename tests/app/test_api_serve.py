"""`soccer-lab serve` refuses busy ports with one line and exit status 2, before starting anything."""

from __future__ import annotations

import socket

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app



@pytest.fixture
def busy_port():
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        yield holder.getsockname()[1]


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.mark.parametrize("option, what", [("--port", "API server"), ("--ui-port", "UI")])
def test_busy_port_is_an_error_naming_it(tmp_path, busy_port, option, what):
    ports = {"--port": free_port(), "--ui-port": free_port(), option: busy_port}
    arguments = ["serve", "--data-dir", str(tmp_path / "data")]
    for name, port in ports.items():
        arguments += [name, str(port)]
    result = CliRunner().invoke(app, arguments)
    assert result.exit_code == 2
    assert result.output.strip().splitlines() == [
        f"error: port {busy_port} for the {what} is busy: stop what uses it or choose another with {option}"
    ]
    assert not (tmp_path / "data").exists()  # nothing started, nothing created


def test_ports_must_differ(tmp_path):
    port = str(free_port())
    result = CliRunner().invoke(app, ["serve", "--port", port, "--ui-port", port, "--data-dir", str(tmp_path)])
    assert result.exit_code == 2
    assert "must be two different ports" in result.output


def test_out_of_range_port_is_a_usage_error(tmp_path):
    result = CliRunner().invoke(app, ["serve", "--port", "70000", "--data-dir", str(tmp_path)])
    words = " ".join(result.output.replace("│", " ").split())  # typer boxes and wraps usage errors
    assert result.exit_code == 2 and "should be less than or equal to 65535" in words


def test_default_data_dir_follows_the_environment(monkeypatch, tmp_path):
    from soccer_lab.app.paths import default_data_dir

    monkeypatch.setenv("SOCCER_LAB_DATA", str(tmp_path / "explicit"))
    assert default_data_dir() == tmp_path / "explicit"
    monkeypatch.delenv("SOCCER_LAB_DATA")
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "xdg"))
    assert default_data_dir() == tmp_path / "xdg" / "soccer-lab"
    monkeypatch.delenv("XDG_DATA_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert default_data_dir() == tmp_path / "home" / ".local" / "share" / "soccer-lab"
