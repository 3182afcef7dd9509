"""The class knockout (issue 39, "Match day"): the class's entries drawn into a bracket, each tie a best of N
matches of two players on one pitch (soccer/match.py), the winners meeting in the next round until one is left.

- The draw is seeded: the entries (in the order they were entered) shuffled by a numpy Generator from the
  knockout's seed; draw number 1 is the first drawn. The bracket has a power of two of places; when the entries
  are fewer, the missing places are byes, and the standard bracket order (1 meets the last, 2 the one before,
  ...) gives the byes to the top of the draw.
- A tie plays all N matches (N odd, the teacher's choice), each from a seed derived from the knockout's seed,
  its round and its tie, and each played twice with the sides swapped (play_matches' two halves). The winner:
  more matches won; level, the better goal difference over the N matches; still level, the higher place in
  the draw (the smaller draw number: the seeded draw decides, as a coin would).
- The matches are played in a process of its own, tie by tie (tournament.py says why), and each tie is stored
  as it finishes, so every screen's bracket fills in live and any played match can be watched. A knockout the
  app ended in the middle of is marked interrupted when the app starts again (store.mark_knockouts_interrupted);
  started again with the same seed, it plays the same matches.
"""

from __future__ import annotations

import csv
import io
import logging
import multiprocessing
import os
import secrets
import threading
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Callable

import numpy as np

from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.store import EntryRecord, KnockoutRecord, KnockoutStatus, NotFound, Store, StoreError
from soccer_lab.app.web.access import Visitor
from soccer_lab.app.web.classroom.settings import MAX_ENTRIES
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.evaluation import start_worker
from soccer_lab.soccer.config import GameConfig

log = logging.getLogger(__name__)
DEFAULT_BEST_OF = 3
MAX_BEST_OF = 9  # matches per tie: 99 ties (100 entries) x 9 matches x 2 halves of at most max_run_ticks
FRESH_SEED_BELOW = 1_000_000  # a drawn seed short enough to read off the projector and type again
CSV_COLUMNS = ("knockout", "round", "tie", "match", "player_a", "player_b", "goals_a", "goals_b", "winner", "seed",
               "tie_winner")
# A spreadsheet runs a cell that starts with one of these as a formula (tournament.py's round CSV does the same).
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")


class Knockout:
    """The class's knockouts: start one (the teacher's), one played at a time; `notify(record)` hears each
    change (started, a tie finished, ended) with the knockout as stored then."""

    def __init__(self, store: Store, vocabulary: Vocabulary, game: Callable[[], GameConfig],
                 max_ticks: Callable[[], int], notify: Callable[[KnockoutRecord], None]):
        self.store = store
        self.vocabulary = vocabulary
        self._game = game  # the class's game (its skill set), as a round plays it
        self._max_ticks = max_ticks  # the class's bound on a game's ticks
        self._notify = notify
        self._lock = threading.Lock()
        self._playing: threading.Thread | None = None
        self._closing = threading.Event()  # the app is ending: stop after the tie being played
        self.interrupted_at_start = store.mark_knockouts_interrupted()

    @property
    def playing(self) -> bool:
        return self._playing is not None and self._playing.is_alive()

    def start(self, visitor: Visitor, entries: list[EntryRecord], *, best_of: int = DEFAULT_BEST_OF,
              seed: int | None = None, max_ticks: int | None = None) -> KnockoutRecord:
        """Draw `entries` and play the knockout in the background; the record as started. StoreError for bad
        input, RunStateError while another knockout plays."""
        visitor.require_teacher("start a knockout")
        bound = self._max_ticks()
        game = self._game()
        max_ticks = min(game.max_ticks, bound) if max_ticks is None else max_ticks
        check_knockout(len(entries), best_of, max_ticks, bound)
        seed = secrets.randbelow(FRESH_SEED_BELOW) if seed is None else seed
        if not 0 <= seed < 2**63:
            raise StoreError("a knockout's seed is a non-negative integer below 2**63")
        game = game.model_copy(update={"max_ticks": max_ticks})
        with self._lock:
            if self.playing:
                raise RunStateError("a knockout is being played: wait for its final")
            record = self.store.create_knockout(seed, best_of, game.model_dump(), draw_entries(entries, seed))
            self._playing = threading.Thread(target=self._play, args=(record, game), name="class-knockout",
                                             daemon=True)
            self._playing.start()
        self._notify(record)
        return record

    def wait(self, timeout: float | None = None) -> None:
        playing = self._playing
        if playing is not None:
            playing.join(timeout)

    def close(self, timeout: float) -> None:
        """The app is ending: a knockout being played stops after its current tie, marked interrupted, so
        nothing writes to the store once it closes; waits at most `timeout` s."""
        self._closing.set()
        self.wait(timeout)

    def knockouts(self) -> list[KnockoutRecord]:
        return self.store.list_knockouts()

    def get(self, knockout_id: int) -> KnockoutRecord:
        return self.store.get_knockout(knockout_id)

    def latest(self) -> KnockoutRecord | None:
        return self.store.latest_knockout()

    def _play(self, record: KnockoutRecord, game: GameConfig) -> None:
        try:
            context = multiprocessing.get_context("spawn")
            with ProcessPoolExecutor(1, mp_context=context, initializer=start_worker,
                                     initargs=(os.getpid(),)) as worker:
                pairing = next_pairing(record)
                while pairing is not None and not self._closing.is_set():
                    arguments = (record.draw, record.seed, record.best_of, game, self.vocabulary, *pairing)
                    bye = pairing[3] is None  # nothing to play: decided here
                    tie = play_tie(*arguments) if bye else worker.submit(play_tie, *arguments).result()
                    self.store.record_tie(record.id, tie)
                    record = self.store.get_knockout(record.id)
                    self._notify(record)
                    pairing = next_pairing(record)
            ended = KnockoutStatus.FINISHED if pairing is None else KnockoutStatus.INTERRUPTED
            record = self.store.end_knockout(record.id, ended)
        except Exception as exc:  # the app goes on; the teacher hears why
            log.exception("class knockout failed")
            record = self.store.end_knockout(record.id, KnockoutStatus.FAILED, f"the knockout failed: {exc}")
        self._notify(record)


def check_knockout(entries: int, best_of: int, max_ticks: int, max_ticks_bound: int) -> None:
    """Every bound a knockout's cost depends on, checked before it is paid (StoreError naming the bound)."""
    if entries < 2:
        raise StoreError(f"a knockout needs at least 2 entries; the class has {entries}: students enter their "
                         "rules from the Class tab first")
    if entries > MAX_ENTRIES:
        raise StoreError(f"a knockout has at most {MAX_ENTRIES} entries, not {entries}")
    if isinstance(best_of, bool) or not isinstance(best_of, int) or not 1 <= best_of <= MAX_BEST_OF \
            or best_of % 2 == 0:
        raise StoreError(f"a tie is the best of an odd number of matches from 1 to {MAX_BEST_OF}, not {best_of}")
    if isinstance(max_ticks, bool) or not isinstance(max_ticks, int) or not 1 <= max_ticks <= max_ticks_bound:
        raise StoreError(f"a knockout's matches last 1 to {max_ticks_bound} ticks a half (the class's "
                         f"max_run_ticks), not {max_ticks}")


# ---- the draw and the bracket --------------------------------------------------------------------


def draw_entries(entries: list[EntryRecord], seed: int) -> list[dict[str, Any]]:
    """The entries in the order the seeded draw put them: draw number 1 first."""
    order = np.random.default_rng(seed).permutation(len(entries))
    return [{"draw": place, "entry_id": entries[i].id, "name": entries[i].name, "source": entries[i].source,
             "text": entries[i].text} for place, i in enumerate(order.tolist(), 1)]


def bracket_size(entries: int) -> int:
    return 1 << max(entries - 1, 0).bit_length()


def bracket_order(size: int) -> list[int]:
    """The draw numbers of a bracket's places, top to bottom (size a power of two): 1 meets `size`, and the
    top two can meet only in the final (for 8: 1 8 4 5 2 7 3 6)."""
    order = [1]
    while len(order) < size:
        order = [place for top in order for place in (top, 2 * len(order) + 1 - top)]
    return order


def rounds_of(entries: int) -> int:
    return max(bracket_size(entries).bit_length() - 1, 1)


def round_name(round_number: int, rounds: int) -> str:
    return {0: "Final", 1: "Semi-finals", 2: "Quarter-finals"}.get(rounds - round_number,
                                                                    f"Round {round_number}")


def next_pairing(record: KnockoutRecord) -> tuple[int, int, int, int | None] | None:
    """The next tie to play after `record.ties`, as (round, tie, draw number of A, of B or None: a bye): the
    first round's in bracket order, then each round's (the winners of the two ties before it meet); None when
    the final is played."""
    for ties in bracket(record):
        for tie in ties:
            if tie["played"] is None:
                return tie["round"], tie["tie"], tie["a"], tie["b"]
    return None


def bracket(record: KnockoutRecord) -> list[list[dict[str, Any]]]:
    """Every round's ties, played or not: {round, tie, a, b (draw numbers; None: not known yet, or b a bye in
    round 1), played (the stored tie, or None)}: what a bracket drawing shows."""
    size = bracket_size(len(record.draw))
    places = [place if place <= len(record.draw) else None for place in bracket_order(size)]
    played = {(t["round"], t["tie"]): t for t in record.ties}
    rounds: list[list[dict[str, Any]]] = []
    for round_number in range(1, rounds_of(len(record.draw)) + 1):
        ties = []
        for tie in range(1, (size >> round_number) + 1):
            if round_number == 1:
                a, b = places[2 * tie - 2], places[2 * tie - 1]
            else:
                feeding = (played.get((round_number - 1, 2 * tie - k)) for k in (1, 0))
                a, b = (None if before is None else before["winner"] for before in feeding)
            ties.append({"round": round_number, "tie": tie, "a": a, "b": b, "played": played.get((round_number, tie))})
        rounds.append(ties)
    return rounds


def match_seeds(seed: int, round_number: int, tie: int, best_of: int) -> list[int]:
    """A tie's matches' seeds: derived from the knockout's seed, its round and tie (the same whatever else
    is played)."""
    state = np.random.SeedSequence([seed, round_number, tie]).generate_state(best_of, np.uint64)
    return [int(s) >> 1 for s in state]  # below 2**63: SQLite's and the API's integers


# ---- a tie ---------------------------------------------------------------------------------------


def play_tie(draw: list[dict[str, Any]], seed: int, best_of: int, game: GameConfig, vocabulary: Vocabulary,
             round_number: int, tie: int, a: int, b: int | None) -> dict[str, Any]:
    """Tie `tie` of round `round_number` between draw numbers `a` and `b` (None: a bye, `a` goes through)."""
    result: dict[str, Any] = {"round": round_number, "tie": tie, "a": a, "b": b, "matches": []}
    if b is None:
        return {**result, "wins": [0, 0], "goals": [0, 0], "winner": a, "decided_by": "bye"}
    from soccer_lab.soccer.match import play_matches  # numba: in the knockout's process only

    players = [parse_rulebase(draw[place - 1]["text"], vocabulary) for place in (a, b)]
    seeds = match_seeds(seed, round_number, tie, best_of)
    matches = play_matches(*players, seeds, game, vocabulary)
    result["matches"] = [
        {"match": k, "seed": m.seed, "goals": list(m.goals), "winner": m.winner,
         "halves": [{"goals": list(h.goals), "ticks": h.ticks, "end_reason": h.end_reason} for h in m.halves]}
        for k, m in enumerate(matches, 1)]
    wins = [sum(m.winner == side for m in matches) for side in "AB"]
    goals = [sum(m.goals[side] for m in matches) for side in (0, 1)]
    winner, decided_by = tie_winner(a, b, wins, goals)
    return {**result, "wins": wins, "goals": goals, "winner": winner, "decided_by": decided_by}


def tie_winner(a: int, b: int, wins: list[int], goals: list[int]) -> tuple[int, str]:
    """(the winner's draw number, what decided it): more matches won, then goal difference, then the higher
    place in the draw."""
    if wins[0] != wins[1]:
        return (a if wins[0] > wins[1] else b), "matches won"
    if goals[0] != goals[1]:
        return (a if goals[0] > goals[1] else b), "goal difference"
    return min(a, b), "higher in the draw"


def champion(record: KnockoutRecord) -> dict[str, Any] | None:
    """The winner of the final (its draw entry), or None before it is played."""
    rounds = rounds_of(len(record.draw))
    final = [t for t in record.ties if t["round"] == rounds]
    return record.draw[final[0]["winner"] - 1] if final and len(record.draw) > 1 else None


# ---- CSV and watching ----------------------------------------------------------------------------


def knockout_csv(record: KnockoutRecord) -> str:
    """One row per match played (a bye: one row with no match); names as text a spreadsheet will not run."""
    out = io.StringIO()
    writer = csv.writer(out)
    writer.writerow(CSV_COLUMNS)
    name = {entry["draw"]: _cell(entry["name"]) for entry in record.draw}
    for tie in record.ties:
        a, b, through = name[tie["a"]], name.get(tie["b"]), name[tie["winner"]]
        if not tie["matches"]:
            writer.writerow([record.id, tie["round"], tie["tie"], "bye", a, "(bye)", "", "", a, "", through])
        for match in tie["matches"]:
            winner = {"A": a, "B": b}.get(match["winner"], "draw")
            writer.writerow([record.id, tie["round"], tie["tie"], match["match"], a, b, *match["goals"], winner,
                             match["seed"], through])
    return out.getvalue()


def _cell(text: str) -> str:
    return "'" + text if text.startswith(FORMULA_STARTS) else text


def knockout_match(record: KnockoutRecord, round_number: int, tie: int, match: int
                   ) -> tuple[str, str, str, str, int, GameConfig]:
    """(A's name, A's rules, B's name, B's rules, seed, game) of a played match, to watch it on a pitch."""
    for played in record.ties:
        if (played["round"], played["tie"]) == (round_number, tie):
            if not 1 <= match <= len(played["matches"]):
                raise StoreError(f"round {round_number}'s tie {tie} has no match {match}")
            a, b = (record.draw[played[side] - 1] for side in "ab")
            return (a["name"], a["text"], b["name"], b["text"], played["matches"][match - 1]["seed"],
                    GameConfig(**record.game))
    raise NotFound(f"tie of knockout {record.id}", f"{round_number}.{tie}",
                   f"knockout {record.id} has no played tie {tie} in round {round_number}")
