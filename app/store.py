"""The SQLite store: saved rulebases, evolution runs with their per-generation statistics and best
individuals, and experiments.

One connection shared by every thread (the UI, the API and background runs) behind a lock; every
write is one transaction, so a crash or a bad value leaves what was saved before intact. The schema
carries its version in `PRAGMA user_version` and is brought up to date by `MIGRATIONS` on open.
"""

from __future__ import annotations

import json
import math
import sqlite3
import unicodedata
import threading
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from datetime import datetime, timezone
from enum import StrEnum
from pathlib import Path
from typing import Any, Iterator

NAME_MAX_LENGTH = 200

# MIGRATIONS[v] brings a database at schema version v to version v + 1.
MIGRATIONS: tuple[tuple[str, ...], ...] = (
    (
        """CREATE TABLE rulebases (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            name TEXT NOT NULL,
            text TEXT NOT NULL,
            created TEXT NOT NULL,
            updated TEXT NOT NULL)""",
        """CREATE TABLE runs (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            name TEXT NOT NULL,
            config TEXT NOT NULL,
            status TEXT NOT NULL,
            created TEXT NOT NULL,
            finished TEXT,
            folder TEXT NOT NULL,
            error TEXT)""",
        """CREATE TABLE generation_statistics (
            run_id INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
            generation INTEGER NOT NULL,
            stats TEXT NOT NULL,
            PRIMARY KEY (run_id, generation))""",
        """CREATE TABLE best_individuals (
            run_id INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
            generation INTEGER NOT NULL,
            rules TEXT NOT NULL,
            chromosome TEXT NOT NULL,
            fitness REAL NOT NULL,
            PRIMARY KEY (run_id, generation))""",
        """CREATE TABLE experiments (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            preset TEXT NOT NULL,
            folder TEXT NOT NULL,
            created TEXT NOT NULL,
            summary TEXT NOT NULL)""",
    ),
    (
        # Every individual of each generation with its birth (ga/lineage.py's generation_record, as JSON).
        """CREATE TABLE lineage (
            run_id INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
            generation INTEGER NOT NULL,
            record TEXT NOT NULL,
            PRIMARY KEY (run_id, generation))""",
    ),
    (  # classroom mode (docs/teaching/classroom.md): who owns a rulebase or run, the class's students,
        # its tournament's entries and rounds
        "ALTER TABLE rulebases ADD COLUMN owner INTEGER",  # a student's id; NULL: the teacher's, shared
        "ALTER TABLE runs ADD COLUMN owner INTEGER",
        """CREATE TABLE students (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            name TEXT NOT NULL,
            name_key TEXT NOT NULL UNIQUE,
            token_hash TEXT NOT NULL UNIQUE,
            created TEXT NOT NULL)""",
        """CREATE TABLE class_entries (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            student_id INTEGER UNIQUE REFERENCES students(id) ON DELETE CASCADE,
            name TEXT NOT NULL,
            name_key TEXT NOT NULL UNIQUE,
            text TEXT NOT NULL,
            source TEXT NOT NULL,
            submitted TEXT NOT NULL)""",
        """CREATE TABLE class_rounds (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            created TEXT NOT NULL,
            seed INTEGER NOT NULL,
            starts INTEGER NOT NULL,
            game TEXT NOT NULL,
            results TEXT NOT NULL)""",
    ),
    (  # a rulebase saved from a run's best keeps what it was measured at (app/runs/outputs.py's best_of_run)
        "ALTER TABLE rulebases ADD COLUMN best_of TEXT",
    ),
    (  # the class knockout (app/web/classroom/knockout.py): its draw, and each tie as it finishes
        """CREATE TABLE class_knockouts (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            created TEXT NOT NULL,
            seed INTEGER NOT NULL,
            best_of INTEGER NOT NULL,
            game TEXT NOT NULL,
            draw TEXT NOT NULL,
            status TEXT NOT NULL,
            finished TEXT,
            error TEXT)""",
        """CREATE TABLE class_knockout_ties (
            knockout_id INTEGER NOT NULL REFERENCES class_knockouts(id) ON DELETE CASCADE,
            round INTEGER NOT NULL,
            tie INTEGER NOT NULL,
            result TEXT NOT NULL,
            PRIMARY KEY (knockout_id, round, tie))""",
    ),
)
SCHEMA_VERSION = len(MIGRATIONS)


class StoreError(ValueError):
    """A value the store refuses (nothing is written) or a database it cannot use."""


class NotFound(KeyError):
    """No record with that id."""

    def __init__(self, kind: str, record_id: object, message: str | None = None):
        super().__init__(message or f"no {kind} with id {record_id}")
        self.kind = kind
        self.record_id = record_id

    def __str__(self) -> str:
        return str(self.args[0])


class RunStatus(StrEnum):
    RUNNING = "running"
    STOPPED = "stopped"
    FINISHED = "finished"
    FAILED = "failed"
    INTERRUPTED = "interrupted"  # the app ended while the run was going (or waiting in the queue); resumable
    QUEUED = "queued"  # classroom mode: waiting for a free core (app/runs/manager.py's RunQueue)

    @property
    def pending(self) -> bool:
        """Going or about to: a run that is neither finished nor resumable."""
        return self in (RunStatus.RUNNING, RunStatus.QUEUED)

    @property
    def resumable(self) -> bool:
        return self in (RunStatus.STOPPED, RunStatus.FAILED, RunStatus.INTERRUPTED)


@dataclass(frozen=True)
class RulebaseRecord:
    id: int
    name: str
    text: str
    created: str
    updated: str
    owner: int | None = None  # the student who saved it (classroom mode); None: shared
    # Saved from a run's best: its run, generation, the fitness the GA saw and its true quality (None: not)
    best_of: dict[str, Any] | None = None

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def of_row(cls, row: sqlite3.Row) -> "RulebaseRecord":
        """The record of a row; a damaged best_of reads as unknown (the rules are kept)."""
        data = dict(row)
        try:
            best_of = json.loads(data.pop("best_of") or "null")
        except ValueError:
            best_of = None
        return cls(**data, best_of=best_of if isinstance(best_of, dict) else None)


@dataclass(frozen=True)
class RunRecord:
    id: int
    name: str
    config: dict[str, Any]
    status: RunStatus
    created: str
    finished: str | None
    folder: str
    error: str | None
    owner: int | None = None  # the student who started it (classroom mode); None: shared

    def to_dict(self) -> dict[str, Any]:
        return {**asdict(self), "status": str(self.status)}


@dataclass(frozen=True)
class BestIndividual:
    run_id: int
    generation: int
    rules: str  # rule text
    chromosome: str  # compact notation
    fitness: float

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class ExperimentRecord:
    id: int
    preset: str
    folder: str
    created: str
    summary: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class StudentRecord:
    id: int
    name: str
    created: str


@dataclass(frozen=True)
class EntryRecord:
    """A rulebase entered in the class tournament: a student's (under their name, one each) or the teacher's
    (`student_id` None: the GA's best or a library rulebase, under the name the teacher gave)."""

    id: int
    student_id: int | None
    name: str
    text: str
    source: str  # where the rules came from, in words ("editor", "run 3's best", "library: striker")
    submitted: str


@dataclass(frozen=True)
class RoundRecord:
    """A played round: every entry on the same `starts` seeds (`results`: one row per entry, ranked)."""

    id: int
    created: str
    seed: int
    starts: int
    game: dict[str, Any]  # the GameConfig every game was played with
    results: list[dict[str, Any]]

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


class KnockoutStatus(StrEnum):
    PLAYING = "playing"
    FINISHED = "finished"
    FAILED = "failed"
    INTERRUPTED = "interrupted"  # the app ended while it was played: started again, the same seed plays it again


@dataclass(frozen=True)
class KnockoutRecord:
    """A class knockout: its seeded `draw` (one dict per entry, draw number 1 first), the ties played so far in
    round and tie order (`ties`: one dict each, app/web/classroom/knockout.py's play_tie), and where it is."""

    id: int
    created: str
    seed: int
    best_of: int  # matches per tie
    game: dict[str, Any]  # the GameConfig every match was played with
    draw: list[dict[str, Any]]
    status: KnockoutStatus
    finished: str | None
    error: str | None
    ties: list[dict[str, Any]]

    def to_dict(self) -> dict[str, Any]:
        return {**asdict(self), "status": str(self.status)}


def name_key(name: str) -> str:
    """What two names must differ in to be two names: case, width and runs of spaces do not count."""
    return " ".join(unicodedata.normalize("NFKC", name).casefold().split())


def now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds")


class Store:
    """The database at `path` (created with its folder when missing)."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            # Autocommit mode: transactions are explicit (BEGIN IMMEDIATE ... COMMIT) in _transaction.
            self._connection = sqlite3.connect(self.path, check_same_thread=False, isolation_level=None)
            self._connection.row_factory = sqlite3.Row
            self._connection.execute("PRAGMA journal_mode=WAL")
            self._connection.execute("PRAGMA foreign_keys=ON")
            self._connection.execute("PRAGMA busy_timeout=5000")
        except (OSError, sqlite3.Error) as exc:
            raise StoreError(f"cannot open database {self.path}: {exc}") from exc
        self._lock = threading.RLock()
        self._migrate()

    # ---- schema -------------------------------------------------------------------------
    @property
    def schema_version(self) -> int:
        with self._lock:
            return self._connection.execute("PRAGMA user_version").fetchone()[0]

    def _migrate(self) -> None:
        version = self.schema_version
        if version > SCHEMA_VERSION:
            raise StoreError(
                f"database {self.path} has schema version {version}, newer than this soccer-lab's {SCHEMA_VERSION}"
            )
        for target, statements in enumerate(MIGRATIONS[version:], start=version + 1):
            with self._transaction() as cursor:
                for statement in statements:
                    cursor.execute(statement)
                cursor.execute(f"PRAGMA user_version = {target}")

    @contextmanager
    def _transaction(self) -> Iterator[sqlite3.Cursor]:
        """One atomic write: everything inside commits together or not at all."""
        with self._lock:
            cursor = self._connection.cursor()
            cursor.execute("BEGIN IMMEDIATE")
            try:
                yield cursor
            except BaseException:
                cursor.execute("ROLLBACK")
                raise
            cursor.execute("COMMIT")

    def _query(self, sql: str, parameters: tuple = ()) -> list[sqlite3.Row]:
        with self._lock:
            return self._connection.execute(sql, parameters).fetchall()

    def close(self) -> None:
        with self._lock:
            self._connection.close()

    # ---- rulebases ----------------------------------------------------------------------
    def create_rulebase(self, name: str, text: str, owner: int | None = None,
                        best_of: dict[str, Any] | None = None) -> RulebaseRecord:
        """`best_of`: the run's best these rules are, with its figures (app/runs/outputs.py's best_of_run)."""
        name, text = valid_name(name), _valid_text(text)
        stamp = now()
        with self._transaction() as cursor:
            cursor.execute(
                "INSERT INTO rulebases (name, text, created, updated, owner, best_of) VALUES (?, ?, ?, ?, ?, ?)",
                (name, text, stamp, stamp, owner, None if best_of is None else json.dumps(best_of)),
            )
            record_id = cursor.lastrowid
        return RulebaseRecord(record_id, name, text, stamp, stamp, owner, best_of)

    def get_rulebase(self, rulebase_id: int) -> RulebaseRecord:
        rows = self._query("SELECT * FROM rulebases WHERE id = ?", (_valid_id(rulebase_id),))
        if not rows:
            raise NotFound("rulebase", rulebase_id)
        return RulebaseRecord.of_row(rows[0])

    def list_rulebases(self) -> list[RulebaseRecord]:
        """Newest first, as every list of the store."""
        return [RulebaseRecord.of_row(row) for row in self._query("SELECT * FROM rulebases ORDER BY id DESC")]

    def update_rulebase(self, rulebase_id: int, *, name: str | None = None, text: str | None = None) -> RulebaseRecord:
        current = self.get_rulebase(rulebase_id)
        name = current.name if name is None else valid_name(name)
        text = current.text if text is None else _valid_text(text)
        stamp = now()
        best_of = current.best_of if text == current.text else None  # other rules: no longer that best's figures
        with self._transaction() as cursor:
            cursor.execute(
                "UPDATE rulebases SET name = ?, text = ?, updated = ?, best_of = ? WHERE id = ?",
                (name, text, stamp, None if best_of is None else json.dumps(best_of), current.id)
            )
            if cursor.rowcount == 0:  # deleted by another thread meanwhile
                raise NotFound("rulebase", rulebase_id)
        return RulebaseRecord(current.id, name, text, current.created, stamp, current.owner, best_of)

    def delete_rulebase(self, rulebase_id: int) -> None:
        with self._transaction() as cursor:
            cursor.execute("DELETE FROM rulebases WHERE id = ?", (_valid_id(rulebase_id),))
            if cursor.rowcount == 0:
                raise NotFound("rulebase", rulebase_id)

    # ---- runs ---------------------------------------------------------------------------
    def create_run(self, name: str, config: dict[str, Any], folder: str | Path, owner: int | None = None,
                   status: RunStatus = RunStatus.RUNNING) -> RunRecord:
        """A new run, status running (or queued). `folder` may contain `{id}`, filled with the new run's id."""
        name = valid_name(name)
        config_json = _json(config, "run config")
        stamp = now()
        with self._transaction() as cursor:
            cursor.execute(
                "INSERT INTO runs (name, config, status, created, folder, owner) VALUES (?, ?, ?, ?, ?, ?)",
                (name, config_json, RunStatus(status).value, stamp, str(folder), owner),
            )
            run_id = cursor.lastrowid
            folder = str(folder).format(id=run_id)
            cursor.execute("UPDATE runs SET folder = ? WHERE id = ?", (folder, run_id))
        return self.get_run(run_id)

    def get_run(self, run_id: int) -> RunRecord:
        rows = self._query("SELECT * FROM runs WHERE id = ?", (_valid_id(run_id),))
        if not rows:
            raise NotFound("run", run_id)
        return _run_record(rows[0])

    def list_runs(self) -> list[RunRecord]:
        """Newest first."""
        return [_run_record(row) for row in self._query("SELECT * FROM runs ORDER BY id DESC")]

    def set_run_status(self, run_id: int, status: RunStatus, error: str | None = None) -> RunRecord:
        status = RunStatus(status)
        finished = None if status.pending else now()
        with self._transaction() as cursor:
            cursor.execute(
                "UPDATE runs SET status = ?, finished = ?, error = ? WHERE id = ?",
                (status.value, finished, error, _valid_id(run_id)),
            )
            if cursor.rowcount == 0:
                raise NotFound("run", run_id)
        return self.get_run(run_id)

    def rename_run(self, run_id: int, name: str) -> RunRecord:
        name = valid_name(name)
        with self._transaction() as cursor:
            cursor.execute("UPDATE runs SET name = ? WHERE id = ?", (name, _valid_id(run_id)))
            if cursor.rowcount == 0:
                raise NotFound("run", run_id)
        return self.get_run(run_id)

    def delete_run(self, run_id: int) -> None:
        """The run's rows (statistics and best individuals go with it); its folder is the caller's."""
        with self._transaction() as cursor:
            cursor.execute("DELETE FROM runs WHERE id = ?", (_valid_id(run_id),))
            if cursor.rowcount == 0:
                raise NotFound("run", run_id)

    def mark_interrupted(self) -> list[int]:
        """Runs left running or queued by an app that ended: mark them interrupted (resumable: a queued one
        starts from its beginning, and in classroom mode its resume queues it again). Their ids."""
        pending = (RunStatus.RUNNING.value, RunStatus.QUEUED.value)
        with self._transaction() as cursor:
            ids = [row[0] for row in cursor.execute("SELECT id FROM runs WHERE status IN (?, ?)", pending)]
            cursor.execute("UPDATE runs SET status = ?, finished = ? WHERE status IN (?, ?)",
                           (RunStatus.INTERRUPTED.value, now(), *pending))
        return ids

    # ---- generations --------------------------------------------------------------------
    def record_generation(
        self, run_id: int, stats: dict[str, Any], rules: str, chromosome: str, fitness: float,
        lineage: str | None = None,
    ) -> None:
        """One finished generation: its statistics (with a `generation` key), its best individual and, when
        given, its lineage record (JSON text), together. A generation played again after a resume replaces
        the earlier one."""
        generation = stats.get("generation")
        if not isinstance(generation, int) or isinstance(generation, bool) or generation < 0:
            raise StoreError("statistics need a non-negative integer 'generation'")
        stats_json = _json(stats, "statistics")
        run_id = _valid_id(run_id)
        with self._transaction() as cursor:
            if cursor.execute("SELECT 1 FROM runs WHERE id = ?", (run_id,)).fetchone() is None:
                raise NotFound("run", run_id)
            cursor.execute(
                "INSERT OR REPLACE INTO generation_statistics (run_id, generation, stats) VALUES (?, ?, ?)",
                (run_id, generation, stats_json),
            )
            cursor.execute(
                "INSERT OR REPLACE INTO best_individuals (run_id, generation, rules, chromosome, fitness)"
                " VALUES (?, ?, ?, ?, ?)",
                (run_id, generation, _valid_text(rules), str(chromosome), float(fitness)),
            )
            if lineage is not None:
                cursor.execute("INSERT OR REPLACE INTO lineage (run_id, generation, record) VALUES (?, ?, ?)",
                               (run_id, generation, _valid_text(lineage)))

    def statistics(self, run_id: int) -> list[dict[str, Any]]:
        self.get_run(run_id)
        rows = self._query(
            "SELECT stats FROM generation_statistics WHERE run_id = ? ORDER BY generation", (_valid_id(run_id),)
        )
        return [json.loads(row["stats"]) for row in rows]

    def lineage_record(self, run_id: int, generation: int) -> dict[str, Any]:
        """Generation `generation`'s lineage record (NotFound when there is none)."""
        return json.loads(self.lineage_text(run_id, generation))

    def lineage_text(self, run_id: int, generation: int) -> str:
        """Generation `generation`'s lineage record as stored, JSON text (NotFound when there is none)."""
        self.get_run(run_id)
        rows = self._query("SELECT record FROM lineage WHERE run_id = ? AND generation = ?",
                           (run_id, _valid_id(generation)))
        if not rows:
            raise NotFound("lineage record", generation, f"run {run_id} has no lineage record of generation {generation}")
        return rows[0]["record"]

    def best_individuals(self, run_id: int) -> list[BestIndividual]:
        self.get_run(run_id)
        rows = self._query("SELECT * FROM best_individuals WHERE run_id = ? ORDER BY generation", (run_id,))
        return [BestIndividual(**dict(row)) for row in rows]

    def best_individual(self, run_id: int) -> BestIndividual:
        """The best individual so far: the lowest fitness, the latest generation among equals."""
        self.get_run(run_id)
        rows = self._query(
            "SELECT * FROM best_individuals WHERE run_id = ? ORDER BY fitness ASC, generation DESC LIMIT 1", (run_id,)
        )
        if not rows:
            raise NotFound("best individual of run", run_id)
        return BestIndividual(**dict(rows[0]))

    # ---- experiments --------------------------------------------------------------------
    def record_experiment(self, preset: str, folder: str | Path, summary: dict[str, Any]) -> ExperimentRecord:
        """A finished experiment. The same preset recorded again in the same folder (a resumed or
        repeated experiment) replaces its earlier summary: one library entry per folder and preset."""
        preset = valid_name(preset)
        summary_json = _json(summary, "experiment summary")
        stamp = now()
        with self._transaction() as cursor:
            row = cursor.execute(
                "SELECT id FROM experiments WHERE preset = ? AND folder = ?", (preset, str(folder))
            ).fetchone()
            if row is None:
                cursor.execute(
                    "INSERT INTO experiments (preset, folder, created, summary) VALUES (?, ?, ?, ?)",
                    (preset, str(folder), stamp, summary_json),
                )
                record_id = cursor.lastrowid
            else:
                record_id = row[0]
                cursor.execute(
                    "UPDATE experiments SET created = ?, summary = ? WHERE id = ?", (stamp, summary_json, record_id)
                )
        return self.get_experiment(record_id)

    def get_experiment(self, experiment_id: int) -> ExperimentRecord:
        rows = self._query("SELECT * FROM experiments WHERE id = ?", (_valid_id(experiment_id),))
        if not rows:
            raise NotFound("experiment", experiment_id)
        return _experiment_record(rows[0])

    def list_experiments(self) -> list[ExperimentRecord]:
        """Newest first."""
        return [_experiment_record(row) for row in self._query("SELECT * FROM experiments ORDER BY id DESC")]


    # ---- classroom: students, tournament entries, rounds ----------------------------------------
    def add_student(self, name: str, token_hash: str) -> StudentRecord:
        """A student who joined under `name` (one line of plain text, unique in the class ignoring case and
        spacing: StoreError when taken); `token_hash` identifies their browser (app/web/classroom/admission.py)."""
        name = valid_name(name)
        stamp = now()
        with self._transaction() as cursor:
            try:
                cursor.execute("INSERT INTO students (name, name_key, token_hash, created) VALUES (?, ?, ?, ?)",
                               (name, name_key(name), token_hash, stamp))
            except sqlite3.IntegrityError:
                raise StoreError(f"the name {name!r} is taken in this class: choose another") from None
            student_id = cursor.lastrowid
        return StudentRecord(student_id, name, stamp)

    def rename_student(self, student_id: int, name: str) -> StudentRecord:
        """A student's browser joined again under another name: the same student, renamed (StoreError when
        the name is taken)."""
        name = valid_name(name)
        with self._transaction() as cursor:
            try:
                cursor.execute("UPDATE students SET name = ?, name_key = ? WHERE id = ?",
                               (name, name_key(name), _valid_id(student_id)))
            except sqlite3.IntegrityError:
                raise StoreError(f"the name {name!r} is taken in this class: choose another") from None
            if cursor.rowcount == 0:
                raise NotFound("student", student_id)
        return self.get_student(student_id)

    def student_by_token(self, token_hash: str) -> StudentRecord | None:
        rows = self._query("SELECT id, name, created FROM students WHERE token_hash = ?", (token_hash,))
        return StudentRecord(**dict(rows[0])) if rows else None

    def get_student(self, student_id: int) -> StudentRecord:
        rows = self._query("SELECT id, name, created FROM students WHERE id = ?", (_valid_id(student_id),))
        if not rows:
            raise NotFound("student", student_id)
        return StudentRecord(**dict(rows[0]))

    def list_students(self) -> list[StudentRecord]:
        return [StudentRecord(**dict(row)) for row in self._query("SELECT id, name, created FROM students ORDER BY id")]

    def remove_student(self, student_id: int) -> None:
        """The student leaves the class: their browser must join again, their entry goes; what they saved
        and ran stays, seen by the teacher only."""
        with self._transaction() as cursor:
            cursor.execute("DELETE FROM students WHERE id = ?", (_valid_id(student_id),))
            if cursor.rowcount == 0:
                raise NotFound("student", student_id)

    def submit_entry(self, student_id: int | None, name: str, text: str, source: str) -> EntryRecord:
        """A student's entry replaces their earlier one (under their name); a teacher's entry (`student_id`
        None) replaces the teacher's entry of the same name. A name another's entry holds is refused."""
        name, text = valid_name(name), _valid_text(text)
        key, stamp = name_key(name), now()
        with self._transaction() as cursor:
            holder = cursor.execute("SELECT id, student_id FROM class_entries WHERE name_key = ?", (key,)).fetchone()
            if holder is not None and holder["student_id"] != student_id:
                raise StoreError(f"the name {name!r} is another entry's: choose another")
            if student_id is not None:
                cursor.execute("DELETE FROM class_entries WHERE student_id = ?", (student_id,))
            elif holder is not None:
                cursor.execute("DELETE FROM class_entries WHERE id = ?", (holder["id"],))
            cursor.execute(
                "INSERT INTO class_entries (student_id, name, name_key, text, source, submitted) VALUES (?, ?, ?, ?, ?, ?)",
                (student_id, name, key, text, source, stamp))
            entry_id = cursor.lastrowid
        return EntryRecord(entry_id, student_id, name, text, source, stamp)

    def list_entries(self) -> list[EntryRecord]:
        """In the order they were (last) submitted."""
        return [EntryRecord(**{k: row[k] for k in row.keys() if k != "name_key"})
                for row in self._query("SELECT * FROM class_entries ORDER BY id")]

    def delete_entry(self, entry_id: int) -> None:
        with self._transaction() as cursor:
            cursor.execute("DELETE FROM class_entries WHERE id = ?", (_valid_id(entry_id),))
            if cursor.rowcount == 0:
                raise NotFound("entry", entry_id)

    def record_round(self, seed: int, starts: int, game: dict[str, Any], results: list[dict[str, Any]]) -> RoundRecord:
        stamp = now()
        with self._transaction() as cursor:
            cursor.execute("INSERT INTO class_rounds (created, seed, starts, game, results) VALUES (?, ?, ?, ?, ?)",
                           (stamp, int(seed), int(starts), _json(game, "round game"), _json(results, "round results")))
            round_id = cursor.lastrowid
        return self.get_round(round_id)

    def get_round(self, round_id: int) -> RoundRecord:
        rows = self._query("SELECT * FROM class_rounds WHERE id = ?", (_valid_id(round_id),))
        if not rows:
            raise NotFound("round", round_id)
        return _round_record(rows[0])

    def list_rounds(self) -> list[RoundRecord]:
        """Newest first."""
        return [_round_record(row) for row in self._query("SELECT * FROM class_rounds ORDER BY id DESC")]


    # ---- classroom: knockouts ----------------------------------------------------------------------
    def create_knockout(self, seed: int, best_of: int, game: dict[str, Any], draw: list[dict[str, Any]]) -> KnockoutRecord:
        """A knockout about to be played (status playing, no tie yet)."""
        with self._transaction() as cursor:
            cursor.execute(
                "INSERT INTO class_knockouts (created, seed, best_of, game, draw, status) VALUES (?, ?, ?, ?, ?, ?)",
                (now(), int(seed), int(best_of), _json(game, "knockout game"), _json(draw, "knockout draw"),
                 KnockoutStatus.PLAYING.value))
            knockout_id = cursor.lastrowid
        return self.get_knockout(knockout_id)

    def record_tie(self, knockout_id: int, tie: dict[str, Any]) -> None:
        """A finished tie (its dict has `round` and `tie`, numbered from 1)."""
        with self._transaction() as cursor:
            cursor.execute("INSERT INTO class_knockout_ties (knockout_id, round, tie, result) VALUES (?, ?, ?, ?)",
                           (_valid_id(knockout_id), int(tie["round"]), int(tie["tie"]), _json(tie, "knockout tie")))

    def end_knockout(self, knockout_id: int, status: KnockoutStatus, error: str | None = None) -> KnockoutRecord:
        with self._transaction() as cursor:
            cursor.execute("UPDATE class_knockouts SET status = ?, finished = ?, error = ? WHERE id = ?",
                           (KnockoutStatus(status).value, now(), error, _valid_id(knockout_id)))
            if cursor.rowcount == 0:
                raise NotFound("knockout", knockout_id)
        return self.get_knockout(knockout_id)

    def mark_knockouts_interrupted(self) -> list[int]:
        """Knockouts left playing by an app that ended: marked interrupted (not resumed: the teacher starts
        one again, and the same seed plays the same matches). Their ids."""
        with self._transaction() as cursor:
            playing = (KnockoutStatus.PLAYING.value,)
            ids = [row[0] for row in cursor.execute("SELECT id FROM class_knockouts WHERE status = ?", playing)]
            cursor.execute("UPDATE class_knockouts SET status = ?, finished = ?, error = ? WHERE status = ?",
                           (KnockoutStatus.INTERRUPTED.value, now(), "the app ended while it was played", *playing))
        return ids

    def get_knockout(self, knockout_id: int) -> KnockoutRecord:
        rows = self._query("SELECT * FROM class_knockouts WHERE id = ?", (_valid_id(knockout_id),))
        if not rows:
            raise NotFound("knockout", knockout_id)
        ties = self._query("SELECT result FROM class_knockout_ties WHERE knockout_id = ? ORDER BY round, tie",
                           (knockout_id,))
        return _knockout_record(rows[0], [json.loads(row["result"]) for row in ties])

    def latest_knockout(self) -> KnockoutRecord | None:
        rows = self._query("SELECT id FROM class_knockouts ORDER BY id DESC LIMIT 1")
        return self.get_knockout(rows[0][0]) if rows else None

    def list_knockouts(self) -> list[KnockoutRecord]:
        """Newest first."""
        ids = [row[0] for row in self._query("SELECT id FROM class_knockouts ORDER BY id DESC")]
        return [self.get_knockout(knockout_id) for knockout_id in ids]


def _knockout_record(row: sqlite3.Row, ties: list[dict[str, Any]]) -> KnockoutRecord:
    values = dict(row)
    values["game"] = json.loads(values["game"])
    values["draw"] = json.loads(values["draw"])
    values["status"] = KnockoutStatus(values["status"])
    return KnockoutRecord(**values, ties=ties)


def _round_record(row: sqlite3.Row) -> RoundRecord:
    values = dict(row)
    values["game"] = json.loads(values["game"])
    values["results"] = json.loads(values["results"])
    return RoundRecord(**values)


def _run_record(row: sqlite3.Row) -> RunRecord:
    values = dict(row)
    values["config"] = json.loads(values["config"])
    values["status"] = RunStatus(values["status"])
    return RunRecord(**values)


def _experiment_record(row: sqlite3.Row) -> ExperimentRecord:
    values = dict(row)
    values["summary"] = json.loads(values["summary"])
    return ExperimentRecord(**values)


def _valid_id(record_id: object) -> int:
    if isinstance(record_id, bool) or not isinstance(record_id, int):
        raise StoreError(f"an id is an integer, not {record_id!r}")
    return record_id


# Characters that change how the text around them is laid out: bidirectional embeddings, overrides and
# isolates (a name "abc\u202efdp.exe" shows as "abcexe.pdf") and the directional marks.
BIDI_CONTROLS = frozenset("\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")


def valid_name(name: object) -> str:
    """A name as users see it everywhere: one line of plain text (no control character, no bidirectional
    override); StoreError saying what was wrong."""
    if not isinstance(name, str) or not name.strip():
        raise StoreError("a name must be a non-empty string")
    if len(name) > NAME_MAX_LENGTH:
        raise StoreError(f"a name is at most {NAME_MAX_LENGTH} characters")
    for position, character in enumerate(name, 1):
        if unicodedata.category(character) == "Cc" or character in BIDI_CONTROLS:
            kind = "a control character" if unicodedata.category(character) == "Cc" else "a bidirectional control"
            raise StoreError(f"a name cannot hold {kind} (U+{ord(character):04X} at character {position}): "
                             "use plain text on one line")
    return name.strip()


def _valid_text(text: object) -> str:
    if not isinstance(text, str):
        raise StoreError("rule text must be a string")
    return text


def _json(value: Any, what: str) -> str:
    try:
        return json.dumps(_finite(value), allow_nan=False, default=_plain)
    except (TypeError, ValueError) as exc:
        raise StoreError(f"{what} is not JSON data: {exc}") from exc


def _finite(value: Any) -> Any:
    """NaN and infinities (e.g. a statistic of an empty set) stored as null: JSON has no such numbers."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(item) for item in value]
    return value


def _plain(value: Any) -> Any:
    """numpy scalars and arrays (statistics computed with numpy) as plain JSON values."""
    if hasattr(value, "tolist"):
        return _finite(value.tolist())
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")
