"""The experiment's figures (PNG, matplotlib without pyplot: no display, no global state), in the manner
of the chapter's Figs. 8-31, drawn from the statistics table, and each trial's best player as the GA
saw it and re-played on fresh starts (bests.csv). Generation axes tick whole generations only. Fitness
curves over several trials are medians over trials, as the report's tables beside them; every axis says
what it averages; legends stand beside the axes, never over the data."""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure as MatplotlibFigure
from matplotlib.ticker import MaxNLocator

from soccer_lab.app.experiment.presets import Preset
from soccer_lab.app.experiment.table import BestsTable, StatisticsTable

FIGURES_FOLDER = "figures"
SIZE_INCHES = (7.5, 4.2)
DPI = 110
TITLE_CHARACTERS = 95  # what fits across SIZE_INCHES at the title's 10 pt
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


def write_figures(table: StatisticsTable, preset: Preset, folder: Path,
                  bests: BestsTable | None = None) -> list[Figure]:
    """Every figure of the preset into folder/figures/ (those of bests when there are bests); their paths
    relative to folder."""
    (folder / FIGURES_FOLDER).mkdir(parents=True, exist_ok=True)
    figures = []
    for kind in preset.figures:
        if kind in BEST_DRAWERS and not (bests and bests.settings(preset.name)):
            continue
        figure, caption = draw_figure(kind, table, preset, bests)
        relative = Path(FIGURES_FOLDER) / f"{preset.name}-{kind}.png"
        figure.savefig(folder / relative, metadata={"Software": None})
        figures.append(Figure(relative, caption))
    return figures


def draw_figure(kind: str, table: StatisticsTable, preset: Preset,
                bests: BestsTable | None = None) -> tuple[MatplotlibFigure, str]:
    """One figure of the preset, and its caption."""
    title, draw = {**DRAWERS, **BEST_DRAWERS}[kind]
    figure = MatplotlibFigure(figsize=SIZE_INCHES, dpi=DPI, layout="constrained")
    axes = figure.subplots()
    draw(axes, bests if kind in BEST_DRAWERS else table, preset)
    if axes.get_xlabel() == "generation":
        axes.xaxis.set_major_locator(MaxNLocator(integer=True))
    chapter = CHAPTER_FIGURES.get((preset.name, kind))
    caption = f"{preset.title}: {title}" + (f" (chapter Fig. {chapter})" if chapter else "")
    # over the whole figure (a legend beside the axes moves them), wrapped so that a long caption is never cut
    figure.suptitle(textwrap.fill(caption, TITLE_CHARACTERS, break_on_hyphens=False), fontsize=10)
    return figure, caption


# ---- drawers ---------------------------------------------------------------------------------------
def _legend(axes, **options) -> None:
    """The legend beside the axes (constrained layout narrows them to make room), never over the data."""
    axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), **{"fontsize": 8, **options})


def _median_curve(curves: np.ndarray) -> np.ndarray:
    """The median over trials at each generation: what the report's tables give (their final medians)."""
    with np.errstate(all="ignore"):
        return np.nanmedian(curves, axis=0)
def _x(table: StatisticsTable, preset: Preset) -> tuple[dict[str, np.ndarray], str]:
    """Generations; evaluations when the settings spend them at different rates (population, random);
    games played when their evaluations play different numbers of games."""
    settings = table.settings(preset.name)
    games = {s.label: s.games_per_evaluation for s in preset.settings}
    if len({games.get(s, 1) for s in settings}) > 1:
        return {s: table.evaluations(preset.name, s) * games.get(s, 1) for s in settings}, "games played"
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
                _legend(axes, fontsize=7)
            over = "each trial"
        else:
            for setting in table.settings(preset.name):
                axes.plot(xs[setting], _median_curve(table.curves(preset.name, setting, column)), label=setting)
            _legend(axes, title=preset.varied)
            over = "median over trials"
        axes.set_xlabel(xlabel)
        axes.set_ylabel(f"{what} fitness ({over}; lower is better)")
        axes.grid(alpha=0.3)
    return draw


def _averaged(column: str, ylabel: str):
    def draw(axes, table: StatisticsTable, preset: Preset) -> None:
        xs, xlabel = _x(table, preset)
        for setting in table.settings(preset.name):
            axes.plot(xs[setting], _median_curve(table.curves(preset.name, setting, column)), label=setting)
        _legend(axes, title=preset.varied)
        axes.set_xlabel(xlabel)
        axes.set_ylabel(f"{ylabel} (median over trials)")
        axes.grid(alpha=0.3)
    return draw


def _goal_histogram(axes, table: StatisticsTable, preset: Preset) -> None:
    """One bar per generation, centred on it, stacked by goals scored."""
    shares = np.array([np.concatenate([table.curves(preset.name, s, c) for s in table.settings(preset.name)])
                       for c in GOAL_COLUMNS])  # goal class x trials x generations
    mean = np.nanmean(shares, axis=1) * 100
    generations = np.arange(mean.shape[1])
    below = np.zeros(mean.shape[1])
    for share, label in zip(mean, GOAL_LABELS):
        axes.bar(generations, share, 0.8, bottom=below, align="center", label=f"{label} goals")
        below += share
    axes.set_xlim(-0.6, mean.shape[1] - 0.4)
    axes.set_xlabel("generation")
    axes.set_ylabel("% of population (mean over trials)")
    _legend(axes, fontsize=7)
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
    axes.set_ylabel("per chromosome (population mean +- std,\naveraged over trials)")
    _legend(axes)
    axes.grid(alpha=0.3)


def _gene_pools(axes, table: StatisticsTable, preset: Preset) -> None:
    setting = table.settings(preset.name)[0]
    for column, label in GENE_POOLS:
        axes.plot(np.nanmean(table.curves(preset.name, setting, column), axis=0), label=label)
    axes.set_xlabel("generation")
    axes.set_ylabel("distinct genes in the population\n(mean over trials)")
    _legend(axes)
    axes.grid(alpha=0.3)


def _best_so_far(axes, table: StatisticsTable, preset: Preset) -> None:
    """The best fitness found so far, averaged over trials: what a run of restarts ends with."""
    xs, xlabel = _x(table, preset)
    for setting in table.settings(preset.name):
        curves = np.fmin.accumulate(table.curves(preset.name, setting, "best"), axis=1)
        axes.plot(xs[setting], _median_curve(curves), label=setting)
    _legend(axes, title=preset.varied)
    axes.set_xlabel(xlabel)
    axes.set_ylabel("best fitness so far (median over trials;\nlower is better)")
    axes.grid(alpha=0.3)


def _rules_and_bound(axes, table: StatisticsTable, preset: Preset) -> None:
    """Valid rules per chromosome against their bound: a valid rule takes two genes at least."""
    for setting in table.settings(preset.name):
        rules = np.nanmean(table.curves(preset.name, setting, "valid_rules_mean"), axis=0)
        bound = np.nanmean(table.curves(preset.name, setting, "genes_mean"), axis=0) / 2
        (line,) = axes.plot(rules, label=f"{setting}: valid rules")
        axes.plot(bound, linestyle="--", color=line.get_color(), label=f"{setting}: bound (genes / 2)")
    axes.set_xlabel("generation")
    axes.set_ylabel("per chromosome (mean over trials)")
    _legend(axes, title=preset.varied, fontsize=7)
    axes.grid(alpha=0.3)


def _premises_per_rule(axes, table: StatisticsTable, preset: Preset) -> None:
    for setting in table.settings(preset.name):
        premises = table.curves(preset.name, setting, "premises_mean")
        rules = table.curves(preset.name, setting, "valid_rules_mean")
        with np.errstate(divide="ignore", invalid="ignore"):  # a generation without valid rules has no ratio
            axes.plot(np.nanmean(premises / rules, axis=0), label=setting)
    axes.set_xlabel("generation")
    axes.set_ylabel("premises per valid rule (mean over trials)")
    _legend(axes, title=preset.varied)
    axes.grid(alpha=0.3)


def _true_quality(axes, bests: BestsTable, preset: Preset) -> None:
    """Each trial's best: the fitness the GA saw (one noisy game, or the mean of the few it survived)
    beside its mean over the replays, joined per trial."""
    replays = sorted({int(row["replays"]) for row in bests.rows if row["preset"] == preset.name})
    for i, setting in enumerate(bests.settings(preset.name)):
        seen = bests.column(preset.name, setting, "fitness_seen")
        replayed = bests.column(preset.name, setting, "replay_fitness")
        x = np.full(len(seen), float(i))
        for a, b in zip(seen, replayed):
            axes.plot([i - 0.15, i + 0.15], [a, b], color="0.75", linewidth=0.7)
        axes.scatter(x - 0.15, seen, facecolors="none", edgecolors="C0", label="as the GA saw it" if i == 0 else None)
        axes.scatter(x + 0.15, replayed, color="C3",
                     label=f"re-played on {'/'.join(map(str, replays))} fresh starts" if i == 0 else None)
    axes.set_xticks(range(len(bests.settings(preset.name))), bests.settings(preset.name))
    axes.set_xlabel(preset.varied)
    axes.set_ylabel("fitness of each trial's best (lower is better)")
    _legend(axes)
    axes.grid(alpha=0.3, axis="y")


# figure kind -> (title, drawer(axes, table, preset))
DRAWERS = {
    "mean_fitness": ("population average fitness", _fitness("mean", "population average")),
    "best_fitness": ("best fitness", _fitness("best", "best")),
    "goal_histogram": ("share of the population scoring 0..>4 goals", _goal_histogram),
    "chromosome_length": ("average chromosome length", _averaged("genes_mean", "genes per chromosome")),
    "valid_rules": ("average valid rules per chromosome", _averaged("valid_rules_mean", "valid rules per chromosome")),
    "composition": ("population composition", _composition),
    "gene_pools": ("gene pools", _gene_pools),
    "best_so_far": ("best fitness so far", _best_so_far),
    "rules_and_bound": ("valid rules per chromosome and their bound", _rules_and_bound),
    "premises_per_rule": ("premises per valid rule", _premises_per_rule),
}
# figure kind -> (title, drawer(axes, bests, preset)): drawn from bests.csv
BEST_DRAWERS = {
    "true_quality": ("each trial's best, as the GA saw it and re-played", _true_quality),
}
FIGURE_KINDS = (*DRAWERS, *BEST_DRAWERS)
