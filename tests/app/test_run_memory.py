"""Memory of one run against the population (issue 36): the probe measured 2.8 GB for `soccer-lab evolve`
at population 10,000 (the rule-set distance's dense N x N matrices); the target is at most 1 GB.
benchmarks/server_memory.py measures the figures the docs show, serve's included."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

LIMIT_MB = 1024


@pytest.mark.slow
def test_evolve_at_population_10000_peaks_under_1_gb(tmp_path):
    command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "evolve", "--population-size", "10000",
               "--generations", "2", "--workers", "1", "--seed", "1", "--max-ticks", "100", "--out",
               str(tmp_path / "run")]
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)  # this child's own peak resident memory
    assert os.waitstatus_to_exitcode(status) == 0, child.stderr.read().decode()
    assert usage.ru_maxrss / 1024 < LIMIT_MB, f"peak {usage.ru_maxrss / 1024:.0f} MB"
    assert (tmp_path / "run" / "statistics.csv").read_text().count("\n") == 3  # header and both generations
