"""rcssservers on a Ray cluster (app/runs/rcss_cluster.py), with a local Ray and the real server: every node starts
its own servers, trials spread over all of them, the results are those of local servers without noise (the
GA's too, from the command line), a server whose actor is killed hands its trial on and dies with it, and no
server is left running after a run or an interrupted one."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.runs.rcss_cluster import ClusterServers, RayCluster, node_servers
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
from soccer_lab.soccer.rcss.servers import NOISELESS_OPTIONS
from soccer_lab.soccer.rcss.trial import TrialConfig
from tests.rcss.conftest import VOCABULARY

ray = pytest.importorskip("ray")
QUIET = TrialConfig(max_ticks=200, skills="assisted", noise=False)
RULES = [parse_rulebase(text, VOCABULARY) for text in (
    "if Ball is not At then GoToBall High\nif Ball is At then KickTowardGoal VeryHigh",
    "if Ball is not At then GoToBall VeryHigh\nif Ball is At then KickTowardGoal Low",
    "if Ball is not At then GoToBall High\nif Ball is At then Kick Left Low",  # kicks, never scores
)]
BATCH = [(rules, seed) for rules in RULES for seed in (1, 2, 3)]


def outcome(results) -> list[tuple]:
    return [(r.fitness, r.goals, r.kicks, r.ticks, r.end) for r in results]


def gone(pids, within: float = 15.0) -> bool:
    """Every process in `pids` has exited (waiting up to `within` seconds)."""
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        alive = []
        for pid in pids:
            try:
                os.kill(pid, 0)
                alive.append(pid)
            except ProcessLookupError:
                pass
        if not alive:
            return True
        time.sleep(0.2)
    return False


@pytest.fixture(scope="module")
def local_ray():
    """A Ray of 2 CPUs on this machine for the module (a busy machine may need a second try to start it)."""
    for attempt in range(2):
        try:
            ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
            break
        except Exception:  # noqa: BLE001 - Ray's own start-up timeout, on a loaded machine
            if attempt:
                raise
    yield
    ray.shutdown()


@pytest.fixture(scope="module")
def local_results(rcssserver):
    """BATCH played on a local server without noise: what the cluster must give."""
    from soccer_lab.soccer.rcss.servers import ServerPool

    with ServerPool(rcssserver, 1, NOISELESS_OPTIONS) as pool, RcssEvaluator(pool.addresses, QUIET) as evaluate:
        results = evaluate(*zip(*BATCH))
    assert any(r.goals for r in results) and any(r.kicks and not r.goals for r in results)  # a telling batch
    return outcome(results)


def test_servers_per_node_default_to_one_per_cpu_and_share_cpus_beyond():
    assert node_servers(4.0, None) == (4, 1.0)
    assert node_servers(2.0, 4) == (4, 0.5)
    assert node_servers(0.5, None) == (1, 0.5)


def test_trials_spread_over_the_cluster_servers_and_match_local_ones(local_ray, rcssserver, local_results):
    lines = []
    with ClusterServers(RayCluster(servers_per_node=2, rcssserver=str(rcssserver)), QUIET, announce=lines.append) \
            as evaluate:
        evaluate.connect()
        pids = [place["pid"] for place in evaluate.places]
        assert len(pids) == 2 and lines[0].startswith("started 2 rcssservers on 1 Ray node: node ")
        assert outcome(evaluate(*zip(*BATCH))) == local_results
        assert sorted(evaluate.played) == sorted(place["address"] for place in evaluate.places)  # both played
        assert sum(evaluate.played.values()) == len(BATCH)
    assert gone(pids)


def test_a_killed_actor_hands_its_trial_to_another_and_its_server_dies_with_it(local_ray, rcssserver, local_results):
    lines = []
    with ClusterServers(RayCluster(servers_per_node=2, rcssserver=str(rcssserver)), QUIET, announce=lines.append) \
            as evaluate:
        evaluate.connect()
        victim, survivor = evaluate.places
        os.kill(victim["worker"], signal.SIGKILL)  # as a node's death ends its actors
        assert outcome(evaluate(*zip(*BATCH))) == local_results
        assert gone([victim["pid"]])
        assert any(line.startswith(f"lost {victim['address']} on node ") for line in lines)
        assert [place["address"] for place in evaluate.places] == [survivor["address"]]
    assert gone([survivor["pid"]])


def test_a_server_that_cannot_start_on_the_cluster_is_one_line(local_ray, tmp_path):
    from soccer_lab.app.runs.rcss_cluster import ClusterError

    with pytest.raises(ClusterError, match=r"no rcssserver started on the Ray cluster: on Ray node \S+: no "
                                           r"rcssserver: '/no/such/rcssserver' does not exist"):
        with ClusterServers(RayCluster(servers_per_node=1, rcssserver="/no/such/rcssserver"), QUIET) as evaluate:
            evaluate.connect()


def csv_rows(path: Path) -> list[list[str]]:
    """statistics.csv without its wall-time column (the only one that may differ)."""
    lines = [line.split(",") for line in path.read_text().splitlines()]
    column = lines[0].index("wall_time")
    return [line[:column] + line[column + 1:] for line in lines]


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_robocup_and_evolve_on_the_cluster_give_the_local_statistics(local_ray, rcssserver, tmp_path):
    shrunk = ["--trials", "2", "--population", "6", "--generations", "2", "--max-ticks", "150", "--seed", "2",
              "--no-noise", "--skills", "assisted", "--rcssserver", rcssserver, "--no-library"]
    for executor in ("local", "ray"):
        result = run("experiment", "robocup", *shrunk, "--executor", executor, "--servers", "2",
                     "--out", tmp_path / f"robocup-{executor}")
        assert result.exit_code == 0, result.output
    assert "on 1 Ray node" in result.output
    local, cluster = (csv_rows(tmp_path / f"robocup-{e}" / "statistics.csv") for e in ("local", "ray"))
    best = local[0].index("best")
    assert cluster == local and {row[best] for row in local[1:]} != {"1.0"}  # and not every fitness the worst
    evolve = ["--env", "rcss", "--population-size", "6", "--generations", "2", "--max-ticks", "150", "--seed", "5",
              "--no-noise", "--skills", "assisted", "--rcssserver", rcssserver, "--servers", "2"]
    for executor in ("local", "ray"):
        result = run("evolve", *evolve, "--executor", executor, "--out", tmp_path / f"evolve-{executor}")
        assert result.exit_code == 0, result.output
    local, cluster = (csv_rows(tmp_path / f"evolve-{e}" / "statistics.csv") for e in ("local", "ray"))
    assert cluster == local


def test_ctrl_c_stops_every_server_of_the_cluster(rcssserver, tmp_path):
    """An evolve run on a Ray it started, interrupted as by Ctrl+C once its servers play: exit status 130, the
    run resumable, and none of its servers left."""
    command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "evolve", "--env", "rcss", "--executor",
               "ray", "--servers", "2", "--rcssserver", str(rcssserver), "--population-size", "40",
               "--generations", "50", "--skills", "assisted", "--out", str(tmp_path / "run")]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    started, lines = threading.Event(), []

    def read() -> None:
        for line in process.stderr:
            lines.append(line)
            if "rcssservers on 1 Ray node" in line:
                started.set()

    threading.Thread(target=read, daemon=True).start()
    try:
        assert started.wait(300), "".join(lines)
        time.sleep(3)  # trials under way
        process.send_signal(signal.SIGINT)
        assert process.wait(120) == 130, "".join(lines)
    finally:
        if process.poll() is None:
            process.kill()
    announced = next(line for line in lines if "rcssservers on 1 Ray node" in line)
    pids = [int(pid) for pid in re.findall(r"\(pid (\d+)\)", announced)]
    assert len(pids) == 2 and gone(pids, within=30)
    assert any("interrupted; continue with: soccer-lab evolve --resume" in line for line in lines)
