"""The Evolve tab's live diversity plot, under its fitness plot: per generation, the share of distinct
chromosomes and (when the run counts them) of distinct behaviours in the population, and the mean
distance between two players' rule sets; the legend names the latest values and the count of distinct
rules (ga/diversity.py, docs/teaching/lineage.md). Every series lies between 0 (all alike) and 1."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np
import viser
import viser.uplot

from soccer_lab.app.web.ui import style
from soccer_lab.ga.statistics import NOT_MEASURED

SERIES = (("distinct_chromosomes", "distinct chromosomes", style.ACCENT, ()),
          ("distinct_behaviours", "distinct behaviours", style.FIRED, (6.0, 4.0)),
          ("rule_set_distance", "rule-set distance", style.SELECTED, ()))


class DiversityPlot:
    def __init__(self, gui: viser.GuiApi):
        self.population_size = 1
        self.behaviour_seeds = 0
        self.last_generation = 1
        self.rows: list[Mapping[str, Any]] = []
        self.plot = gui.add_uplot(data=self._data(), series=self._series(), scales=self._scales(),
                                  legend=viser.uplot.Legend(live=False), title=self._title(), aspect=1.6,
                                  padding=style.PLOT_PADDING,
                                  axes=(viser.uplot.Axis(incrs=style.GENERATION_STEPS), viser.uplot.Axis()))

    def reset(self, population_size: int, max_generations: int, behaviour_seeds: int) -> None:
        """A new run: shares of `population_size`, generations 0 .. max_generations - 1."""
        self.population_size = max(1, population_size)
        self.last_generation = max(1, max_generations - 1)
        self.behaviour_seeds = behaviour_seeds
        self.rows = []
        self.plot.scales = self._scales()
        self._redraw()

    def add(self, stats: Mapping[str, Any]) -> None:
        """A finished generation's statistics (GenerationStats.to_dict())."""
        self.rows.append(stats)
        self._redraw()

    def _redraw(self) -> None:
        self.plot.data = self._data()
        self.plot.series = self._series()
        self.plot.title = self._title()

    def _values(self, name: str) -> np.ndarray:
        values = np.array([float(row[name]) for row in self.rows], dtype=np.float64)
        if name == "distinct_behaviours":
            values[values == NOT_MEASURED] = np.nan  # uPlot draws nothing where a run did not measure
        if name.startswith("distinct_"):
            values /= self.population_size
        return values

    def _data(self) -> tuple[np.ndarray, ...]:
        if not self.rows:  # uPlot needs a point to set its scales up; NaN draws nothing
            return (np.zeros(1), *(np.full(1, np.nan) for _ in SERIES))
        return (np.array([float(row["generation"]) for row in self.rows]), *(self._values(name) for name, *_ in SERIES))

    def _series(self) -> tuple[viser.uplot.Series, ...]:
        latest = self.rows[-1] if self.rows else None
        labels = []
        for name, label, _, _ in SERIES:
            if latest is None:
                labels.append(label)
            elif name == "rule_set_distance":
                labels.append(f"{label} {float(latest[name]):.2f}")
            elif name == "distinct_behaviours" and int(latest[name]) == NOT_MEASURED:
                labels.append(f"{label}: not counted (behaviour seeds 0)")
            else:
                seeds = f" on {self.behaviour_seeds} seeds" if name == "distinct_behaviours" else ""
                labels.append(f"{label} {int(latest[name])}/{self.population_size}{seeds}")
        return (viser.uplot.Series(label="generation"),
                *(viser.uplot.Series(label=text, stroke=colour, width=2.5, **({"dash": dash} if dash else {}))
                  for text, (_, _, colour, dash) in zip(labels, SERIES)))

    def _scales(self) -> dict[str, viser.uplot.Scale]:
        return {"x": viser.uplot.Scale(time=False, auto=False, range=(0.0, float(self.last_generation))),
                "y": viser.uplot.Scale(auto=False, range=(0.0, 1.0))}

    def _title(self) -> str:
        rules = f": {int(self.rows[-1]['distinct_rules'])} distinct rules" if self.rows else ""
        return f"Diversity (1 = all different){rules}"
