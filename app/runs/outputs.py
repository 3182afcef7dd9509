"""The run folder: where `evolve`, `random-search` and the server keep one run's outputs.

```
RUN_DIR/
  run.json               what is run (algorithm, GA parameters, environment): enough to resume it; and
                         under "best" the best so far: the fitness the GA saw and its true quality
                         (re-played on the same fresh starts as every run's players: app/runs/true_quality.py)
  statistics.csv         every statistic of each generation, one row per generation
  generation_bests.jsonl each generation's best individual, one JSON object a line
  lineage.jsonl          every individual of each generation with its birth (parents, operations), a line
                         a generation (ga/lineage.py): what `soccer-lab lineage` follows back
  checkpoint             the GA's full state after the last finished generation
  best.rules             the best rulebase so far, as rule text
  best.json              the same, as versioned JSON
  run.rrd                the rerun recording (app/runs/recording.py)
```
`RunOutputs` is the per-generation callback that keeps the folder current, so a killed run keeps
every finished generation. Generations are numbered from 0 (the evaluated initial population)
everywhere: in statistics.csv, generation_bests.jsonl, the recording and the app's API.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Sequence

from soccer_lab.app.rulebase_files import rulebase_json, rulebase_text
from soccer_lab.app.runs.true_quality import TrueQuality
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.lineage import generation_record

RUNS_ROOT = Path("runs")
RUN_MANIFEST = "run.json"
STATISTICS_CSV = "statistics.csv"
CHECKPOINT = "checkpoint"
BEST_RULES = "best.rules"
BEST_JSON = "best.json"
RECORDING = "run.rrd"
GENERATION_BESTS = "generation_bests.jsonl"
LINEAGE = "lineage.jsonl"
TIMESTAMP_FORMAT = "%Y%m%d-%H%M%S"
BEST_KEY = "best"  # run.json's record of the best so far
Replayer = Callable[[Rulebase], TrueQuality]  # a player's true quality


class RunFolderError(ValueError):
    """A run folder that cannot be created, read or resumed."""


def default_run_dir(now: datetime | None = None, root: Path = RUNS_ROOT) -> Path:
    """root/<timestamp>, e.g. runs/20240131-142502 (runs/20240131-142502-2 if that one is taken)."""
    stamp = (now or datetime.now()).strftime(TIMESTAMP_FORMAT)
    path, number = root / stamp, 1
    while path.exists():
        number += 1
        path = root / f"{stamp}-{number}"
    return path


@dataclass(frozen=True)
class RunFolder:
    path: Path

    @property
    def manifest(self) -> Path:
        return self.path / RUN_MANIFEST

    @property
    def statistics(self) -> Path:
        return self.path / STATISTICS_CSV

    @property
    def checkpoint(self) -> Path:
        return self.path / CHECKPOINT

    @property
    def best_rules(self) -> Path:
        return self.path / BEST_RULES

    @property
    def best_json(self) -> Path:
        return self.path / BEST_JSON

    @property
    def recording(self) -> Path:
        return self.path / RECORDING

    @property
    def generation_bests(self) -> Path:
        return self.path / GENERATION_BESTS

    @property
    def lineage(self) -> Path:
        return self.path / LINEAGE

    @classmethod
    def create(cls, path: str | Path, manifest: Mapping[str, Any]) -> "RunFolder":
        """A new run folder. Refuses a folder that already holds a run (use resume for that)."""
        folder = cls(Path(path))
        if folder.manifest.exists():
            raise RunFolderError(f"{folder.path} already holds a run (use --resume {folder.path} to continue it)")
        try:
            folder.path.mkdir(parents=True, exist_ok=True)
            _write_atomically(folder.manifest, json.dumps(manifest, indent=2) + "\n")
        except OSError as exc:
            raise RunFolderError(f"cannot create run folder {folder.path}: {exc.strerror or exc}") from exc
        return folder

    @classmethod
    def open(cls, path: str | Path) -> "RunFolder":
        """An existing run folder, for resuming: it must have its manifest and a checkpoint."""
        folder = cls(Path(path))
        if not folder.path.is_dir():
            raise RunFolderError(f"{folder.path} is not a run folder")
        if not folder.manifest.is_file():
            raise RunFolderError(f"{folder.path} is not a run folder (no {RUN_MANIFEST})")
        if not folder.checkpoint.is_file():
            raise RunFolderError(f"{folder.path} has no checkpoint: the run finished no generation to resume from")
        return folder

    def read_manifest(self) -> dict[str, Any]:
        try:
            manifest = json.loads(self.manifest.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise RunFolderError(f"cannot read {self.manifest}: {exc}") from exc
        if not isinstance(manifest, dict):
            raise RunFolderError(f"{self.manifest} is not a run manifest")
        return manifest

    def write_best(self, rule_text: str, json_text: str) -> None:
        _write_atomically(self.best_rules, rule_text)
        _write_atomically(self.best_json, json_text)

    def write_best_record(self, record: Mapping[str, Any]) -> None:
        """run.json's "best": the best so far, its fitness as the GA saw it and its true quality."""
        manifest = self.read_manifest()
        manifest[BEST_KEY] = dict(record)
        _write_atomically(self.manifest, json.dumps(manifest, indent=2) + "\n")

    def best_record(self) -> dict[str, Any] | None:
        """run.json's "best", None for runs from before it was kept (or a folder without run.json)."""
        try:
            record = self.read_manifest().get(BEST_KEY)
        except RunFolderError:
            return None
        return record if isinstance(record, dict) else None

    def best_quality(self) -> TrueQuality | None:
        record = self.best_record()
        return TrueQuality.from_dict(record.get("true_quality")) if record else None


def generation_best(population: Sequence[Individual]) -> Individual:
    """A generation's best individual: the lowest (running mean) fitness, the first of equals, as the GA's."""
    return min(population, key=lambda individual: individual.fitness)


class GenerationBestsFile:
    """generation_bests.jsonl: each generation's best individual (its genes, evaluations and the seed of
    its first game), one JSON object a line: what the recording's replays are played from, so a resumed
    run can replay the generations before it again."""

    def __init__(self, path: Path, bests: Iterable[tuple[int, Individual]] = ()):
        """Starts the file afresh with `bests` (generation, individual), as StatisticsFile does."""
        self.path = path
        self.path.write_text("")
        for generation, individual in bests:
            self.append(generation, individual)

    def append(self, generation: int, individual: Individual) -> None:
        with self.path.open("a") as handle:
            handle.write(json.dumps({"generation": generation, **individual.to_dict()}) + "\n")

    @staticmethod
    def read(path: Path) -> list[tuple[int, Individual]]:
        """The (generation, individual) lines written whole; [] when there is no file (older run folders).
        A line cut short by a kill ends the list."""
        bests = []
        try:
            lines = path.read_text().splitlines()
        except OSError:
            return []
        for line in lines:
            try:
                row = json.loads(line)
                bests.append((int(row["generation"]), Individual.from_dict(row)))
            except (ValueError, KeyError, TypeError):
                break
        return bests


class LineageFile:
    """lineage.jsonl: every generation's population with each individual's birth (ga/lineage.py's
    generation_record), one JSON object a line, appended as each generation finishes."""

    def __init__(self, path: Path, lines: Iterable[str] = ()):
        """Starts the file afresh with `lines` (when resuming: those of the generations the checkpoint holds)."""
        self.path = path
        self.path.write_text("".join(line + "\n" for line in lines))

    def append(self, generation: int, population: Sequence[Individual], opponents: Sequence[str] | None = None) -> None:
        with self.path.open("a") as handle:
            handle.write(lineage_line(generation, population, opponents) + "\n")

    @staticmethod
    def read(path: Path) -> dict[int, str]:
        """generation -> its line, for the lines written whole ({} when there is no file: runs from before
        lineage was recorded). A line cut short by a kill ends the file, as in GenerationBestsFile."""
        try:
            lines = path.read_text().splitlines()
        except OSError:
            return {}
        records = {}
        for line in lines:
            try:
                records[int(json.loads(line)["generation"])] = line
            except (ValueError, KeyError, TypeError):
                break
        return records


def lineage_line(generation: int, population: Sequence[Individual], opponents: Sequence[str] | None = None) -> str:
    return json.dumps(generation_record(generation, population, opponents), separators=(",", ":"))


class StatisticsFile:
    """statistics.csv, one row per generation, appended as each generation finishes."""

    def __init__(self, path: Path, history: Iterable[Mapping[str, Any]] = ()):
        """Starts the file afresh with `history`: the rows of the generations already finished (when
        resuming, those the checkpoint holds; rows a killed run wrote after its checkpoint go)."""
        self.path = path
        self._fields: list[str] | None = None
        self.path.write_text("")
        for row in history:
            self.append(row)

    def append(self, row: Mapping[str, Any]) -> None:
        header = self._fields is None
        if header:
            self._fields = list(row)
        self._write_rows([row], header=header)

    def _write_rows(self, rows: Iterable[Mapping[str, Any]], header: bool) -> None:
        with self.path.open("a", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=self._fields)
            if header:
                writer.writeheader()
            writer.writerows(rows)


class RunOutputs:
    """Callback for `soccer_lab.ga.algorithms.evolve`: after each generation, appends its statistics to
    statistics.csv and its population to lineage.jsonl, and rewrites best.rules and best.json when the best
    individual so far changed (the GA's own rule: a lower running mean; the first of equals stays); then
    `replay` (when given) re-plays the new best for its true quality, kept in run.json."""

    def __init__(self, folder: RunFolder, vocabulary: Vocabulary, *, history: Iterable[Mapping[str, Any]] = (),
                 best: Individual | None = None, generation_bests: Iterable[tuple[int, Individual]] = (),
                 lineage: Iterable[str] = (), replay: Replayer | None = None):
        """history, best, generation_bests, lineage: the finished generations' statistics, the run's best
        individual, each generation's best and the lines of lineage.jsonl, when resuming."""
        self.folder = folder
        self.vocabulary = vocabulary
        self.codec = ChromosomeCodec(vocabulary)
        self.replay = replay
        self.statistics = StatisticsFile(folder.statistics, history)
        self.generation_bests = GenerationBestsFile(folder.generation_bests, generation_bests)
        self.lineage = LineageFile(folder.lineage, lineage)
        self.best: Individual | None = None
        self.best_quality: TrueQuality | None = None
        self.opponents: list[str] | None = None  # whom the generation under way is scored against (co-evolution)
        if best is not None:
            self._keep_best(best, _found_in(folder.best_record(), best))

    def on_opponents(self, generation: int, members: list[Any]) -> None:
        self.opponents = [member.label for member in members]

    def on_generation(self, stats: Any, population: list[Individual]) -> None:
        self.statistics.append(stats.to_dict())
        self.lineage.append(stats.generation, population, self.opponents)
        contender = generation_best(population)
        self.generation_bests.append(stats.generation, contender)
        if self.best is None or contender.fitness < self.best.fitness:
            self._keep_best(contender, stats.generation)

    def write_best(self, rulebase: Rulebase) -> None:
        self.folder.write_best(rulebase_text(rulebase, self.vocabulary), rulebase_json(rulebase, self.vocabulary))

    def _keep_best(self, best: Individual, generation: int | None) -> None:
        self.best = best
        rulebase = self.codec.decode(best.chromosome)
        self.write_best(rulebase)
        self.best_quality = self.replay(rulebase) if self.replay is not None else None
        self.folder.write_best_record(best_record(best, generation, self.best_quality))


def best_quality_of(folder: str | Path, fitness: float | None = None) -> TrueQuality | None:
    """The true quality run.json keeps for a run folder's best so far; with `fitness`, only when that best
    is the player of this fitness (the store's best may be a generation ahead of run.json for a moment)."""
    record = RunFolder(Path(folder)).best_record()
    if record is None or (fitness is not None and record.get("fitness_seen") != fitness):
        return None
    return TrueQuality.from_dict(record.get("true_quality"))


def replayed_note(quality: TrueQuality | None) -> str:
    """' (re-played on 20 fresh starts: 0.823 ± 0.101)' to stand beside a one-game fitness; '' when unknown."""
    if quality is None:
        return ""
    return f" (re-played on {quality.starts} fresh starts: {quality.fitness:.3f} ± {quality.fitness_std:.3f})"


def run_replayed_note(store: Any, run_id: int, fitness: float | None = None) -> str:
    """replayed_note for a stored run's best (the app's runs keep run.json in their folder); '' when the
    run or its quality is unknown."""
    try:
        folder = store.get_run(run_id).folder
    except KeyError:  # the store's NotFound
        return ""
    return replayed_note(best_quality_of(folder, fitness))


def best_of_run(store: Any, run_id: int) -> dict[str, Any]:
    """What a stored run's best so far was measured at, as the library and class entries keep it beside its
    rules: the run, the generation, the fitness the GA saw and its true quality (None: not re-played).
    NotFound when the run or its best is unknown."""
    best = store.best_individual(run_id)
    quality = best_quality_of(store.get_run(run_id).folder, best.fitness)
    return {"run_id": run_id, "generation": best.generation, "fitness_seen": best.fitness,
            "true_quality": quality.to_dict() if quality is not None else None}


def best_of_text(best_of: dict[str, Any] | None) -> str:
    """e.g. "run #3's best (gen 7): fitness 0.125 as the GA saw it (re-played on 20 fresh starts: 0.823 ± 0.101)";
    '' for rules not saved from a run's best (or a damaged record)."""
    try:
        seen = (f"run #{int(best_of['run_id'])}'s best (gen {int(best_of['generation'])}): "
                f"fitness {float(best_of['fitness_seen']):.3f} as the GA saw it")
    except (KeyError, TypeError, ValueError):
        return ""
    quality = TrueQuality.from_dict(best_of.get("true_quality"))
    return seen + (replayed_note(quality) if quality is not None else " (not re-played)")


def _found_in(record: dict[str, Any] | None, best: Individual) -> int | None:
    """The generation a resumed run's best was found in, as run.json recorded it (None: not recorded)."""
    return record.get("generation") if record and record.get("fitness_seen") == best.fitness else None


def best_record(best: Individual, generation: int | None, quality: TrueQuality | None) -> dict[str, Any]:
    """The best so far as run.json keeps it: the one figure the GA saw beside its true quality."""
    return {"generation": generation, "fitness_seen": best.fitness, "evaluations_seen": best.evaluations,
            "goals_seen": best.goals, "true_quality": quality.to_dict() if quality else None}


def _write_atomically(path: Path, text: str) -> None:
    """Write to a temporary file, then rename: a kill mid-write never leaves a half-written file."""
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(text)
    temporary.replace(path)
