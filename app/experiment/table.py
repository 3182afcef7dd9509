"""statistics.csv in memory: one row per (preset, setting, trial, generation), every statistic of `soccer_lab.ga.statistics.GenerationStats`.
bests.csv: one row per (preset, setting, trial), its best player's fitness as the GA saw it and re-played.
Figures and the report read only these tables, so they work as well on fabricated statistics."""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any, Iterable, Mapping, Self

import numpy as np

from soccer_lab.ga.statistics import ADDED_LATER, GenerationStats

PRESET, SETTING, TRIAL, SEED, ALGORITHM = "preset", "setting", "trial", "seed", "algorithm"
KEY_COLUMNS = (PRESET, SETTING, TRIAL, SEED, ALGORITHM)
STATISTIC_COLUMNS = GenerationStats.field_names()
COLUMNS = (*KEY_COLUMNS, *STATISTIC_COLUMNS)
TEXT_COLUMNS = (PRESET, SETTING, ALGORITHM)
# bests.csv: where the best was found, the fitness the GA saw (its running mean over `evaluations_seen`
# evaluations), then its `replays` fresh starts: mean and std of fitness, mean goals, share that scored
BEST_COLUMNS = (*KEY_COLUMNS, "generation", "fitness_seen", "evaluations_seen", "replays", "replay_fitness",
                "replay_fitness_std", "replay_goals", "replay_scoring")


class TableError(ValueError):
    pass


class CsvTable:
    """Rows of a CSV the runner writes, with `columns` checked on reading (`what`: the rows, in errors)."""

    columns: tuple[str, ...] = ()
    what = "rows"

    def __init__(self, rows: Iterable[Mapping[str, Any]]):
        self.rows = [self._completed(row) for row in rows]
        missing = [c for c in self.columns if self.rows and c not in self.rows[0]]
        if missing:
            raise TableError(f"{self.what} lack the columns {', '.join(missing)}")

    @staticmethod
    def _completed(row: Mapping[str, Any]) -> dict[str, Any]:
        return dict(row)

    @classmethod
    def read(cls, path: str | Path) -> Self:
        with Path(path).open(newline="") as handle:
            return cls(_typed(row) for row in csv.DictReader(handle))

    def to_csv(self) -> str:
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=self.columns, extrasaction="ignore", lineterminator="\n")
        writer.writeheader()
        writer.writerows(self.rows)
        return buffer.getvalue()


class StatisticsTable(CsvTable):
    columns, what = COLUMNS, "statistics"

    @staticmethod
    def _completed(row: Mapping[str, Any]) -> dict[str, Any]:
        return {**ADDED_LATER, **row}  # an older study's table lacks the later statistics

    # ---- selections -----------------------------------------------------------------------------
    def presets(self) -> list[str]:
        return _unique(row[PRESET] for row in self.rows)

    def settings(self, preset: str) -> list[str]:
        return _unique(row[SETTING] for row in self.rows if row[PRESET] == preset)

    def trials(self, preset: str, setting: str) -> list[int]:
        return _unique(int(row[TRIAL]) for row in self._rows(preset, setting))

    def curves(self, preset: str, setting: str, column: str) -> np.ndarray:
        """trials x generations; a trial with fewer generations is padded with NaN."""
        by_trial: dict[int, list[tuple[int, float]]] = {}
        for row in self._rows(preset, setting):
            by_trial.setdefault(int(row[TRIAL]), []).append((int(row["generation"]), float(row[column])))
        length = max((len(points) for points in by_trial.values()), default=0)
        curves = np.full((len(by_trial), length), np.nan)
        for i, points in enumerate(by_trial.values()):
            values = [value for _, value in sorted(points)]
            curves[i, :len(values)] = values
        return curves

    def final(self, preset: str, setting: str, column: str) -> np.ndarray:
        """Each trial's value in its last generation."""
        curves = self.curves(preset, setting, column)
        return np.array([row[~np.isnan(row)][-1] for row in curves]) if curves.size else np.array([])

    def best_so_far(self, preset: str, setting: str) -> np.ndarray:
        """Each trial's best fitness over the whole run."""
        curves = self.curves(preset, setting, "best")
        return np.nanmin(curves, axis=1) if curves.size else np.array([])

    def evaluations(self, preset: str, setting: str) -> np.ndarray:
        """The x axis for comparisons at equal evaluations: evaluations so far, per generation."""
        return np.nanmean(self.curves(preset, setting, "evaluations"), axis=0)

    def _rows(self, preset: str, setting: str) -> list[dict[str, Any]]:
        return [row for row in self.rows if row[PRESET] == preset and row[SETTING] == setting]


class BestsTable(CsvTable):
    columns, what = BEST_COLUMNS, "bests"

    def settings(self, preset: str) -> list[str]:
        return _unique(row[SETTING] for row in self.rows if row[PRESET] == preset)

    def column(self, preset: str, setting: str, column: str) -> np.ndarray:
        """One value per trial, in trial order."""
        rows = sorted((row for row in self.rows if row[PRESET] == preset and row[SETTING] == setting),
                      key=lambda row: int(row[TRIAL]))
        return np.array([float(row[column]) for row in rows])


def _unique(values: Iterable[Any]) -> list[Any]:
    return list(dict.fromkeys(values))


def _typed(row: Mapping[str, str]) -> dict[str, Any]:
    try:
        return {name: value if name in TEXT_COLUMNS else _number(value) for name, value in row.items()}
    except ValueError as exc:
        raise TableError(f"statistics.csv holds a value that is not a number: {exc}") from None


def _number(text: str) -> int | float:
    """Integers stay exact (seeds need 63 bits), the rest are floats."""
    try:
        return int(text)
    except ValueError:
        return float(text)
