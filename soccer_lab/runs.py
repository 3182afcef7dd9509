"""Evolution runs from Python, as `soccer-lab evolve`, `random-search` and `lineage` do: a run plays
SimpleSoccer games and writes the same run folder (run.json, statistics.csv, best.rules, best.json,
lineage.jsonl, checkpoint, run.rrd), which `open_run` reads back and `soccer-lab evolve --resume` continues."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from soccer_lab.fuzzy.rule import Rulebase

if TYPE_CHECKING:  # the run's machinery (numpy, numba, rerun) is imported when a run starts or is read
    from soccer_lab.app.lineage.family_tree import FamilyTreeView
    from soccer_lab.app.runs.run import RunSettings
    from soccer_lab.fuzzy.vocabulary import Vocabulary

RENAMED = {"generations": "max_generations"}  # keyword -> GAConfig field, as the CLI names its options
OnGeneration = Callable[[dict[str, Any]], None]


@dataclass(frozen=True)
class Best:
    """The run's best player: the lowest running mean fitness the run saw (lower is better), over its
    `evaluations`, with the goals of its latest game."""

    rules: Rulebase = field(repr=False)  # format_rules(best.rules) prints them
    fitness: float
    goals: int
    evaluations: int


@dataclass(frozen=True)
class RunRecord:
    """A run folder read back: its `settings` (soccer_lab.app.runs.run.RunSettings: `.ga`, `.game`, `.algorithm`), one dict
    of statistics per finished generation (soccer_lab.ga.statistics.GenerationStats's fields: best, mean, worst,
    goals_0, ..., evaluations, wall_time), and its `best` (None before the first generation finished)."""

    folder: Path
    settings: "RunSettings" = field(repr=False)
    statistics: list[dict[str, Any]] = field(repr=False)
    best: Best | None
    vocabulary: "Vocabulary" = field(repr=False)

    @property
    def generations(self) -> int:
        """Generations finished."""
        return len(self.statistics)

    def column(self, name: str) -> list[Any]:
        """One statistic over the generations, e.g. `record.column("mean")`."""
        return [row[name] for row in self.statistics]


def evolve(population_size: int | None = None, generations: int | None = None, seed: int | None = None, *,
           out: str | PathLike | None = None, on_generation: OnGeneration | None = None,
           **options: Any) -> RunRecord:
    """Evolve a rulebase with the messy-coded GA, as `soccer-lab evolve` does: the same options and seed
    give the same run, bit for bit (whatever `workers`). Unset options keep the chapter's Table 2 defaults.
    `options`: any other GA option (max_length, crossover, selection, mutation_rate, target_fitness,
    workers, ...; soccer_lab.ga.config.GAConfig) or game option (max_ticks, skills, fitness, games_per_evaluation, ...;
    soccer_lab.soccer.config.GameConfig), or `opponent` (a Rulebase or a rulebase file: evolve against that fixed
    player, each evaluation a match against it; docs/research/matches.md), or `coevolve` (True, or a dict with
    hall_size and hall_sample: co-evolve against a hall of fame of earlier bests founded by `opponent` or the
    built-in demo). `out`: the run folder (None: a new temporary folder, in `.folder`).
    `on_generation(statistics)` hears each finished generation's statistics. Bad options raise a
    ValueError (TypeError for a name no option has); a folder already holding a run, RunFolderError.

    >>> import soccer_lab as sl
    >>> run = sl.evolve(population_size=6, generations=2, seed=1, max_ticks=200, workers=1)
    >>> run.generations, [row["generation"] for row in run.statistics]
    (2, [0, 1])
    >>> run.best.fitness == min(run.column("best"))
    True
    >>> sorted(p.name for p in run.folder.iterdir())[:3]
    ['best.json', 'best.rules', 'checkpoint']
    """
    from soccer_lab.ga.state import GA

    return _run(GA, out, on_generation, population_size=population_size, generations=generations, seed=seed,
                **options)


def random_search(population_size: int | None = None, generations: int | None = None, seed: int | None = None, *,
                  out: str | PathLike | None = None, on_generation: OnGeneration | None = None,
                  **options: Any) -> RunRecord:
    """The baseline, as `soccer-lab random-search`: the same evaluations (population x generations) spent on
    fresh random rulebases, with the same statistics and run folder as `evolve` (whose options it takes).

    >>> import soccer_lab as sl
    >>> run = sl.random_search(population_size=6, generations=2, seed=1, max_ticks=200, workers=1)
    >>> run.settings.algorithm, run.generations
    ('random-search', 2)
    """
    from soccer_lab.ga.state import RANDOM_SEARCH

    return _run(RANDOM_SEARCH, out, on_generation, population_size=population_size, generations=generations,
                seed=seed, **options)


def _run(algorithm: str, out: str | PathLike | None, on_generation: OnGeneration | None,
         **options: Any) -> RunRecord:
    from soccer_lab.app.runs.run import Run

    settings = _settings(algorithm, {name: value for name, value in options.items() if value is not None})
    folder = Path(out) if out is not None else Path(tempfile.mkdtemp(prefix="soccer-lab-run-"))
    _play(Run.create(settings, folder), on_generation)
    return open_run(folder)


def resume(folder: str | PathLike, *, on_generation: OnGeneration | None = None) -> RunRecord:
    """Continue a run that was stopped (Ctrl-C, a killed kernel, an exception from `on_generation`) from its
    folder's checkpoint, with its own settings, as `soccer-lab evolve --resume` does: it finishes exactly as
    the uninterrupted run would. A finished run is returned as it is.

    >>> import soccer_lab as sl, tempfile
    >>> folder = tempfile.mkdtemp()
    >>> def stop_after_first(statistics):
    ...     raise KeyboardInterrupt
    >>> try:
    ...     sl.evolve(population_size=4, generations=3, seed=2, max_ticks=100, workers=1, out=folder,
    ...               on_generation=stop_after_first)
    ... except KeyboardInterrupt:
    ...     pass
    >>> sl.open_run(folder).generations
    1
    >>> sl.resume(folder).generations
    3
    """
    from soccer_lab.app.runs.run import Run

    run = Run.open(folder)
    if not _finished(run.saved_state()):
        run.refuse_if_played_elsewhere()
        _play(run, on_generation)
    return open_run(folder)


def _finished(state: Any) -> bool:
    """The run reached its target or its last generation (soccer_lab.ga.algorithms stops there too)."""
    config, history = state.config, state.history
    return bool(history) and (history[-1].best <= config.target_fitness or len(history) >= config.max_generations)


def _play(run: Any, on_generation: OnGeneration | None) -> None:
    callbacks = [] if on_generation is None else [lambda stats, population: on_generation(stats.to_dict())]
    with run.evaluator() as evaluate:
        run.play(evaluate, callbacks=callbacks)


def _settings(algorithm: str, options: dict[str, Any]) -> "RunSettings":
    """RunSettings from keyword options, each to the GA's or the game's settings by its name; the workers
    default to every core, as the CLI's."""
    from soccer_lab.app.runs.environments import default_workers
    from soccer_lab.app.runs.run import RunSettings
    from soccer_lab.ga.config import GAConfig
    from soccer_lab.soccer.config import GameConfig

    opponent = options.pop("opponent", None)
    coevolve = options.pop("coevolve", None)
    coevolve = {} if coevolve is True else coevolve or None  # True: the hall of fame's defaults
    ga, game, unknown = {}, {}, []
    for name, value in options.items():
        field = RENAMED.get(name, name)
        if field in GAConfig.model_fields and name not in RENAMED.values():
            ga[field] = value
        elif name in GameConfig.model_fields:
            game[name] = value
        else:
            unknown.append(name)
    if unknown:
        raise TypeError(f"unknown option{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}: expected a GA "
                        f"option ({', '.join(_ga_names())}) or a game option ({', '.join(GameConfig.model_fields)})")
    ga.setdefault("workers", default_workers())
    return RunSettings.build(ga=ga, game=game, algorithm=algorithm, opponent=_opponent_text(opponent),
                             coevolve=coevolve)


def _opponent_text(opponent: Any) -> str | None:
    """The `opponent` option (a Rulebase, or the path of a rulebase file) as rule text, as run.json keeps it."""
    if opponent is None:
        return None
    from soccer_lab.fuzzy.printer import format_rulebase
    from soccer_lab.rules import rulebase_of
    from soccer_lab.soccer.config import SOCCER_VOCABULARY

    return format_rulebase(rulebase_of(opponent), SOCCER_VOCABULARY)


def _ga_names() -> list[str]:
    from soccer_lab.ga.config import GAConfig

    fields = {field: name for name, field in RENAMED.items()}
    return [fields.get(field, field) for field in GAConfig.model_fields]


def open_run(folder: str | PathLike) -> RunRecord:
    """The run a folder holds (what `evolve` or `soccer-lab evolve --out` wrote, or the app's runs/<id>):
    its settings, per-generation statistics and best player, read from its run.json and checkpoint.
    soccer_lab.app.runs.outputs.RunFolderError (a ValueError) for a folder holding no run or no finished generation.

    >>> import soccer_lab as sl
    >>> run = sl.evolve(population_size=4, generations=1, seed=2, max_ticks=100, workers=1)
    >>> again = sl.open_run(run.folder)
    >>> again.best == run.best, again.settings.ga.population_size
    (True, 4)
    """
    from soccer_lab.app.runs.run import Run
    from soccer_lab.ga.checkpoint import CheckpointError
    from soccer_lab.ga.codec import ChromosomeCodec

    run = Run.open(folder)
    try:
        state = run.saved_state()
    except CheckpointError as exc:
        from soccer_lab.app.runs.outputs import RunFolderError

        raise RunFolderError(f"{run.folder.checkpoint}: {exc}") from None
    best = None
    if state.best is not None:
        rules = ChromosomeCodec(state.vocabulary).decode(state.best.chromosome)
        best = Best(rules, state.best.fitness, state.best.goals, state.best.evaluations)
    return RunRecord(run.folder.path, run.settings, [stats.to_dict() for stats in state.history], best,
                     state.vocabulary)


# ---- lineage ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class FamilyTree:
    """A player's family tree: `text` as `soccer-lab lineage` prints it, `view` its parts
    (soccer_lab.app.lineage.family_tree.FamilyTreeView: the ancestors row by row, each rule with the ancestor it came from);
    `svg()` and `dot()` draw it as `--svg` and `--dot` do."""

    view: "FamilyTreeView"
    quality: str  # the player re-played on the common fresh starts, in one line

    @property
    def text(self) -> str:
        from soccer_lab.app.lineage.drawing import tree_text

        return tree_text(self.view) + self.quality + "\n"

    def svg(self, with_rules: bool = True) -> str:
        from soccer_lab.app.lineage.drawing import tree_svg

        return tree_svg(self.view, with_rules=with_rules)

    def dot(self) -> str:
        from soccer_lab.app.lineage.drawing import tree_dot

        return tree_dot(self.view)

    def __str__(self) -> str:
        return self.text


def lineage(run: RunRecord | str | PathLike, index: int | None = None, *, generation: int | None = None,
            generations: int | None = None) -> FamilyTree:
    """A player's family tree from a run folder's lineage records, as `soccer-lab lineage RUN_DIR`: by default
    the run's best so far; `generation` G for that generation's best, with `index` I for its player I;
    `generations` back (default: to generation 0). soccer_lab.ga.lineage.LineageError (a LookupError) for a place the
    run does not have, or a folder with no lineage records.

    >>> import soccer_lab as sl
    >>> run = sl.evolve(population_size=6, generations=2, seed=1, max_ticks=200, workers=1)
    >>> tree = sl.lineage(run, generation=1, index=0)
    >>> tree.text.splitlines()[0].startswith("Generation 1, individual #0")
    True
    """
    from soccer_lab.app.lineage.family_tree import RunLineage, player_quality_line
    from soccer_lab.ga.lineage import LineageError

    if index is not None and generation is None:
        raise LineageError("an individual's index needs its generation")
    folder = run.folder if isinstance(run, RunRecord) else Path(run)
    found = RunLineage.from_folder(folder)
    view = found.family_tree(found.place(generation, index), generations)
    rulebase = view.codec.decode(view.tree.individual.chromosome)
    return FamilyTree(view, player_quality_line(folder, rulebase, view.vocabulary))
