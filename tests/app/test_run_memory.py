"""Memory of one run against the population (issue 36): the probe measured 2.8 GB for `soccer-lab evolve`
at population 10,000 (the rule-set distance's dense N x N matrices); the target is at most 1 GB.
benchmarks/server_memory.py measures the figures the docs show, serve's included."""

from __future__ import annotations

import subprocess
import sys

import pytest

LIMIT_MB = 1024


@pytest.mark.slow
def test_evolve_at_population_10000_peaks_under_1_gb(tmp_path):
    command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "evolve", "--population-size", "10000",
               "--generations", "2", "--workers", "1", "--seed", "1", "--max-ticks", "100", "--out",
               str(tmp_path / "run")]
    # Measured by a small launcher: a child started from pytest's own (large) process shares its memory until
    # it execs (vfork), and its peak then reads as pytest's, not the run's
    launcher = ("import resource, subprocess, sys; done = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL); "
                "print(done.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    done = subprocess.run([sys.executable, "-c", launcher, *command], capture_output=True, text=True, timeout=900)
    status, peak_kb = map(int, done.stdout.split())
    assert status == 0, done.stderr
    assert peak_kb / 1024 < LIMIT_MB, f"peak {peak_kb / 1024:.0f} MB"
    assert (tmp_path / "run" / "statistics.csv").read_text().count("\n") == 3  # header and both generations
