"""Against a real rcssserver, when one is installed (it is on no package registry; see README)."""

import shutil
import socket
import subprocess
import time

import pytest

from soccer.rcss.client import Timeouts
from soccer.rcss.evaluate import RcssEvaluator
from soccer.rcss.trial import TrialConfig

SERVER = shutil.which("rcssserver")
pytestmark = pytest.mark.skipif(
    SERVER is None, reason="no rcssserver executable on PATH (build it from the RoboCup project to run this test)"
)


def free_port_triple() -> int:
    """A port P with P, P+1, P+2 free (player, trainer, online coach)."""
    for _ in range(50):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        if port + 2 < 65535:
            return port
    raise RuntimeError("no free ports")


@pytest.fixture
def rcssserver(tmp_path):
    port = free_port_triple()
    process = subprocess.Popen(
        [SERVER, f"server::port={port}", f"server::coach_port={port + 1}", f"server::olcoach_port={port + 2}",
         "server::synch_mode=true", "server::auto_mode=false", "server::coach=true",
         "server::coach_w_referee=true", "server::game_logging=false", "server::text_logging=false",
         "server::use_offside=false", "server::free_kick_faults=false", "server::nr_extra_halfs=0",
         "server::penalty_shoot_outs=false"],
        cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    time.sleep(1.0)
    yield f"127.0.0.1:{port}"
    process.terminate()
    process.wait(timeout=10)


def test_two_short_trials_on_a_real_server(rcssserver, chaser):
    with RcssEvaluator([rcssserver], TrialConfig(max_cycles=200), timeouts=Timeouts(connect=5.0)) as evaluate:
        results = evaluate([chaser, chaser], [1, 2])
    for result in results:
        assert 0 < result.ticks <= 200
        assert 0.0 < result.fitness <= 1.0
        assert result.kicks >= 0 and result.goals >= 0
