"""Issue 36's probe replayed: one pupil sends ten 1 MB JSON bodies of 90,000 unknown keys to /api/rules/parse
at once. Does the teacher's GET /api/class still answer at once (target: <= 200 ms median, <= 1 s at most)?
The same in plain mode (no rate limit: only the body's shape check, off the event loop, protects the others):
GET /api/rulebases while one script sends the ten bodies. Then, in plain mode, POST /api/runs of a tiny run against
an opponent of 200,000 characters of rules, one at a time: its rules are parsed in the route's thread, not while
the body is validated on the event loop (which held every request for the whole parse, twice over).

A real `soccer-lab serve` (its own process, 127.0.0.1, an empty data folder) is started for each mode. The
teacher (or the plain mode's user) asks every 50 ms from before the flood until a second after its last
answer; the flood is ROUNDS rounds of ten bodies at once, each round as the last one's answers come. Printed:
the teacher's median and largest time, the flood's answers (413: refused by its shape, 429: by the pupil's
rate) and the largest error body.

    python benchmarks/hostile_pupil.py [--rounds 3] [--record]
"""

from __future__ import annotations

import argparse
import json
import re
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor

import httpx

from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py

CODE = "HOSTILE1"
BODIES = 10
KEYS = 90_000
POLL_SECONDS = 0.05
OPPONENT_RULE = "if Ball is not At and Goal is not Near and Ball is Left then GoToBall VeryHigh\n"


def opponent_body() -> bytes:
    """A tiny run (two games of ten ticks) against an opponent of about 200,000 characters of rules."""
    rules = OPPONENT_RULE * (199_000 // len(OPPONENT_RULE))
    return json.dumps({"opponent": rules, "ga": {"population_size": 2, "max_generations": 1, "workers": 1},
                       "game": {"max_ticks": 10, "games_per_evaluation": 1}}).encode()


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def flood_body() -> bytes:
    """About 1 MB of JSON: rule text and 90,000 unknown keys (the probe's body)."""
    return json.dumps({"text": "", **{f"k{i:x}": 0 for i in range(KEYS)}}, separators=(",", ":")).encode()


class Serve:
    """`soccer-lab serve` (with --class: classroom mode) in its own process, until stopped."""

    def __init__(self, folder: str, classroom: bool):
        self.port = free_port()
        arguments = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--host", "127.0.0.1",
                     "--data-dir", folder, "--port", str(self.port), "--ui-port", str(free_port())]
        if classroom:
            arguments += ["--class", "--join-code", CODE, "--address", "127.0.0.1"]
        self.process = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.printed = ""
        for line in self.process.stdout:
            self.printed += line
            if " data " in line:
                break
        else:
            raise SystemExit(f"serve did not start:\n{self.printed}")
        token = re.search(r"teacher token\s+(\S+)", self.printed)
        self.teacher_token = token.group(1) if token else None
        self.url = f"http://127.0.0.1:{self.port}"
        while True:  # serve prints its addresses just before uvicorn listens
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=1).close()
                break
            except OSError:
                time.sleep(0.1)

    def stop(self) -> None:
        self.process.send_signal(signal.SIGINT)
        self.process.wait(30)


def flood(url: str, cookies: httpx.Cookies | None, body: bytes, rounds: int, route: str = "/api/rules/parse",
          at_once: int = BODIES) -> tuple[Counter, int]:
    """ROUNDS rounds of `at_once` bodies at once: (answers by status, the largest answer's bytes)."""
    statuses, largest = Counter(), 0

    def send(_: int) -> httpx.Response:
        with httpx.Client(base_url=url, cookies=cookies, timeout=120) as client:
            return client.post(route, content=body, headers={"Content-Type": "application/json"})

    with ThreadPoolExecutor(at_once) as pool:
        for _ in range(rounds):
            for response in pool.map(send, range(at_once)):
                statuses[response.status_code] += 1
                largest = max(largest, len(response.content))
    return statuses, largest


def watched(url: str, path: str, cookies: httpx.Cookies | None, during) -> tuple[list[float], list[str], object]:
    """Times of GET `path` every POLL_SECONDS from before `during()` to a second after it, what failed, and
    `during()`'s result."""
    times: list[float] = []
    failed: list[str] = []
    done = threading.Event()

    def poll() -> None:
        with httpx.Client(base_url=url, cookies=cookies, timeout=120) as client:
            finished = None
            while finished is None or time.monotonic() - finished < 1.0:
                start = time.perf_counter()
                try:
                    response = client.get(path)
                    times.append(time.perf_counter() - start)
                    if response.status_code != 200:
                        failed.append(f"{response.status_code}: {response.text[:200]}")
                except httpx.HTTPError as exc:
                    failed.append(repr(exc))
                if done.is_set() and finished is None:
                    finished = time.monotonic()
                time.sleep(POLL_SECONDS)

    watcher = threading.Thread(target=poll)
    watcher.start()
    time.sleep(0.5)
    result = during()
    done.set()
    watcher.join()
    return times, failed, result


def scenario(classroom: bool, rounds: int, body: bytes, route: str = "/api/rules/parse", at_once: int = BODIES,
             what: str = "the flood", one: str = "a flood body") -> list[Figure]:
    mode = "classroom" if classroom else "plain"
    with tempfile.TemporaryDirectory() as folder:
        serve = Serve(folder, classroom)
        try:
            pupil = teacher = None
            if classroom:
                with httpx.Client(base_url=serve.url) as client:
                    assert client.post("/api/class/join", json={"code": CODE, "name": "Mallory"}).status_code == 200
                    pupil = client.cookies
                with httpx.Client(base_url=serve.url) as client:
                    assert client.post("/api/class/teacher", json={"token": serve.teacher_token}).status_code == 200
                    teacher = client.cookies
            path = "/api/class" if classroom else "/api/rulebases"
            times, failed, (statuses, largest) = watched(serve.url, path, teacher,
                                                 lambda: flood(serve.url, pupil, body, rounds, route, at_once))
        finally:
            serve.stop()
    median, most = statistics.median(times), max(times)
    answers = ", ".join(f"{count} x {status}" for status, count in sorted(statuses.items()))
    print(f"{mode}: GET {path} median {median * 1000:.0f} ms, max {most * 1000:.0f} ms over {len(times)} requests; "
          f"{what}'s answers: {answers}; largest {largest:,} bytes; failed: {failed or 'none'}")
    who = "the teacher's GET /api/class" if classroom else "GET /api/rulebases"
    return [Figure(f"{mode}: {who} during {what}, median", round(median * 1000), "ms",
                   target="<= 200 ms" if classroom else "",
                   note=f"{len(times)} requests, {len(failed)} failed; {what}: {answers}"),
            Figure(f"{mode}: {who} during {what}, max", round(most * 1000), "ms",
                   target="<= 1000 ms" if classroom else ""),
            Figure(f"{mode}: the largest answer to {one}", largest, "bytes", target="<= 16,000 bytes")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=3, help="rounds of ten bodies at once")
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    body = flood_body()
    print(f"{BODIES} bodies of {len(body):,} bytes ({KEYS:,} unknown keys) at once, {args.rounds} rounds; "
          f"load average {load_before}")
    figures = scenario(True, args.rounds, body) + scenario(False, args.rounds, body)
    figures += scenario(False, args.rounds, opponent_body(), "/api/runs", 1, "a run's 200 KB opponent, one at a time",
                        "a run's 200 KB opponent")[:2]  # its answer is the run, opponent included: no error's size
    print(f"load average after: {load_average()}")
    if args.record:
        record("hostile_pupil", figures, command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
