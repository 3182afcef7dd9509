"""How long a class knockout takes (app/web/classroom/knockout.py): ENTRIES entries (the four examples of
soccer/data/examples/ in turn, each under a name of its own), each tie the best of BEST_OF matches of at most
MAX_TICKS ticks a half (the class's default bound), played as `serve --class` plays it: in a process of its own,
tie by tie, each stored as it finishes. Measured: the seconds from Start to the final (the process's start
included) and the longest wait for one tie (what a class watches between two updates of the bracket). The
largest knockout the bounds allow (100 entries, best of 9, max_run_ticks) is estimated from the seconds a
match half-tick costs here.

    python benchmarks/knockout.py [--entries 30] [--best-of 3] [--max-ticks 1000] [--record]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

from results import Figure, add_record_option, load_average, record, this_command

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--entries", type=int, default=30)
    parser.add_argument("--best-of", type=int, default=3)
    parser.add_argument("--max-ticks", type=int, default=1000)
    add_record_option(parser)
    args = parser.parse_args()

    from soccer_lab.app.store import Store
    from soccer_lab.app.web.access import LOCAL
    from soccer_lab.app.web.classroom.knockout import MAX_BEST_OF
    from soccer_lab.app.web.classroom.settings import MAX_ENTRIES, ClassSettings
    from soccer_lab.app.web.classroom.tournament import Tournament
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.config import GameConfig
    from soccer_lab.soccer.examples import examples

    load_before = load_average()
    settings = ClassSettings()
    with tempfile.TemporaryDirectory() as folder:
        store = Store(Path(folder) / "db.sqlite3")
        tournament = Tournament(store, Vocabulary.default(), GameConfig(), lambda: settings)
        kinds = examples()
        for i in range(args.entries):
            store.submit_entry(None, f"pupil {i + 1}", kinds[i % len(kinds)].text, kinds[i % len(kinds)].name)
        updates: list[tuple[float, int]] = []  # (when, matches played so far) at each update of the bracket
        tournament.add_listener(lambda event: updates.append(
            (time.perf_counter(), sum(len(tie["matches"]) for tie in event.knockout.ties))))
        started = time.perf_counter()
        knockout = tournament.knockout.start(LOCAL, tournament.entries(), best_of=args.best_of, seed=1,
                                             max_ticks=args.max_ticks)
        tournament.knockout.wait()
        seconds = time.perf_counter() - started
        done = store.get_knockout(knockout.id)
        store.close()
    assert str(done.status) == "finished", done.error
    played = [tie for tie in done.ties if tie["matches"]]
    first = next(when for when, matches in updates if matches)  # the process's start and the first tie
    first_tie = first - started
    # after the first tie: the waits between the bracket's updates, and the seconds per half-tick played
    after = [when for when, _ in updates if when >= first]
    gaps = [b - a for a, b in zip(after, after[1:])] or [0.0]
    half_ticks = sum(half["ticks"] for tie in played[1:] for match in tie["matches"] for half in match["halves"])
    per_half_tick = (seconds - first_tie) / max(half_ticks, 1)
    largest = (MAX_ENTRIES - 1) * MAX_BEST_OF * 2 * settings.max_run_ticks * per_half_tick
    figures = [
        Figure(f"a knockout of {args.entries} entries, best of {args.best_of}, at most {args.max_ticks} ticks a "
               "half: Start to the final", round(seconds, 1), "s",
               note=f"{len(played)} ties played"),
        Figure("the first tie played, from Start (the knockout's process starts)", round(first_tie, 1), "s"),
        Figure("then the longest wait for the next tie (the bracket's updates)", round(max(gaps), 2), "s"),
        Figure(f"the largest knockout the bounds allow ({MAX_ENTRIES} entries, best of {MAX_BEST_OF}, "
               f"{settings.max_run_ticks} ticks a half, every half played to the end), estimated",
               round(largest / 60, 1), "min", note="from the seconds a half-tick cost above"),
    ]
    for figure in figures:
        print(f"{figure.name}: {figure.value} {figure.unit} {figure.note}")
    print(f"load average before {load_before}, after {load_average()}")
    if args.record:
        record("knockout", figures, command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
