"""Throughput on real rcssservers in synch mode, with 1 and with 2 servers that soccer-lab starts itself:
simulator cycles per second (whole trials of a player that runs, kicks and scores) and GA evaluations per
second (a small evolution from random rulebases, the chapter's RoboCup trials). Targets: at least 1,000
cycles/s per server, and 2 servers nearly twice one (each server steps only when its client says (done),
so the client's own work per cycle counts as much as the server's). For the striker it also prints the
CPU time per cycle of the clients (this process with one server, the client processes with two) and of
the servers, read from /proc (Linux), and what share of a core each took.

    python benchmarks/rcss_throughput.py [--rcssserver PATH] [--trials 4] [--population 20] [--generations 2]
                                         [--rounds 2]

The executable comes from --rcssserver, else $RCSSSERVER, else `rcssserver` on PATH. Rounds alternate
1 and 2 servers, so other load on the machine affects both alike; the load average is printed.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path
from typing import NamedTuple, Sequence

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.ga.algorithms import evolve
from soccer_lab.ga.config import GAConfig
from soccer_lab.soccer.config import SOCCER_VOCABULARY
from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
from soccer_lab.soccer.rcss.servers import ServerPool
from soccer_lab.soccer.rcss.trial import TrialConfig, TrialResult
from results import Figure, add_record_option, record, this_command  # benchmarks/results.py

# A player that goes to the ball and kicks it towards the goal: it plays whole trials (it scores, so
# neither the idle limit nor out-of-play ends them early), every cycle with a decision.
STRIKER = parse_rulebase("""
if Ball is not At then GoToBall High
if Ball is At then KickTowardGoal VeryHigh
""", SOCCER_VOCABULARY)
TARGET_PER_SERVER = 1000.0  # cycles/s
NEARLY_TWICE = 1.8


class CountingEvaluator:
    """The rcss evaluator, counting the cycles its trials played."""

    def __init__(self, evaluate: RcssEvaluator):
        self.evaluate = evaluate
        self.cycles = 0
        self.trials = 0

    def __call__(self, rulebases: Sequence, seeds: Sequence[int]) -> list[TrialResult]:
        results = self.evaluate(rulebases, seeds)
        self.cycles += sum(result.ticks for result in results)
        self.trials += len(results)
        return results


def cpu_seconds(pid: int) -> float:
    """User and system CPU time of a process so far (0 once it is gone)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def children() -> set[int]:
    """This process's child processes (servers and client processes)."""
    pids: set[int] = set()
    for task in Path(f"/proc/{os.getpid()}/task").iterdir():
        try:
            pids.update(int(pid) for pid in (task / "children").read_text().split())
        except OSError:
            pass
    return pids


class CpuUse(NamedTuple):
    client: float  # CPU seconds of the clients: this process and its children other than servers
    server: float  # CPU seconds of the servers


def cpu_use(pool: ServerPool) -> CpuUse:
    servers = {server.pid for server in pool.servers}
    clients = children() - servers
    return CpuUse(time.process_time() + sum(map(cpu_seconds, clients)), sum(map(cpu_seconds, servers)))


class StrikerRun(NamedTuple):
    cycles_per_second: float
    cycles: int
    client_ms: float  # CPU per cycle
    server_ms: float
    client_cores: float  # CPU seconds per second of wall time
    server_cores: float


def striker_cycles(pool: ServerPool, trials: int) -> StrikerRun:
    """Cycles/s over all servers and CPU per cycle for `trials` whole trials of the striker."""
    with RcssEvaluator(pool.addresses, TrialConfig()) as evaluate:
        evaluate.connect()
        before = cpu_use(pool)
        started = time.perf_counter()
        results = evaluate([STRIKER] * trials, list(range(trials)))
        seconds = time.perf_counter() - started
        after = cpu_use(pool)  # before the client processes end
    cycles = sum(result.ticks for result in results)
    client, server = after.client - before.client, after.server - before.server
    return StrikerRun(cycles / seconds, cycles, 1000 * client / cycles, 1000 * server / cycles, client / seconds,
                      server / seconds)


def evolution(pool: ServerPool, population: int, generations: int) -> tuple[float, float, int]:
    """(evaluations/s, cycles/s, evaluations) of a small GA run from random rulebases."""
    config = GAConfig(population_size=population, max_generations=generations, workers=1, seed=1,
                      target_fitness=0.0)
    with RcssEvaluator(pool.addresses, TrialConfig()) as rcss:
        rcss.connect()
        counting = CountingEvaluator(rcss)
        started = time.perf_counter()
        result = evolve(config, counting, SOCCER_VOCABULARY)
        seconds = time.perf_counter() - started
    return result.evaluations / seconds, counting.cycles / seconds, result.evaluations


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rcssserver", default=None, help="the rcssserver executable")
    parser.add_argument("--trials", type=int, default=4, help="striker trials per measurement (1200 cycles each)")
    parser.add_argument("--population", type=int, default=20)
    parser.add_argument("--generations", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=2, help="alternating 1-server and 2-server measurements")
    add_record_option(parser)
    args = parser.parse_args()

    load_before = os.getloadavg()
    cycles: dict[int, list[float]] = {1: [], 2: []}
    evaluations: dict[int, list[float]] = {1: [], 2: []}
    evolution_cycles: dict[int, list[float]] = {1: [], 2: []}
    for round_number in range(args.rounds):
        for servers in (1, 2):
            with ServerPool(args.rcssserver, servers) as pool:
                run = striker_cycles(pool, args.trials)
                cycles[servers].append(run.cycles_per_second)
            with ServerPool(args.rcssserver, servers) as pool:
                per_second, cycle_rate, count = evolution(pool, args.population, args.generations)
                evaluations[servers].append(per_second)
                evolution_cycles[servers].append(cycle_rate)
            print(f"round {round_number + 1}, {servers} server{'s' if servers > 1 else ''}: striker "
                  f"{run.cycles_per_second:.0f} cycles/s ({run.cycles} cycles; CPU per cycle: client "
                  f"{run.client_ms:.3f} ms, server {run.server_ms:.3f} ms; cores busy: clients {run.client_cores:.2f}, "
                  f"servers {run.server_cores:.2f}); evolution {per_second:.1f} evaluations/s, {cycle_rate:.0f} "
                  f"cycles/s ({count} evaluations)", flush=True)
    load_after = os.getloadavg()

    one, two = statistics.median(cycles[1]), statistics.median(cycles[2])
    print(f"\nmedian over {args.rounds} rounds (load average {load_before[0]:.1f} before, {load_after[0]:.1f} after, "
          f"{os.cpu_count()} cores)")
    print(f"cycles/s, striker:   1 server {one:.0f}; 2 servers {two:.0f} ({two / 2:.0f} per server), "
          f"{two / one:.2f}x one")
    print(f"evaluations/s:       1 server {statistics.median(evaluations[1]):.1f}; "
          f"2 servers {statistics.median(evaluations[2]):.1f} "
          f"({statistics.median(evaluations[2]) / statistics.median(evaluations[1]):.2f}x)")
    print(f"cycles/s, evolution: 1 server {statistics.median(evolution_cycles[1]):.0f}; "
          f"2 servers {statistics.median(evolution_cycles[2]):.0f}")
    print(f"target: >= {TARGET_PER_SERVER:.0f} cycles/s per server: {'met' if one >= TARGET_PER_SERVER else 'MISSED'}; "
          f"2 servers >= {NEARLY_TWICE}x one: {'met' if two >= NEARLY_TWICE * one else 'MISSED'}")
    if args.record:
        record("rcss_throughput", [
            Figure("rcssserver in synch mode, one server, a striker's 1200-cycle trials", round(one), "cycles/s",
                   target=f"≥ {TARGET_PER_SERVER:.0f} cycles/s per server"),
            Figure("two servers, each with its own client, against one", round(two / one, 2), "×",
                   target=f"≈ 2× ({NEARLY_TWICE}×)", note=f"{two:.0f} cycles/s in all"),
            Figure("evolution on one server", round(statistics.median(evaluations[1]), 1), "evaluations/s"),
        ], command=this_command(), load_before=[round(x, 2) for x in load_before])


if __name__ == "__main__":
    main()
