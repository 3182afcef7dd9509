"""The class tournament: each student enters a rulebase under their name (a new one replaces the old), the
teacher may enter the GA's best or a library rulebase, and a round plays every entry on the same starts.

A round is one GameBatch: entries x starts games, the k-th start of every entry from the same seed (derived
from the round's seed as an evaluation's games are, soccer/evaluate.py), so every entry meets the same
positions and a game is the same whatever else is in the batch (docs/design.md, "A game does not depend on
its batch"). The batch plays in a process of its own: the server's threads (every pupil's tab, the API) share
one interpreter lock, and a round played among 30 tabs' threads took a minute instead of seconds
(benchmarks/classroom.py). The table ranks entries by goals, then the chapter's fitness (the mean over the starts; lower
is better), then kicks. A round is stored when its table is complete (the store's `class_rounds`), so it
survives restarts; each game can be played again on a pitch from its entry's rules and its seed.
"""

from __future__ import annotations

import csv
import io
import logging
import multiprocessing
import os
import threading
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from statistics import fmean
from typing import Any, Callable

from soccer_lab.app.web.access import Forbidden, Visitor
from soccer_lab.app.web.classroom.knockout import Knockout
from soccer_lab.app.web.classroom.settings import (ENTRY_MAX_CHARACTERS, ENTRY_MAX_RULES, MAX_ENTRIES, MAX_STARTS,
                                                   ClassSettings)
from soccer_lab.app.words import plural
from soccer_lab.app.runs.listeners import Listeners
from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.store import EntryRecord, KnockoutRecord, NotFound, RoundRecord, Store, StoreError, name_key
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.evaluation import start_worker
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_games
from soccer_lab.soccer.evaluate import game_seeds

log = logging.getLogger(__name__)
CSV_COLUMNS = ("rank", "name", "source", "goals", "fitness", "kicks", "starts", "round", "seed")
# A spreadsheet runs a cell that starts with one of these as a formula: a name like "=HYPERLINK(...)" is
# written with a leading apostrophe, so it is shown as the text it is.
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")


@dataclass(frozen=True)
class TournamentEvent:
    """What sessions hear: the entries changed, a round started, a round's table is ready (`round`), or the
    knockout changed (`knockout`, as stored then: started, a tie played, ended)."""

    kind: str  # "entries", "started", "finished", "failed", "knockout"
    round: RoundRecord | None = None
    message: str = ""
    knockout: KnockoutRecord | None = None


class Tournament:
    def __init__(self, store: Store, vocabulary: Vocabulary, game: GameConfig,
                 settings: Callable[[], ClassSettings]):
        self.store = store
        self.vocabulary = vocabulary
        self.game = game  # the app's game; a round plays it with the class's skill set
        self._settings = settings
        self._listeners: Listeners[TournamentEvent] = Listeners("tournament")
        self._lock = threading.Lock()
        self._playing: threading.Thread | None = None
        self.knockout = Knockout(store, vocabulary, self.round_game, lambda: self.settings.max_run_ticks,
                                 lambda record: self._notify(TournamentEvent("knockout", knockout=record)))

    # ---- listeners ----
    def add_listener(self, listener: Callable[[TournamentEvent], None]) -> Callable[[], None]:
        return self._listeners.add(listener)

    def _notify(self, event: TournamentEvent) -> None:
        self._listeners.notify(event)

    # ---- entries ----
    def submit(self, visitor: Visitor, text: str, *, name: str | None = None, source: str = "rules") -> EntryRecord:
        """A student's entry under their name (replacing their earlier one); the teacher's under `name`."""
        rulebase_of_entry(text, self.vocabulary)
        if visitor.is_student:
            if name is not None and name_key(name) != name_key(visitor.name):
                raise Forbidden("only the teacher can enter a rulebase under another name than their own")
            entry_name = visitor.name
        else:
            visitor.require_teacher("enter a rulebase under another name")
            if not name:
                raise StoreError("the teacher's entry needs a name (e.g. 'GA best')")
            entry_name = name
        if len(self.store.list_entries()) >= MAX_ENTRIES and not any(
                e.student_id == visitor.student_id and visitor.is_student for e in self.store.list_entries()):
            raise StoreError(f"the tournament has {MAX_ENTRIES} entries, its limit: the teacher may remove some")
        entry = self.store.submit_entry(visitor.student_id, entry_name, text, source)
        self._notify(TournamentEvent("entries"))
        return entry

    def entries(self) -> list[EntryRecord]:
        return self.store.list_entries()

    def remove(self, visitor: Visitor, entry_id: int) -> None:
        visitor.require_teacher("remove an entry")
        self.store.delete_entry(entry_id)
        self._notify(TournamentEvent("entries"))

    def remove_student(self, visitor: Visitor, student_id: int) -> None:
        """The student leaves the class (their entry with them)."""
        visitor.require_teacher("remove a student")
        self.store.remove_student(student_id)
        self._notify(TournamentEvent("entries"))

    # ---- rounds ----
    @property
    def playing(self) -> bool:
        return self._playing is not None and self._playing.is_alive()

    def start_round(self, visitor: Visitor, *, starts: int | None = None, seed: int | None = None) -> dict[str, Any]:
        """Play a round in the background (the teacher's); what was started. RunStateError while one plays."""
        visitor.require_teacher("start a round")
        starts = self.settings.starts if starts is None else starts
        if not 1 <= starts <= MAX_STARTS:
            raise StoreError(f"a round plays 1 to {MAX_STARTS} starts, not {starts}")
        entries = self.entries()
        if not entries:
            raise StoreError("no entries yet: students submit their rules from the Class tab first")
        seed = len(self.store.list_rounds()) + 1 if seed is None else seed
        if not 0 <= seed < 2**63:
            raise StoreError("a round's seed is a non-negative integer below 2**63")
        game = self.round_game()
        with self._lock:
            if self.playing:
                raise RunStateError("a round is being played: wait for its table")
            self._playing = threading.Thread(target=self._play_round, args=(entries, starts, seed, game),
                                             name="class-round", daemon=True)
            self._playing.start()
        message = f"{plural(len(entries), 'entry', 'entries')} x {plural(starts, 'start')}"
        self._notify(TournamentEvent("started", message=message))
        return {"entries": len(entries), "starts": starts, "seed": seed, "game": game.model_dump()}

    @property
    def settings(self) -> ClassSettings:
        return self._settings()

    def round_game(self) -> GameConfig:
        return self.game.model_copy(update={"skills": self.settings.skills})

    def wait(self, timeout: float | None = None) -> None:
        playing = self._playing
        if playing is not None:
            playing.join(timeout)

    def close(self, timeout: float) -> None:
        """The app is ending: the round being played and the knockout end before the store closes (at most
        `timeout` s each)."""
        self.knockout.close(timeout)
        self.wait(timeout)

    def _play_round(self, entries: list[EntryRecord], starts: int, seed: int, game: GameConfig) -> None:
        try:
            results = play_round_apart(entries, starts, seed, game, self.vocabulary)
            record = self.store.record_round(seed, starts, game.model_dump(), results)
        except Exception as exc:  # the app goes on; the teacher hears why
            log.exception("class round failed")
            self._notify(TournamentEvent("failed", message=f"the round failed: {exc}"))
            return
        self._notify(TournamentEvent("finished", record))

    def rounds(self) -> list[RoundRecord]:
        return self.store.list_rounds()

    def get_round(self, round_id: int) -> RoundRecord:
        return self.store.get_round(round_id)

    def latest_round(self) -> RoundRecord | None:
        rounds = self.store.list_rounds()
        return rounds[0] if rounds else None


def rulebase_of_entry(text: object, vocabulary: Vocabulary) -> Rulebase:
    """An entry's rules, parsed and bounded (StoreError or RuleSyntaxError saying what is wrong)."""
    if not isinstance(text, str):
        raise StoreError("an entry's rules are text")
    if len(text) > ENTRY_MAX_CHARACTERS:
        raise StoreError(f"an entry is at most {ENTRY_MAX_CHARACTERS:,} characters; this one has {len(text):,}")
    rulebase = parse_rulebase(text, vocabulary)
    if not len(rulebase):
        raise StoreError("an entry needs at least one rule")
    if len(rulebase) > ENTRY_MAX_RULES:
        raise StoreError(f"an entry has at most {ENTRY_MAX_RULES} rules; this one has {len(rulebase)}")
    return rulebase


def start_seeds(seed: int, starts: int) -> list[int]:
    """The round's starts: the same for every entry."""
    return game_seeds(seed, starts)


def play_round_apart(entries: list[EntryRecord], starts: int, seed: int, game: GameConfig,
                     vocabulary: Vocabulary) -> list[dict[str, Any]]:
    """play_round in a process of its own (it dies with the server, ga/evaluation.start_worker)."""
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(1, mp_context=context, initializer=start_worker, initargs=(os.getpid(),)) as worker:
        return worker.submit(play_round, entries, starts, seed, game, vocabulary).result()


def play_round(entries: list[EntryRecord], starts: int, seed: int, game: GameConfig,
               vocabulary: Vocabulary) -> list[dict[str, Any]]:
    """Every entry on every start, in one batch; one ranked row per entry."""
    seeds = start_seeds(seed, starts)
    rulebases = [parse_rulebase(entry.text, vocabulary) for entry in entries]
    results = play_games([r for r in rulebases for _ in seeds], seeds * len(entries), game, vocabulary)
    rows = []
    for index, entry in enumerate(entries):
        games = results[index * starts:(index + 1) * starts]
        rows.append({
            "entry_id": entry.id, "student_id": entry.student_id, "name": entry.name, "source": entry.source,
            "text": entry.text,
            "goals": sum(g.goals for g in games), "fitness": fmean(g.fitness for g in games),
            "kicks": sum(g.kicks for g in games),
            "games": [{"seed": s, "goals": g.goals, "kicks": g.kicks, "fitness": g.fitness, "ticks": g.ticks,
                       "end_reason": g.end_reason} for s, g in zip(seeds, games)],
        })
    rows.sort(key=lambda row: (-row["goals"], row["fitness"], -row["kicks"], row["name"].casefold()))
    for position, row in enumerate(rows):
        before = rows[position - 1] if position else None
        tied = before is not None and all(before[k] == row[k] for k in ("goals", "fitness", "kicks"))
        row["rank"] = before["rank"] if tied else position + 1
    return rows


def round_csv(record: RoundRecord) -> str:
    out = io.StringIO()
    writer = csv.writer(out)
    writer.writerow(CSV_COLUMNS)
    for row in record.results:
        writer.writerow([row["rank"], _cell(row["name"]), _cell(row["source"]), row["goals"], f"{row['fitness']:.6f}",
                         row["kicks"], record.starts, record.id, record.seed])
    return out.getvalue()


def _cell(text: str) -> str:
    return "'" + text if text.startswith(FORMULA_STARTS) else text


def entry_game(record: RoundRecord, entry_id: int, start: int) -> tuple[str, str, int, GameConfig]:
    """(name, rule text, seed, game) of entry `entry_id`'s game on start `start` (1-based) of a round."""
    for row in record.results:
        if row["entry_id"] == entry_id:
            if not 1 <= start <= len(row["games"]):
                raise StoreError(f"round {record.id} has starts 1 to {len(row['games'])}, not {start}")
            return row["name"], row["text"], row["games"][start - 1]["seed"], GameConfig(**record.game)
    raise NotFound(f"entry of round {record.id}", entry_id)
