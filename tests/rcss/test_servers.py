"""The launcher: real rcssservers on free ports in scratch folders, and none left running after the block
ends, the program is interrupted (Ctrl+C, SIGTERM), exits without stopping them, or is killed."""

from __future__ import annotations

import shutil
import signal
import socket
import stat
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import pytest

from soccer_lab.soccer.rcss.client import Session
from soccer_lab.soccer.rcss.servers import RcssLaunchError, ServerPool, find_rcssserver

from .real_server import process_exists, wait_until_gone

CHILD_TIMEOUT = 60


def test_a_pool_starts_answering_servers_and_stops_every_one(start_servers):
    pool = start_servers(2)
    ports = [server.port for server in pool.servers]
    assert len(set(ports)) == 2 and len(pool.addresses) == 2
    folders, pids = [server.folder for server in pool.servers], [server.pid for server in pool.servers]
    for address in pool.addresses:
        with Session(address) as session:
            first = session.open()
            assert first.sense_body.time == 0 and session.params.synch_mode
    assert all((folder / "~" / ".rcssserver").is_dir() for folder in folders)  # it wrote there, nowhere else
    pool.stop()
    assert wait_until_gone(pids) == [] and not any(folder.exists() for folder in folders)
    for port in ports:  # the ports are free again
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            probe.bind(("127.0.0.1", port))


def child(rcssserver: Path, body: str) -> subprocess.Popen:
    """A Python process that starts a pool of 2 servers, prints their PIDs and scratch folders, then runs
    `body` (indented inside the pool's block when it uses `with`)."""
    script = textwrap.dedent("""
        import signal, sys, time
        # Ctrl+C as a terminal's program gets it: a parent that ignores SIGINT (something in a long test
        # session can leave it so) would hand the ignoring on to this child
        signal.signal(signal.SIGINT, signal.default_int_handler)
        from soccer_lab.soccer.rcss.servers import ServerPool
        def report(pool):
            print(" ".join(f"{s.pid}:{s.folder}" for s in pool.servers), flush=True)
    """) + textwrap.dedent(body)
    return subprocess.Popen([sys.executable, "-c", script, str(rcssserver)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def started(process: subprocess.Popen) -> tuple[list[int], list[Path]]:
    line = process.stdout.readline()
    assert line, process.stderr.read()
    pairs = [item.split(":", 1) for item in line.split()]
    return [int(pid) for pid, _ in pairs], [Path(folder) for _, folder in pairs]


IN_A_BLOCK = """
    with ServerPool(sys.argv[1], 2) as pool:
        report(pool)
        time.sleep(60)
"""


@pytest.mark.parametrize("number", [signal.SIGINT, signal.SIGTERM], ids=["ctrl-c", "sigterm"])
def test_an_interrupted_program_stops_its_servers(rcssserver, number):
    process = child(rcssserver, IN_A_BLOCK)
    pids, folders = started(process)
    assert all(process_exists(pid) for pid in pids)
    process.send_signal(number)
    process.wait(CHILD_TIMEOUT)
    assert wait_until_gone(pids) == [] and not any(folder.exists() for folder in folders)


def test_a_program_that_exits_without_stopping_them_stops_them_at_exit(rcssserver):
    process = child(rcssserver, """
        pool = ServerPool(sys.argv[1], 2).start()  # never stopped by the program
        report(pool)
        raise SystemExit(3)
    """)
    pids, folders = started(process)
    assert process.wait(CHILD_TIMEOUT) == 3
    assert wait_until_gone(pids) == [] and not any(folder.exists() for folder in folders)


def test_a_killed_program_leaves_no_server_running(rcssserver):
    process = child(rcssserver, IN_A_BLOCK)
    pids, folders = started(process)
    process.kill()  # SIGKILL: no handler, no atexit; the kernel's parent-death signal ends the servers
    process.wait(CHILD_TIMEOUT)
    assert wait_until_gone(pids) == []
    for folder in folders:  # nobody was left to remove them
        shutil.rmtree(folder)


def test_an_executable_that_is_not_there_is_one_clear_line(tmp_path, monkeypatch):
    monkeypatch.delenv("RCSSSERVER", raising=False)
    with pytest.raises(RcssLaunchError, match=f"no rcssserver: '{tmp_path / 'nothing'}' does not exist"):
        find_rcssserver(tmp_path / "nothing")
    monkeypatch.setenv("RCSSSERVER", "no-such-rcssserver")
    with pytest.raises(RcssLaunchError, match=r"no rcssserver: 'no-such-rcssserver' \(from \$RCSSSERVER\) is not on PATH"):
        find_rcssserver()


def test_a_program_that_is_not_a_server_fails_to_start_with_its_own_words(tmp_path, monkeypatch):
    fake = tmp_path / "rcssserver"
    fake.write_text("#!/bin/sh\necho 'cannot open display' >&2\nexit 1\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))
    with pytest.raises(RcssLaunchError, match="did not start: cannot open display"):
        ServerPool(fake, 2).start()
    assert list(scratch.iterdir()) == []  # no scratch folder left behind
