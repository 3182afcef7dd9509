"""The memory of `soccer-lab serve` (issue 25: every request's cost bounded, nothing leaks), measured on a
real serve process: its resident memory and threads after the heaviest request each route allows, then
across 100 generations of runs (5 runs x 20 generations, one after another).

    python benchmarks/server_memory.py [--runs 5] [--generations 20] [--record]

The heaviest requests: rule usage and simplification at the limits (docs/reference/limits.md: the most
games of 1,000 ticks the work bound allows with 20 and with 1,000 rules), the longest rule text parsed, evaluated and saved,
and a run of the largest population started and stopped in its generation 0.
"""

from __future__ import annotations

import argparse
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np
import psutil

from results import Figure, add_record_option, load_average, record

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
HEADERS = {"Content-Type": "application/json"}


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def rule_text(rules: int) -> str:
    from fuzzy.printer import format_rulebase
    from fuzzy.random_rulebase import random_rulebase
    from fuzzy.vocabulary import Vocabulary

    vocabulary = Vocabulary.default()
    return format_rulebase(random_rulebase(np.random.default_rng(1), vocabulary, rules), vocabulary)


def memory(process: psutil.Process) -> tuple[float, float, int]:
    """Resident MB now, the peak so far (VmHWM), threads."""
    status = Path(f"/proc/{process.pid}/status").read_text()
    peak = next(int(line.split()[1]) for line in status.splitlines() if line.startswith("VmHWM")) / 1024
    return process.memory_info().rss / 2**20, peak, process.num_threads()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--generations", type=int, default=20)
    add_record_option(parser)
    args = parser.parse_args()
    from app.rule_inspection import MAX_RULES, SIMPLIFY_PLAYS, USAGE_PLAYS, affordable_games
    from ga.config import MAX_POPULATION

    load_before = load_average()
    folder = tempfile.mkdtemp()
    port = free_port()
    command = [sys.executable, "-c", "from app.cli import main; main()", "serve", "--data-dir", folder,
               "--port", str(port), "--ui-port", str(free_port())]
    serve = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    api = f"http://127.0.0.1:{port}/api"
    http = httpx.Client(headers=HEADERS, timeout=600)
    figures = []
    try:
        while True:
            try:
                if http.get(f"{api}/server").status_code == 200:
                    break
            except httpx.HTTPError:
                time.sleep(0.2)
        process = psutil.Process(serve.pid)
        idle = memory(process)
        print(f"idle: {idle[0]:.0f} MB resident, {idle[2]} threads")
        figures.append(Figure("serve idle", round(idle[0]), "MB"))
        many = rule_text(MAX_RULES)
        twenty = rule_text(20)
        longest = (many + "\n") * max(1, 190_000 // (len(many) + 1))  # near the 200,000-character text limit
        no_end = {"max_ticks": 1000, "goal_cap": 1000, "idle_ticks": 1000}  # every game plays its 1000 ticks
        heavy = []
        for route, plays in (("usage", USAGE_PLAYS), ("simplify", SIMPLIFY_PLAYS)):
            for rules, text in ((20, twenty), (MAX_RULES, many)):
                games = affordable_games(rules, 1000, plays)  # the most the bound allows
                heavy.append((f"{route}, {rules:,} rules x {games:,} games x 1,000 ticks", "POST", f"/rules/{route}",
                              {"text": text, "games": games, "game": no_end}))
        heavy += [
            ("parse, the longest text", "POST", "/rules/parse", {"text": longest}),
            ("evaluate, 1,000 rules", "POST", "/rules/evaluate", {"text": many}),
            ("save a rulebase of 1,000 rules", "POST", "/rulebases", {"name": "big", "text": many}),
        ]
        for name, method, path, body in heavy:
            started = time.perf_counter()
            response = http.request(method, f"{api}{path}", json=body)
            took = time.perf_counter() - started
            now, peak, threads = memory(process)
            print(f"{name}: HTTP {response.status_code} in {took:.1f} s; after {now:.0f} MB, peak {peak:.0f} MB")
            figures.append(Figure(f"after {name}", round(now), "MB", note=f"peak so far {peak:.0f} MB; {took:.1f} s"))
        run = http.post(f"{api}/runs", json={"ga": {"population_size": MAX_POPULATION, "seed": 1}}).json()
        while not (http.get(f"{api}/runs/{run['id']}").json().get("progress") or {}).get("evaluated"):
            time.sleep(0.1)
        http.post(f"{api}/runs/{run['id']}/stop")
        now, peak, threads = memory(process)
        print(f"a run of population {MAX_POPULATION} stopped in generation 0: after {now:.0f} MB, peak {peak:.0f} MB")
        figures.append(Figure(f"after a run of population {MAX_POPULATION}, stopped", round(now), "MB",
                              note=f"peak so far {peak:.0f} MB"))
        rows = []
        for i in range(args.runs):
            run = http.post(f"{api}/runs", json={"ga": {"population_size": 20, "max_generations": args.generations,
                                                         "target_fitness": 0.0, "seed": i}}).json()
            while http.get(f"{api}/runs/{run['id']}").json()["status"] == "running":
                time.sleep(0.2)
            rows.append(memory(process))
            print(f"after run {i + 1} ({(i + 1) * args.generations} generations): {rows[-1][0]:.0f} MB, "
                  f"{rows[-1][2]} threads")
        figures += [Figure(f"after {args.generations} generations of runs", round(rows[0][0]), "MB",
                           note=f"{rows[0][2]} threads"),
                    Figure(f"after {args.runs * args.generations} generations of runs", round(rows[-1][0]), "MB",
                           note=f"{rows[-1][2]} threads")]
    finally:
        serve.send_signal(signal.SIGTERM)
        serve.wait(60)
    print(f"load average before {load_before}, after {load_average()}")
    if args.record:
        record("server_memory", figures, command=f"python benchmarks/server_memory.py --runs {args.runs} "
               f"--generations {args.generations}", load_before=load_before)


if __name__ == "__main__":
    main()
