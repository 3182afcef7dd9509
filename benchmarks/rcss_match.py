"""Wall time of one match on a real rcssserver in synch mode (as trials run it): two of our clients, one per side,
the demo against the striker, two halves of 1000 cycles each (the goal cap and idle limit raised so that neither
ends a half early), the server's default noise. Also the whole command's time: the server started, the clients
connected, the match, the server stopped (what `soccer-lab match A B --matches 1 --env rcss` costs beyond
importing soccer-lab).

    python benchmarks/rcss_match.py [--rcssserver PATH] [--rounds 3] [--cycles 1000]

The executable comes from --rcssserver, else $RCSSSERVER, else `rcssserver` on PATH. Medians over the rounds
(each on a new server); the load average is printed.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

from soccer_lab.soccer.examples import example
from soccer_lab.soccer.config import SOCCER_VOCABULARY
from soccer_lab.soccer.rcss.match import RcssMatchConfig, play_rcss_matches
from soccer_lab.soccer.rcss.match_session import MatchSession
from soccer_lab.soccer.rcss.player import load_compiled_skills
from soccer_lab.soccer.rcss.servers import ServerPool
from results import Figure, add_record_option, record, this_command  # benchmarks/results.py


def one_match(executable: str | None, cycles: int) -> tuple[float, float, int, tuple[int, int]]:
    """(seconds of the match, seconds from starting the server to stopping it, cycles played, goals)."""
    config = RcssMatchConfig(max_ticks=cycles, goal_cap=cycles, idle_ticks=cycles)
    demo, striker = (example(name).rulebase(SOCCER_VOCABULARY) for name in ("demo", "striker"))
    started = time.perf_counter()
    with ServerPool(executable, 1) as pool, MatchSession(pool.addresses[0]) as session:
        session.open()
        playing = time.perf_counter()
        (result,) = play_rcss_matches(session, demo, striker, [0], config)
        match_seconds = time.perf_counter() - playing
    return match_seconds, time.perf_counter() - started, sum(half.ticks for half in result.halves), result.goals


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rcssserver", default=None, help="the rcssserver executable")
    parser.add_argument("--rounds", type=int, default=3, help="matches, each on a new server")
    parser.add_argument("--cycles", type=int, default=1000, help="cycles per half")
    add_record_option(parser)
    args = parser.parse_args()

    load_compiled_skills()
    load_before = os.getloadavg()
    matches, wholes = [], []
    for round_number in range(args.rounds):
        match_seconds, whole_seconds, cycles, goals = one_match(args.rcssserver, args.cycles)
        matches.append(match_seconds)
        wholes.append(whole_seconds)
        print(f"round {round_number + 1}: the match {match_seconds:.2f} s ({cycles} cycles, {cycles / match_seconds:.0f} "
              f"cycles/s, goals demo {goals[0]} striker {goals[1]}); server start to stop {whole_seconds:.2f} s",
              flush=True)
    load_after = os.getloadavg()
    match_median, whole_median = statistics.median(matches), statistics.median(wholes)
    print(f"\nmedian over {args.rounds} rounds: the match {match_median:.2f} s, with the server's start and stop "
          f"{whole_median:.2f} s (load average {load_before[0]:.1f} before, {load_after[0]:.1f} after, "
          f"{os.cpu_count()} cores)")
    if args.record:
        halves = f"2 × {args.cycles} cycles"
        record("rcss_match", [
            Figure(f"one match on rcssserver in synch mode, {halves}, two clients", round(match_median, 2), "s",
                   note=f"{2 * args.cycles / match_median:.0f} cycles/s; median of {args.rounds}"),
            Figure("the same match with the server started and stopped", round(whole_median, 2), "s",
                   note=f"median of {args.rounds}"),
        ], command=this_command(), load_before=[round(x, 2) for x in load_before])


if __name__ == "__main__":
    main()
