"""Stop latency and peak memory of a run in generation 0, against the population (issue 22, "Stop means
stop"), as the user sees it: a run started through the app's RunManager (what the API and the UI call),
stopped once its first chunk is evaluated; the latency is from the stop asked for to the run's row
leaving 'running' (the answer the API and the UI show). Each population runs in a fresh process, whose
peak resident memory (the kernel's maxrss) is the figure. Also how long `soccer-lab serve` takes to exit
after SIGTERM with such a run going.

    python benchmarks/stop_latency.py [--populations 200 1000 10000] [--record]

Games are the defaults (1000 ticks at most, sighted skills); workers 1 (the app's default).
"""

from __future__ import annotations

import argparse
import json
import resource
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from results import Figure, add_record_option, load_average, record

ROOT = Path(__file__).resolve().parent.parent
POLL_S = 0.01


def one_population(population: int) -> dict:
    """In this (fresh) process: start a run of `population`, stop it after its first chunk."""
    sys.path.insert(0, str(ROOT))
    from soccer_lab.app.paths import DATABASE_FILE
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import RunStatus, Store

    with tempfile.TemporaryDirectory() as folder:
        store = Store(Path(folder) / DATABASE_FILE)
        runs = RunManager(store, folder)
        started = time.perf_counter()
        record_ = runs.start("bench", {"population_size": population, "max_generations": 2, "seed": 1})
        while not ((p := runs.progress(record_.id)) and p.evaluated):
            time.sleep(POLL_S)
        first_chunk = time.perf_counter() - started
        asked = time.perf_counter()
        runs.stop(record_.id, wait=0.0)
        while store.get_run(record_.id).status is RunStatus.RUNNING:
            time.sleep(POLL_S)
        latency = time.perf_counter() - asked
        runs.wait(record_.id, timeout=60)
        thread_ended = time.perf_counter() - asked
        status = str(store.get_run(record_.id).status)
        store.close()
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return {"population": population, "first_chunk_s": first_chunk, "stop_latency_s": latency,
            "thread_ended_s": thread_ended, "status": status, "peak_mb": peak_mb}


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def serve_exit(population: int) -> float:
    """Seconds from SIGTERM to `soccer-lab serve`'s exit, a run of `population` in its generation 0."""
    import httpx

    with tempfile.TemporaryDirectory() as folder:
        ports = [free_port() for _ in range(2)]
        command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", folder,
                   "--port", str(ports[0]), "--ui-port", str(ports[1])]
        serve = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        api = f"http://127.0.0.1:{ports[0]}/api"
        try:
            for _ in range(600):
                try:
                    if httpx.get(f"{api}/server", timeout=1).status_code == 200:
                        break
                except httpx.HTTPError:
                    time.sleep(0.1)
            run = httpx.post(f"{api}/runs", json={"ga": {"population_size": population, "seed": 1}},
                             headers={"Content-Type": "application/json"}, timeout=30).json()
            while not (httpx.get(f"{api}/runs/{run['id']}", timeout=30).json().get("progress") or {}).get("evaluated"):
                time.sleep(0.05)
            sent = time.perf_counter()
            serve.send_signal(signal.SIGTERM)
            serve.wait(120)
            return time.perf_counter() - sent
        finally:
            if serve.poll() is None:
                serve.kill()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--populations", type=int, nargs="+", default=[200, 1000, 10000])
    parser.add_argument("--one", type=int, help=argparse.SUPPRESS)  # a child process measuring one population
    add_record_option(parser)
    args = parser.parse_args()
    if args.one:
        print(json.dumps(one_population(args.one)))
        return
    load_before = load_average()
    figures = []
    for population in args.populations:
        out = subprocess.run([sys.executable, __file__, "--one", str(population)], capture_output=True, text=True,
                             cwd=ROOT, check=True).stdout
        row = json.loads(out.strip().splitlines()[-1])
        print(f"population {population:>7}: first chunk after {row['first_chunk_s']:.2f} s, stop seen after "
              f"{row['stop_latency_s']:.3f} s (thread ended after {row['thread_ended_s']:.3f} s), status "
              f"{row['status']}, peak memory {row['peak_mb']:.0f} MB")
        figures += [Figure(f"stop latency, population {population}", round(row["stop_latency_s"], 3), "s",
                           target="about 1 s", note="from the stop asked for to the run's row leaving 'running'"),
                    Figure(f"peak memory, population {population}", round(row["peak_mb"]), "MB",
                           note="the whole app process (RunManager, store, run thread) in generation 0")]
    exit_seconds = serve_exit(args.populations[-1])
    print(f"serve exits {exit_seconds:.2f} s after SIGTERM (population {args.populations[-1]} in generation 0)")
    figures.append(Figure("serve exit after SIGTERM", round(exit_seconds, 2), "s", target="<= 3 s",
                          note=f"a run of population {args.populations[-1]} in its generation 0"))
    print(f"load average before {load_before}, after {load_average()}")
    if args.record:
        record("stop_latency", figures, command="python benchmarks/stop_latency.py " +
               " ".join(["--populations", *map(str, args.populations)]), load_before=load_before)


if __name__ == "__main__":
    main()
