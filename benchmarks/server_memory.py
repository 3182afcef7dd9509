"""The memory of `soccer-lab serve` (issue 25: every request's cost bounded, nothing leaks), measured on a
real serve process: its resident memory and threads after the heaviest request each route allows, then
across 100 generations of runs (5 runs x 20 generations, one after another). Then, against the population
(issue 36: memory linear in it), for each population a run of 2 generations: the peak memory of
`soccer-lab evolve --workers 1` (past MAX_POPULATION, which the CLI and the API refuse, the same run played
by soccer_lab.app.runs.run.Run directly) and of a fresh serve running it, the run's checkpoint and lineage.jsonl
sizes, how long the lineage and population requests of its last generation take, and how long a stop
takes asked as generation 0's evaluation ends (the end-of-generation work, which a stop waits for, then begins).

    python benchmarks/server_memory.py [--runs 5] [--generations 20] [--populations 200 1000 10000 50000]
                                       [--only-populations] [--record]

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

POPULATIONS = (200, 1_000, 10_000, 50_000)

from results import Figure, add_record_option, load_average, record, this_command

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
HEADERS = {"Content-Type": "application/json"}


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def rule_text(rules: int) -> str:
    from soccer_lab.fuzzy.printer import format_rulebase
    from soccer_lab.fuzzy.random_rulebase import random_rulebase
    from soccer_lab.fuzzy.vocabulary import Vocabulary

    vocabulary = Vocabulary.default()
    return format_rulebase(random_rulebase(np.random.default_rng(1), vocabulary, rules), vocabulary)


def memory(process: psutil.Process) -> tuple[float, float, int]:
    """Resident MB now, the peak so far (VmHWM), threads."""
    status = Path(f"/proc/{process.pid}/status").read_text()
    peak = next(int(line.split()[1]) for line in status.splitlines() if line.startswith("VmHWM")) / 1024
    return process.memory_info().rss / 2**20, peak, process.num_threads()


def start_serve(folder: str) -> tuple[subprocess.Popen, str]:
    port = free_port()
    command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", folder,
               "--port", str(port), "--ui-port", str(free_port())]
    serve = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    api = f"http://127.0.0.1:{port}/api"
    while True:
        try:
            if httpx.get(f"{api}/server", timeout=5).status_code == 200:
                return serve, api
        except httpx.HTTPError:
            time.sleep(0.2)


# Past MAX_POPULATION the CLI refuses: the run is played by the code `soccer-lab evolve` calls (soccer_lab.app.runs.run.Run),
# its GAConfig copied past the bound
BEYOND_THE_BOUND = """
import sys
from soccer_lab.app.runs.run import Run, RunSettings
from soccer_lab.ga.config import GAConfig
ga = GAConfig(max_generations=2, workers=1, seed=1).model_copy(update={"population_size": int(sys.argv[1])})
run = Run.create(RunSettings(ga=ga), sys.argv[2])
with run.evaluator() as evaluate:
    run.play(evaluate)
"""


def cli_run(population: int, folder: Path) -> float:
    """Peak resident MB of `soccer-lab evolve` playing 2 generations of `population` in one process."""
    from soccer_lab.ga.config import MAX_POPULATION

    command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "evolve", "--population-size",
               str(population), "--generations", "2", "--workers", "1", "--seed", "1", "--out", str(folder)]
    if population > MAX_POPULATION:
        command = [sys.executable, "-c", BEYOND_THE_BOUND, str(population), str(folder)]
    child = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode:
        raise SystemExit(f"soccer-lab evolve --population-size {population} failed ({child.returncode})")
    return usage.ru_maxrss / 1024


def timed_get(http: httpx.Client, url: str) -> float:
    started = time.perf_counter()
    response = http.get(url)
    response.raise_for_status()
    return time.perf_counter() - started


def generation_0_evaluated(run: dict) -> bool:
    """Whether the run is past its generation 0's last evaluation: in its end-of-generation work (statistics,
    checkpoint, lineage, breeding), which a stop waits for, or in generation 1."""
    progress = run.get("progress") or {}
    evaluated = progress.get("evaluated")
    return progress.get("generation", 0) >= 1 or (evaluated is not None and evaluated == progress.get("population"))


def serve_run(population: int, folder: str) -> dict:
    """A fresh serve runs 2 generations of `population`: its peak, its lineage requests' times, then a second
    run is stopped as its generation 0's evaluation ends."""
    serve, api = start_serve(folder)
    http = httpx.Client(headers=HEADERS, timeout=600)
    try:
        ga = {"population_size": population, "max_generations": 2, "target_fitness": 0.0, "seed": 1}
        run = http.post(f"{api}/runs", json={"ga": ga}).json()
        while http.get(f"{api}/runs/{run['id']}").json()["status"] == "running":
            time.sleep(0.2)
        peak = memory(psutil.Process(serve.pid))[1]
        lineage_s = timed_get(http, f"{api}/runs/{run['id']}/lineage")
        page_s = timed_get(http, f"{api}/runs/{run['id']}/population?generation=1&limit=50")
        second = http.post(f"{api}/runs", json={"ga": {**ga, "max_generations": 3, "seed": 2}}).json()
        while not generation_0_evaluated(http.get(f"{api}/runs/{second['id']}").json()):
            time.sleep(0.02)
        asked = time.perf_counter()
        http.post(f"{api}/runs/{second['id']}/stop")
        while http.get(f"{api}/runs/{second['id']}").json()["status"] == "running":
            time.sleep(0.02)
        stop_s = time.perf_counter() - asked
        return {"peak": peak, "lineage_s": lineage_s, "page_s": page_s, "stop_s": stop_s}
    finally:
        serve.send_signal(signal.SIGTERM)
        serve.wait(60)


def population_figures(populations: list[int]) -> list[Figure]:
    from soccer_lab.ga.config import MAX_POPULATION

    figures: list[Figure] = []
    peaks: dict[str, dict[int, float]] = {"evolve": {}, "serve": {}}
    for population in populations:
        load = load_average()
        at = f"population {population:,}"
        with tempfile.TemporaryDirectory() as folder:
            cli_peak = peaks["evolve"][population] = cli_run(population, Path(folder) / "cli")
            files = Path(folder) / "cli"
            past = population > MAX_POPULATION
            figures += [Figure(f"evolve peak, {at}", round(cli_peak), "MB", target="<= 1,000 MB at 10,000",
                               note=f"2 generations, one process; load {load}"
                                    + ("; past MAX_POPULATION: soccer_lab.app.runs.run.Run, as evolve plays it" if past else "")),
                        Figure(f"checkpoint, {at}", round((files / "checkpoint").stat().st_size / 2**20, 1), "MB"),
                        Figure(f"lineage.jsonl, {at}", round((files / "lineage.jsonl").stat().st_size / 2**20, 1),
                               "MB", note="2 generations")]
            print(f"{at}: evolve peak {cli_peak:.0f} MB, checkpoint {figures[-2].value} MB, lineage "
                  f"{figures[-1].value} MB (load {load})")
            if past:
                continue  # the API refuses it
            served = serve_run(population, str(Path(folder) / "serve"))
        peaks["serve"][population] = served["peak"]
        print(f"{at}: serve peak {served['peak']:.0f} MB, lineage request {served['lineage_s']:.2f} s, population "
              f"page {served['page_s']:.2f} s, stop after generation 0 {served['stop_s']:.2f} s (load {load_average()})")
        figures += [Figure(f"serve peak, {at}", round(served["peak"]), "MB", target="<= 1,000 MB at 10,000",
                           note="a fresh serve running 2 generations"),
                    Figure(f"lineage request, {at}", round(served["lineage_s"], 2), "s", target="<= 0.5 s",
                           note=f"population page (50) {served['page_s']:.2f} s"),
                    Figure(f"stop after generation 0, {at}", round(served["stop_s"], 2), "s", target="<= 1 s at 10,000")]
    for name, peak in peaks.items():
        if len(peak) >= 2:
            small, large = min(peak), max(peak)
            per = (peak[large] - peak[small]) * 2**20 / (large - small)
            print(f"{name}: {per:,.0f} bytes per individual (peak from population {small:,} to {large:,})")
            figures.append(Figure(f"{name} peak per individual", round(per), "bytes",
                                  note=f"slope of the peak from population {small:,} to {large:,}"))
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--generations", type=int, default=20)
    parser.add_argument("--populations", type=int, nargs="*", default=list(POPULATIONS))
    parser.add_argument("--only-populations", action="store_true", help="skip the heavy requests and the 100 generations")
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    figures = [] if args.only_populations else request_figures(args)
    figures += population_figures(args.populations)
    print(f"load average before {load_before}, after {load_average()}")
    if args.record:
        record("server_memory", figures, command=this_command(), load_before=load_before)


def request_figures(args: argparse.Namespace) -> list[Figure]:
    from soccer_lab.app.rule_inspection import MAX_RULES, SIMPLIFY_PLAYS, USAGE_PLAYS, affordable_games
    from soccer_lab.ga.config import MAX_POPULATION

    folder = tempfile.mkdtemp()
    port = free_port()
    command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", folder,
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
    return figures


if __name__ == "__main__":
    main()
