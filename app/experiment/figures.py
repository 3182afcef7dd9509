"""The experiment's figures (PNG, matplotlib without pyplot: no display, no global state), in the manner
of the chapter's Figs. 8-31, drawn from the statistics table alone."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure as MatplotlibFigure

from app.experiment.presets import Preset
from app.experiment.table import StatisticsTable

FIGURES_FOLDER = "figures"
SIZE_INCHES = (7.5, 4.2)
DPI = 110
GOAL_COLUMNS = ("goals_0", "goals_1", "goals_2", "goals_3", "goals_4", "goals_more")
GOAL_LABELS = ("0", "1", "2", "3", "4", ">4")
COMPOSITION = (("genes", "genes"), ("premises", "premises"), ("rules", "rules"), ("valid_rules", "valid rules"))
GENE_POOLS = (("unique_premise_genes", "unique premise genes"), ("unique_consequent_genes", "unique consequent genes"),
              ("unique_genes", "all unique genes"))
# (preset, figure kind) -> the chapter's figure it re-creates
CHAPTER_FIGURES = {
    ("robocup", "mean_fitness"): 8, ("robocup", "best_fitness"): 9, ("robocup", "goal_histogram"): 10,
    ("initial", "mean_fitness"): 11, ("initial", "best_fitness"): 12, ("initial", "goal_histogram"): 13,
    ("max-length", "mean_fitness"): 14, ("max-length", "best_fitness"): 15,
    ("max-length", "chromosome_length"): 16, ("max-length", "valid_rules"): 17,
    ("population", "mean_fitness"): 18, ("population", "best_fitness"): 19,
    ("selection", "mean_fitness"): 20, ("selection", "best_fitness"): 21,
    ("crossover", "mean_fitness"): 22, ("crossover", "best_fitness"): 23,
    ("mutation", "mean_fitness"): 24, ("mutation", "best_fitness"): 25,
    ("long", "mean_fitness"): 26, ("long", "best_fitness"): 27, ("long", "composition"): 28,
    ("long", "gene_pools"): 29,
    ("random", "mean_fitness"): 30, ("random", "best_fitness"): 31,
}


@dataclass(frozen=True)
class Figure:
    path: Path  # relative to the experiment folder
    caption: str


def write_figures(table: StatisticsTable, preset: Preset, folder: Path) -> list[Figure]:
    """Every figure of the preset into folder/figures/; their paths relative to folder."""
    (folder / FIGURES_FOLDER).mkdir(parents=True, exist_ok=True)
    figures = []
    for kind in preset.figures:
        title, draw = DRAWERS[kind]
        figure = MatplotlibFigure(figsize=SIZE_INCHES, dpi=DPI, layout="constrained")
        axes = figure.subplots()
        draw(axes, table, preset)
        chapter = CHAPTER_FIGURES.get((preset.name, kind))
        caption = f"{preset.title}: {title}" + (f" (chapter Fig. {chapter})" if chapter else "")
        axes.set_title(caption, fontsize=10)
        relative = Path(FIGURES_FOLDER) / f"{preset.name}-{kind}.png"
        figure.savefig(folder / relative, metadata={"Software": None})
        figures.append(Figure(relative, caption))
    return figures


# ---- drawers ---------------------------------------------------------------------------------------
def _x(table: StatisticsTable, preset: Preset) -> tuple[dict[str, np.ndarray], str]:
    """Generations, or evaluations when the settings spend them at different rates (population, random)."""
    settings = table.settings(preset.name)
    rates = {table.evaluations(preset.name, s)[0] for s in settings}
    if len(rates) > 1:
        return {s: table.evaluations(preset.name, s) for s in settings}, "evaluations"
    return {s: np.arange(table.curves(preset.name, s, "generation").shape[1]) for s in settings}, "generation"


def _fitness(column: str, what: str):
    def draw(axes, table: StatisticsTable, preset: Preset) -> None:
        xs, xlabel = _x(table, preset)
        if preset.per_trial:
            for setting in table.settings(preset.name):
                for trial, curve in zip(table.trials(preset.name, setting), table.curves(preset.name, setting, column)):
                    axes.plot(xs[setting][:len(curve)], curve, linewidth=0.9, label=f"trial {trial}")
            if len(axes.lines) <= 10:
                axes.legend(fontsize=7, ncols=2)
        else:
            for setting in table.settings(preset.name):
                axes.plot(xs[setting], np.nanmean(table.curves(preset.name, setting, column), axis=0), label=setting)
            axes.legend(title=preset.varied, fontsize=8)
        axes.set_xlabel(xlabel)
        axes.set_ylabel(f"{what} fitness (lower is better)")
        axes.grid(alpha=0.3)
    return draw


def _averaged(column: str, ylabel: str):
    def draw(axes, table: StatisticsTable, preset: Preset) -> None:
        xs, xlabel = _x(table, preset)
        for setting in table.settings(preset.name):
            axes.plot(xs[setting], np.nanmean(table.curves(preset.name, setting, column), axis=0), label=setting)
        axes.legend(title=preset.varied, fontsize=8)
        axes.set_xlabel(xlabel)
        axes.set_ylabel(ylabel)
        axes.grid(alpha=0.3)
    return draw


def _goal_histogram(axes, table: StatisticsTable, preset: Preset) -> None:
    shares = np.array([np.concatenate([table.curves(preset.name, s, c) for s in table.settings(preset.name)])
                       for c in GOAL_COLUMNS])  # goal class x trials x generations
    mean = np.nanmean(shares, axis=1) * 100
    generations = np.arange(mean.shape[1])
    width = 0.8 / len(GOAL_COLUMNS)
    for i, label in enumerate(GOAL_LABELS):
        axes.bar(generations + (i - (len(GOAL_COLUMNS) - 1) / 2) * width, mean[i], width, label=f"{label} goals")
    axes.set_xlabel("generation")
    axes.set_ylabel("% of population (mean over trials)")
    axes.legend(fontsize=7, ncols=3)
    axes.grid(alpha=0.3, axis="y")


def _composition(axes, table: StatisticsTable, preset: Preset) -> None:
    setting = table.settings(preset.name)[0]
    for stem, label in COMPOSITION:
        mean = np.nanmean(table.curves(preset.name, setting, f"{stem}_mean"), axis=0)
        std = np.nanmean(table.curves(preset.name, setting, f"{stem}_std"), axis=0)
        generations = np.arange(len(mean))
        (line,) = axes.plot(generations, mean, label=label)
        axes.fill_between(generations, mean - std, mean + std, color=line.get_color(), alpha=0.2)
    axes.set_xlabel("generation")
    axes.set_ylabel("per chromosome (mean +- std)")
    axes.legend(fontsize=8)
    axes.grid(alpha=0.3)


def _gene_pools(axes, table: StatisticsTable, preset: Preset) -> None:
    setting = table.settings(preset.name)[0]
    for column, label in GENE_POOLS:
        axes.plot(np.nanmean(table.curves(preset.name, setting, column), axis=0), label=label)
    axes.set_xlabel("generation")
    axes.set_ylabel("distinct genes in the population")
    axes.legend(fontsize=8)
    axes.grid(alpha=0.3)


# figure kind -> (title, drawer(axes, table, preset))
DRAWERS = {
    "mean_fitness": ("population average fitness", _fitness("mean", "population average")),
    "best_fitness": ("best fitness", _fitness("best", "best")),
    "goal_histogram": ("share of the population scoring 0..>4 goals", _goal_histogram),
    "chromosome_length": ("average chromosome length", _averaged("genes_mean", "genes per chromosome")),
    "valid_rules": ("average valid rules per chromosome", _averaged("valid_rules_mean", "valid rules per chromosome")),
    "composition": ("population composition", _composition),
    "gene_pools": ("gene pools", _gene_pools),
}
FIGURE_KINDS = tuple(DRAWERS)
