"""The transfer study: does training in SimpleSoccer carry over to rcssserver?

The chapter (6.3) calls SimpleSoccer "a good simplified model" of RoboCupSoccer from the broad likeness
of the two studies' curves, and moves on; Riley's thesis asks whether rules learned in SimpleSoccer
transfer to RoboCupSoccer, and seeds RoboCup runs with them. `soccer-lab experiment transfer` measures
both on the same fuzzy controller and skills:

1. Sources: `trials` GA runs of Table 2 in SimpleSoccer, each exactly the `initial` preset's trial of
   that number (same settings, same seed); each keeps its best rulebase and its last population
   (transfer/source-N.json, so a resumed study does not run them again).
2. Players: each source's best plays `STARTS` games in SimpleSoccer and `STARTS` trials on rcssserver
   (transfer/players.csv): goals, kicks, ticks and each game's own fitness, per start.
3. Seeding: on rcssserver, GA runs of Table 2 whose generation 0 is a source's last population
   ("seeded from SimpleSoccer"), against runs from random populations ("random initial population"),
   at equal rcssserver evaluations. The random runs are the `robocup` preset's trials of the same numbers
   (same settings, same seeds): run into the robocup experiment's folder, the study reuses them.

Outputs beside the folder's own: transfer-statistics.csv (the GA runs of part 3, as statistics.csv),
figures/transfer-*.png, transfer.md and transfer.html (measured figures, the tests named, the verdicts).
"""

from __future__ import annotations

import csv
import json
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np
from matplotlib.figure import Figure as MatplotlibFigure
from scipy import stats

from soccer_lab.app.experiment.figures import DPI, FIGURES_FOLDER, SIZE_INCHES, Figure, write_figures
from soccer_lab.app.experiment.presets import (CHAPTER_GENERATIONS, CHAPTER_POPULATION, TRANSFER,
                                               TRANSFER_TRIALS as DEFAULT_TRIALS)
from soccer_lab.app.experiment.presets import ExperimentOptions, Preset, Setting, preset, trial_seed
from soccer_lab.app.experiment.report import _html, _markdown
from soccer_lab.app.experiment.runner import (Progress, RunClock, TrialFolder, TrialResult, TrialSpec, best_record,
                                              prepare_folder, run_trial)
from soccer_lab.app.experiment.table import ALGORITHM, PRESET, SEED, SETTING, TRIAL, StatisticsTable
from soccer_lab.app.experiment.verdicts import ALPHA, AGREES, DISAGREES, INCONCLUSIVE, MIN_TRIALS
from soccer_lab.ga.config import SEED_BOUND
from soccer_lab.ga.genes import GENE_DTYPE, GENE_WIDTH
from soccer_lab.soccer.config import SOCCER_VOCABULARY

STARTS = 20  # games (and trials) each source's best plays in each environment
SEEDED_GA = "ga-seeded"  # the algorithm of a run whose generation 0 is a SimpleSoccer population
SEEDED, RANDOM_START = "seeded from SimpleSoccer", "random initial population"
FOLDER = "transfer"
PLAYERS_FILE = "players.csv"
STATISTICS_FILE = "transfer-statistics.csv"
REPORT_MD, REPORT_HTML = "transfer.md", "transfer.html"
SIMPLE, RCSS = "SimpleSoccer", "rcssserver"
PLAYER_COLUMNS = ("source", "environment", "start", "seed", "goals", "kicks", "ticks", "fitness")
STARTS_KEY = 0x7472616E  # "tran": the players' starts come from their own branch of the experiment seed
CHAPTER_6_3 = ("While the difference in the results of the experiments in the RoboCupSoccer and SimpleSoccer "
               "environments indicate that SimpleSoccer is not an exact model of RoboCupSoccer (as indeed it was not "
               "intended to be), there is a broad similarity in the results which is sufficient to indicate that the "
               "SimpleSoccer environment is a good simplified model of the RoboCupSoccer environment.")
THESIS_QUESTION = ("Riley's thesis (its abstract) asks whether rules learned in SimpleSoccer transfer to "
                   "RoboCupSoccer, and seeds RoboCup runs with them.")


@dataclass(frozen=True)
class TransferPlan:
    options: ExperimentOptions
    source: Setting  # Table 2 in SimpleSoccer: the initial preset's
    random_start: Setting  # Table 2 on rcssserver: the robocup preset's
    seeded: Setting  # the same, its generation 0 a source's last population
    trials: int

    @property
    def specs(self) -> list[TrialSpec]:
        """The rcssserver GA runs, seeded and random, alternately (so a partial study compares like with like)."""
        game = self.options.game()
        return [TrialSpec(setting, trial, trial_seed(self.options.seed, self.random_start, trial), game)
                for trial in range(self.trials) for setting in (self.seeded, self.random_start)]


def transfer_plan(options: ExperimentOptions) -> TransferPlan:
    source = preset("initial", options).settings[0]
    random_start = preset("robocup", options).settings[0]
    seeded = replace(random_start, label=SEEDED, algorithm=SEEDED_GA)
    return TransferPlan(options, source, replace(random_start, label=RANDOM_START), seeded,
                        options.trials or DEFAULT_TRIALS)


def start_seeds(options: ExperimentOptions, source: int) -> list[int]:
    """The STARTS seeds source `source`'s best plays from, the same in both environments."""
    state = np.random.SeedSequence(options.seed, spawn_key=[STARTS_KEY, source]).generate_state(STARTS, np.uint64)
    return [int(value) % SEED_BOUND for value in state]


# ---- 1. sources ----------------------------------------------------------------------------------------
class Sources:
    """transfer/source-N.json: a SimpleSoccer trial's statistics, best rulebase and last population."""

    def __init__(self, folder: Path, plan: TransferPlan):
        self.folder = folder / FOLDER
        self.folder.mkdir(parents=True, exist_ok=True)
        self.plan = plan

    def path(self, trial: int) -> Path:
        return self.folder / f"source-{trial}.json"

    def get(self, trial: int) -> dict[str, Any]:
        """The source, run now (in this process: a few seconds) unless it was kept."""
        path = self.path(trial)
        if not path.is_file():
            from soccer_lab.ga.algorithms import evolve
            from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator

            config = self.plan.source.ga.model_copy(
                update={"seed": trial_seed(self.plan.options.seed, self.plan.source, trial)})
            result = evolve(config, SimpleSoccerEvaluator(self.plan.options.game(), SOCCER_VOCABULARY), SOCCER_VOCABULARY)
            document = {"trial": trial, "seed": config.seed, "statistics": [s.to_dict() for s in result.history],
                        "best": result.best.chromosome.tolist(), "best_fitness": result.best.fitness,
                        "population": [individual.chromosome.tolist() for individual in result.population]}
            temporary = path.with_suffix(".tmp")
            temporary.write_text(json.dumps(document))
            temporary.replace(path)
        return json.loads(path.read_text())

    def best(self, trial: int):
        from soccer_lab.ga.codec import ChromosomeCodec

        return ChromosomeCodec(SOCCER_VOCABULARY).decode(_chromosome(self.get(trial)["best"]))

    def population(self, trial: int) -> list[np.ndarray]:
        return [_chromosome(genes) for genes in self.get(trial)["population"]]


def _chromosome(genes: list[list[int]]) -> np.ndarray:
    """A chromosome as ga keeps it (one row per gene), from its JSON rows."""
    return np.array(genes, dtype=GENE_DTYPE).reshape(-1, GENE_WIDTH)


# ---- 2. players ----------------------------------------------------------------------------------------
def play_players(plan: TransferPlan, sources: Sources, evaluator: Callable[[], Any], path: Path) -> list[dict]:
    """Each source's best from STARTS starts in both environments; rows kept in players.csv, whose finished
    sources are not played again."""
    from soccer_lab.soccer.engine import play_games

    rows = _read_rows(path)
    done = {int(row["source"]) for row in rows}
    for source in range(plan.trials):
        if source in done:
            continue
        player, seeds = sources.best(source), start_seeds(plan.options, source)
        simple = play_games([player] * STARTS, seeds, plan.options.game())
        on_server = evaluator()([player] * STARTS, seeds)
        for environment, results in ((SIMPLE, simple), (RCSS, on_server)):
            rows += [{"source": source, "environment": environment, "start": start, "seed": seed, "goals": r.goals,
                      "kicks": r.kicks, "ticks": r.ticks, "fitness": r.fitness}
                     for start, (seed, r) in enumerate(zip(seeds, results))]
        _write_rows(path, rows)
    return rows


def _read_rows(path: Path) -> list[dict]:
    if not path.is_file():
        return []
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


def _write_rows(path: Path, rows: list[dict]) -> None:
    temporary = path.with_suffix(".tmp")
    with temporary.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=PLAYER_COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    temporary.replace(path)


# ---- 3. seeded and random rcssserver runs ----------------------------------------------------------------
def run_transfer_trial(spec: TrialSpec, evaluate: Any, sources: Sources) -> TrialResult:
    """A random-start run as the robocup preset's; a seeded one from its source's last population (and from its
    checkpoint when there is one). Its best is re-played on the spec's replays, on the same servers."""
    if spec.setting.algorithm != SEEDED_GA or (spec.checkpoint is not None and spec.checkpoint.is_file()):
        return run_trial(spec, evaluate)  # a checkpoint holds all a seeded run needs to go on
    from soccer_lab.ga.algorithms import evolve

    result = evolve(spec.config, evaluate, SOCCER_VOCABULARY, checkpoint=spec.checkpoint,
                    initial_population=sources.population(spec.trial))
    rows = [stats.to_dict() for stats in result.history]
    return TrialResult(rows, best_record(result, rows, evaluate, spec.replay_seeds()))


@dataclass(frozen=True)
class TransferOutcome:
    folder: Path
    plan: TransferPlan
    table: StatisticsTable
    players: list[dict]
    findings: list[tuple[str, str, str, str]]  # claim, measured, verdict, test
    figures: list[Figure]
    ran: int
    seconds: float


def run_transfer(options: ExperimentOptions, folder: Path, executor: Any,
                 progress: Progress | None = None) -> TransferOutcome:
    """The whole study into `folder` (resuming what is there); `executor` plays rcssserver trials (an
    RcssExecutor, local or on a Ray cluster). The invocation's wall time and load go to runs.jsonl."""
    clock = RunClock()
    plan = transfer_plan(options)
    prepare_folder(folder, options.identity(on_servers=True))
    sources = Sources(folder, plan)
    trials = TrialFolder(folder)
    with executor:
        for source in range(plan.trials):
            sources.get(source)
        players = play_players(plan, sources, lambda: executor.evaluator(options.trial()),
                               folder / FOLDER / PLAYERS_FILE)
        pending = [replace(spec, checkpoint=trials.checkpoint(spec)) for spec in plan.specs if not trials.finished(spec)]
        total = sum(spec.setting.evaluations for spec in plan.specs)
        completed = total - sum(spec.setting.evaluations for spec in pending)
        if progress is not None:
            progress.update(completed, total, skipped=len(plan.specs) - len(pending))
        for spec, result in executor.map_unordered(lambda spec, evaluate: run_transfer_trial(spec, evaluate, sources),
                                                   pending):
            trials.write(spec, result)
            completed += spec.setting.evaluations
            if progress is not None:
                progress.update(completed, total, skipped=len(plan.specs) - len(pending))
    table = _assemble(plan, trials, folder)
    outcome = write_transfer_report(plan, table, players, folder)
    seconds = clock.log(folder, TRANSFER, options, [options.seed], len(pending), len(plan.specs) - len(pending))
    return replace(outcome, ran=len(pending), seconds=seconds)


def _assemble(plan: TransferPlan, trials: TrialFolder, folder: Path) -> StatisticsTable:
    rows = []
    for spec in plan.specs:
        keys = {PRESET: TRANSFER, SETTING: spec.setting.label, TRIAL: spec.trial, SEED: spec.seed,
                ALGORITHM: spec.setting.algorithm}
        rows.extend({**keys, **row} for row in trials.read(spec))
    table = StatisticsTable(rows)
    (folder / STATISTICS_FILE).write_text(table.to_csv())
    return StatisticsTable.read(folder / STATISTICS_FILE)


# ---- findings, figures, report ---------------------------------------------------------------------------
def player_means(players: Sequence[dict], column: str) -> dict[str, np.ndarray]:
    """Per environment, each source's mean of `column` over its starts (sources in order)."""
    means = {}
    for environment in (SIMPLE, RCSS):
        by_source: dict[int, list[float]] = {}
        for row in players:
            if row["environment"] == environment:
                by_source.setdefault(int(row["source"]), []).append(float(row[column]))
        means[environment] = np.array([np.mean(by_source[s]) for s in sorted(by_source)])
    return means


def assess(plan: TransferPlan, table: StatisticsTable, players: Sequence[dict]) -> list[tuple[str, str, str, str]]:
    """(claim, measured, verdict, test) for each question the study answers."""
    findings = []
    goals = player_means(players, "goals")
    simple, server = goals[SIMPLE], goals[RCSS]
    scoring = float(np.mean(server > 0)) if len(server) else 0.0
    measured = (f"mean goals per game, median over {len(simple)} players: SimpleSoccer {np.median(simple):.2f}, "
                f"rcssserver {np.median(server):.2f}; {scoring:.0%} of the players score on rcssserver")
    if len(simple) < MIN_TRIALS:
        findings.append(("SimpleSoccer's best players score on rcssserver as they do in SimpleSoccer.", measured,
                         INCONCLUSIVE, f"too few players ({len(simple)}; the test needs {MIN_TRIALS})"))
    else:
        difference = simple - server
        p = 1.0 if np.all(difference == 0) else float(stats.wilcoxon(difference, alternative="greater").pvalue)
        verdict = DISAGREES if p < ALPHA else AGREES
        findings.append(("SimpleSoccer's best players score on rcssserver as they do in SimpleSoccer.", measured,
                         verdict, f"Wilcoxon signed-rank, one-sided (fewer goals on rcssserver), paired by player, "
                                  f"p = {p:.3g}"))
        if np.ptp(simple) == 0 or np.ptp(server) == 0:
            rho, p = 0.0, 1.0
        else:
            rho, p = (float(v) for v in stats.spearmanr(simple, server))
        findings.append(("A better SimpleSoccer player is a better rcssserver player (the ranking carries over).",
                         f"Spearman rho = {rho:+.2f} between the players' mean goals in the two environments",
                         AGREES if rho > 0 and p < ALPHA else DISAGREES if rho <= 0 else INCONCLUSIVE,
                         f"Spearman rank correlation, p = {p:.3g}"))
    settings = table.settings(TRANSFER)
    if SEEDED in settings and RANDOM_START in settings:
        for what, values, column in (("final average fitness", "final", "mean"), ("run's best fitness", "best", "best")):
            seeded = table.final(TRANSFER, SEEDED, column) if values == "final" else table.best_so_far(TRANSFER, SEEDED)
            random = (table.final(TRANSFER, RANDOM_START, column) if values == "final"
                      else table.best_so_far(TRANSFER, RANDOM_START))
            measured = (f"{what}, median over runs: seeded {np.median(seeded):.3f} ({len(seeded)} runs), random "
                        f"{np.median(random):.3f} ({len(random)} runs)")
            claim = f"RoboCup runs seeded with a SimpleSoccer population reach a better {what} at equal evaluations."
            if min(len(seeded), len(random)) < MIN_TRIALS:
                findings.append((claim, measured, INCONCLUSIVE, f"too few runs (the test needs {MIN_TRIALS} per arm)"))
                continue
            pooled = np.concatenate([seeded, random])
            p = 1.0 if np.all(pooled == pooled[0]) else float(stats.mannwhitneyu(seeded, random,
                                                                                 alternative="less").pvalue)
            verdict = AGREES if p < ALPHA else DISAGREES if np.median(seeded) >= np.median(random) else INCONCLUSIVE
            findings.append((claim, measured, verdict, f"Mann-Whitney U, one-sided (seeded lower), p = {p:.3g}"))
    return findings


def write_transfer_report(plan: TransferPlan, table: StatisticsTable, players: list[dict],
                          folder: Path) -> TransferOutcome:
    findings = assess(plan, table, players)
    study = Preset(TRANSFER, "RoboCup runs seeded from SimpleSoccer against random starts", "start",
                   (plan.seeded, plan.random_start), plan.trials, False, ("mean_fitness", "best_fitness"))
    figures = [_players_figure(players, folder)]
    if table.rows:
        figures += write_figures(table, study, folder)
    blocks = _blocks(plan, table, players, findings, figures)
    (folder / REPORT_MD).write_text(_markdown(blocks))
    (folder / REPORT_HTML).write_text(_html(blocks, folder))
    return TransferOutcome(folder, plan, table, players, findings, figures, 0, 0.0)


def _players_figure(players: Sequence[dict], folder: Path) -> Figure:
    goals = player_means(players, "goals")
    figure = MatplotlibFigure(figsize=SIZE_INCHES, dpi=DPI, layout="constrained")
    axes = figure.subplots()
    axes.scatter(goals[SIMPLE], goals[RCSS], s=24)
    # players that score the same in both draw one point: it says how many (often several at 0, 0)
    for (x, y), count in Counter(zip(goals[SIMPLE], goals[RCSS])).items():
        if count > 1:
            axes.annotate(f"×{count}", (x, y), xytext=(5, 5), textcoords="offset points", fontsize=8)
    top = max([1.0, *goals[SIMPLE], *goals[RCSS]]) * 1.05
    axes.plot([0, top], [0, top], color="grey", linewidth=0.8, linestyle="--", label="the same in both")
    axes.set_xlim(-0.03 * top, top)  # a point at 0 shown whole, not cut by the axes
    axes.set_ylim(-0.03 * top, top)
    axes.set_xlabel(f"mean goals per game in SimpleSoccer ({STARTS} starts)")
    axes.set_ylabel(f"mean goals per trial on rcssserver ({STARTS} starts)")
    axes.legend(fontsize=8)
    axes.grid(alpha=0.3)
    caption = "The best player of each SimpleSoccer trial, in SimpleSoccer and on rcssserver"
    axes.set_title(caption, fontsize=10)
    relative = Path(FIGURES_FOLDER) / f"{TRANSFER}-players.png"
    (folder / FIGURES_FOLDER).mkdir(parents=True, exist_ok=True)
    figure.savefig(folder / relative, metadata={"Software": None})
    return Figure(relative, caption)


def _size(plan: TransferPlan) -> str:
    """" at population P x G generations" when the study is not at Table 2's own size."""
    ga = plan.random_start.ga
    if (ga.population_size, ga.max_generations) == (CHAPTER_POPULATION, CHAPTER_GENERATIONS):
        return ""
    return f" at population {ga.population_size} x {ga.max_generations} generations"


def _blocks(plan: TransferPlan, table: StatisticsTable, players: list[dict], findings: list, figures: list) -> list:
    blocks: list = [("h1", "soccer-lab: does SimpleSoccer training carry over to rcssserver?"),
                    ("p", f"The chapter, 6.3: \"{CHAPTER_6_3}\""), ("p", THESIS_QUESTION),
                    ("p", f"Sources: {plan.trials} GA runs of Table 2{_size(plan)} in SimpleSoccer (the initial "
                          f"preset's trials 0-{plan.trials - 1}). Each run's best player played {STARTS} games in "
                          f"SimpleSoccer and {STARTS} trials on rcssserver from the same seeds; then {plan.trials} GA "
                          "runs of the same on rcssserver started from a source's last population, against as many "
                          "from random populations (the robocup preset's trials), at equal rcssserver evaluations.")]
    blocks.append(("h2", "Players"))
    rows = []
    for source in sorted({int(r["source"]) for r in players}):
        mine = [r for r in players if int(r["source"]) == source]
        cells = [str(source)]
        for environment in (SIMPLE, RCSS):
            games = [r for r in mine if r["environment"] == environment]
            goals = [float(r["goals"]) for r in games]
            cells += [f"{np.mean(goals):.2f}", f"{np.mean([g > 0 for g in goals]):.0%}",
                      f"{np.mean([float(r['kicks']) for r in games]):.1f}"]
        rows.append(cells)
    blocks.append(("table", ["source", "SimpleSoccer goals (mean)", "SimpleSoccer games scoring",
                             "SimpleSoccer kicks (mean)", "rcssserver goals (mean)", "rcssserver trials scoring",
                             "rcssserver kicks (mean)"], rows))
    blocks.extend(("figure", f.path, f.caption) for f in figures if f.path.name.endswith("players.png"))
    if table.rows:
        blocks.append(("h2", "Seeded against random RoboCup runs"))
        rows = []
        for setting in table.settings(TRANSFER):
            rows.append([setting, str(len(table.trials(TRANSFER, setting))),
                         f"{np.median(table.curves(TRANSFER, setting, 'mean')[:, 0]):.3f}",
                         f"{np.median(table.final(TRANSFER, setting, 'mean')):.3f}",
                         f"{np.median(table.best_so_far(TRANSFER, setting)):.3f}"])
        blocks.append(("table", ["start", "runs", "generation 0 average (median)", "final average (median)",
                                 "run's best (median)"], rows))
        blocks.extend(("figure", f.path, f.caption) for f in figures if not f.path.name.endswith("players.png"))
    blocks.append(("h2", "Findings"))
    blocks.append(("table", ["claim", "measured here", "verdict", "test"],
                   [[c, m, v.upper() if v == DISAGREES else v, t] for c, m, v, t in findings]))
    return blocks
