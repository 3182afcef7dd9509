"""The chapter's study (section 6) as presets: which settings each varies, at which size, and how the
options shrink them. `robocup` is the chapter's RoboCup initial trials (6.1): Table 2 on rcssserver,
its trials played on servers (soccer/rcss/); every other preset plays SimpleSoccer games, and `all`
is those.

Control parameters. Table 2 (roulette selection, one-point crossover, 10% mutation rate, population
200, 25 generations, max length 64) is the control for `initial`, `max-length`, `population` and
`selection`. The chapter says (section 4) that "elitist selection was used in the remainder of the
SimpleSoccer trials" after the selection comparison; section 6.4 presents crossover, mutation,
maximum generations and GA against random search after it, so those presets use elitist selection
(5% retained). Every trial runs all its generations: the chapter's target fitness (0.05) "did not
occur", but our simulator does reach 10 goals, and curves averaged over trials need equal lengths,
so experiments switch early stopping off (`EXPERIMENT_TARGET_FITNESS`).

A setting is identified by its full configuration, not by its preset: the same configuration in two
presets (Table 2 is the control of four of them) is one set of trials, run once and shared.

Beyond the chapter (`all-plus` adds them to `all`): the experiments its text leaves for future work.
`uniform-crossover` (6.4.4) adds a rule-wise uniform crossover (ga/crossover.py) to the crossover
comparison; `rule-pressure` (6.4.1, 6.4.5) follows rules per chromosome and premises per rule for 100
generations at maximum lengths 25, 64 and 128, to tell "more rules" from "shorter rules" and show what
happens where rules reach their bound (half the chromosome length); `games-per-evaluation` (5.2) scores
each evaluation on 1 or on 5 games at equal games played (the 1-game run gets 5x the generations);
`restarts` (6.4.4, after Luke) sets 4 independent runs of 25 generations against one of 100 at equal
evaluations. The chapter's later control (elitist selection) is theirs, but for `games-per-evaluation`,
whose question the chapter raised about its Table 2 trials.

`matches` (docs/research/matches.md; the chapter's background: Luke's co-evolved teams) plays matches: Table 2 evolved
alone (the `initial` preset's trials), Table 2 co-evolved against a hall of fame of earlier bests founded by
the built-in demo (COEVOLUTION: each evaluation a match against each of 3 members drawn from the last 10
distinct bests and the demo), and the same seeing the opponent (the opponent vocabulary). Its questions and
their tests are app/experiment/matches.py's.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from pydantic import BaseModel, ConfigDict, Field

from soccer_lab.ga.config import MAX_POPULATION, SEED_BOUND, CoevolutionConfig, GAConfig, RouletteWeighting
from soccer_lab.ga.state import GA, RANDOM_SEARCH
from soccer_lab.soccer.config import GameConfig, SkillSet

if TYPE_CHECKING:  # soccer_lab.soccer.rcss.trial loads the player's compiled skills: imported when robocup runs
    from soccer_lab.soccer.rcss.trial import TrialConfig

ALL = "all"
ALL_PLUS = "all-plus"
ROBOCUP = "robocup"
TRANSFER = "transfer"  # app/experiment/transfer.py: named here, where `experiment --help` reads it without numpy
EXPERIMENT_TARGET_FITNESS = 0.0  # fitness is always > 0, so no trial stops early (see above)

TABLE_2 = GAConfig()  # the chapter's control values are GAConfig's defaults
CHAPTER_POPULATION = TABLE_2.population_size
CHAPTER_GENERATIONS = TABLE_2.max_generations
LATER_CONTROL = {"selection": "elitist"}  # section 4: used after the selection comparison

DEFAULT_TRIALS = 10
TRANSFER_TRIALS = 10  # a seeded rcssserver run of Table 2 takes about 20 minutes on a 2-core machine
INITIAL_TRIALS = 20
MAX_LENGTHS = (25, 50, 64, 75, 100)
POPULATION_SIZES = (50, 100, 200, 500)
POPULATION_EVALUATIONS = 10_000
SELECTIONS = ("roulette", "tournament", "elitist")
CROSSOVERS = ("one-point", "two-point")
MUTATION_RATES = (0.05, 0.10, 0.15, 0.20, 0.25)
LONG_GENERATIONS = 100
RANDOM_SEARCH_POPULATION = 500  # the chapter: 40 "generations" of 500 = the GA's 20,000 evaluations
BEYOND_CROSSOVERS = ("one-point", "two-point", "uniform")
RULE_PRESSURE_LENGTHS = (25, 64, 128)  # the chapter's smallest maximum (rules reach their bound), Table 2's, twice it
GAMES_PER_EVALUATION = (1, 5)  # the chapter, 5.2: "the average of five games"
RESTARTS = 4  # runs of Table 2's 25 generations, against one of LONG_GENERATIONS (Luke's "many shorter experiments")
MATCHES = "matches"
COEVOLUTION = CoevolutionConfig(hall_size=10, hall_sample=3)  # the matches preset's hall of fame
ALONE, COEVOLVED, SEEING = "alone", "co-evolved", "co-evolved, seeing the opponent"  # its settings
RCSS_TRIAL = "rcss_trial"  # a manifest's rcssserver trial length and noise (ExperimentOptions.identity)
DEFAULT_REPLAYS = 100  # fresh starts each trial's best is re-played on: its true quality


class ExperimentOptions(BaseModel):
    """What the command line may change. Population and generations shrink (or grow) every setting in
    proportion to Table 2's 200 and 25, so the study keeps its shape: `population` keeps equal
    evaluations per setting, `long` keeps 4x the generations, `random` keeps equal evaluations."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    trials: int | None = Field(None, ge=1, le=10_000, description="trials per setting (default: the chapter's)")
    population: int = Field(CHAPTER_POPULATION, ge=2, le=MAX_POPULATION, description="Table 2's population size")
    generations: int = Field(CHAPTER_GENERATIONS, ge=1, le=100_000, description="Table 2's generations")
    max_ticks: int = Field(GameConfig().max_ticks, ge=1, le=1_000_000, description="ticks a game lasts at most")
    seed: int = Field(0, ge=0, lt=SEED_BOUND, description="experiment seed: every trial's seed derives from it")
    # The choices the chapter leaves open, for every setting of the study (defaults: GameConfig's, GAConfig's).
    skills: SkillSet = Field(GameConfig.model_fields["skills"].default, description="the skill set (soccer/skills.py)")
    noise: bool = Field(GameConfig.model_fields["noise"].default, description="rcssserver-like movement noise")
    count_touches: bool = Field(GameConfig.model_fields["count_touches"].default,
                                description="every tick the player's body pushes the ball counts as a kick")
    roulette_weighting: RouletteWeighting = Field(GAConfig.model_fields["roulette_weighting"].default,
                                                  description="roulette weight: 1 - fitness or 1 / fitness")
    replays: int = Field(DEFAULT_REPLAYS, ge=1, le=10_000,
                         description="fresh starts each trial's best is re-played on (its true quality)")

    @property
    def population_scale(self) -> float:
        return self.population / CHAPTER_POPULATION

    @property
    def generation_scale(self) -> float:
        return self.generations / CHAPTER_GENERATIONS

    def scaled_population(self, chapter_size: int) -> int:
        return max(2, round(chapter_size * self.population_scale))

    def scaled_generations(self, chapter_generations: int) -> int:
        return max(1, round(chapter_generations * self.generation_scale))

    def game(self) -> GameConfig:
        return GameConfig(max_ticks=self.max_ticks, skills=self.skills, noise=self.noise,
                          count_touches=self.count_touches)

    def trial(self) -> TrialConfig:
        """The rcssserver trials: the chapter's (1200 cycles, the server's noise) unless max_ticks or noise was
        given, with the skill set (the server counts the kicks)."""
        from soccer_lab.soccer.rcss.trial import TrialConfig

        given = {name: getattr(self, name) for name in ("max_ticks", "noise") if name in self.model_fields_set}
        return TrialConfig(skills=self.skills, **given)

    def identity(self, on_servers: bool = False) -> dict[str, Any]:
        """What makes two experiment folders' finished trials interchangeable (trials count excluded:
        more trials only add files). On rcssserver (robocup, transfer) also the trials' own game length and
        noise: a max_ticks or noise left unset there means the chapter's RoboCup values, not SimpleSoccer's."""
        identity = self.model_dump(exclude={"trials"})
        if on_servers:
            trial = self.trial()
            identity[RCSS_TRIAL] = {"max_ticks": trial.max_ticks, "noise": trial.noise}
        return identity

    @classmethod
    def from_identity(cls, identity: dict[str, Any]) -> "ExperimentOptions":
        """The options as the command line gave them, from a folder's manifest (`identity`): the values that
        differ from the defaults, and the rcssserver trials' length and noise where they differ from theirs."""
        from soccer_lab.soccer.rcss.trial import TrialConfig

        defaults = cls().model_dump()
        given = {name: value for name, value in identity.items() if name in cls.model_fields
                 and value != defaults.get(name)}
        trial_defaults = TrialConfig().model_dump()
        given |= {name: value for name, value in identity.get(RCSS_TRIAL, {}).items()
                  if value != trial_defaults[name]}
        return cls(**given)

    def size(self, robocup: bool = False) -> RunSize:
        """Table 2's control at this run's size (games: server cycles for robocup)."""
        return RunSize(self.population, self.generations, self.trial().max_ticks if robocup else self.max_ticks)


@dataclass(frozen=True)
class RunSize:
    """The size of a run's Table 2 control: what a shrunk experiment shrinks."""

    population: int
    generations: int
    max_ticks: int  # a game's length (server cycles on rcssserver)

    def shortfalls(self, needed: "RunSize") -> list[str]:
        """What this size lacks against `needed`, e.g. ["population 200 (here 20)"]."""
        return [f"{what} {need} (here {have})"
                for what, have, need in (("population", self.population, needed.population),
                                         ("generations", self.generations, needed.generations),
                                         ("game length", self.max_ticks, needed.max_ticks))
                if have < need]


CHAPTER_SIZE = RunSize(CHAPTER_POPULATION, CHAPTER_GENERATIONS, GameConfig().max_ticks)


@dataclass(frozen=True)
class Setting:
    """One value of the varied parameter: a label for figures and the whole GA configuration."""

    label: str
    algorithm: str  # soccer_lab.ga.state.GA or RANDOM_SEARCH
    ga: GAConfig  # seed 0: each trial gets its own
    trial: TrialConfig | None = None  # rcssserver trials; None: SimpleSoccer games (the options' game)
    games_per_evaluation: int = 1  # SimpleSoccer games averaged into one evaluation
    restarts: int = 1  # independent runs of `ga` in one trial; its best is the best of their bests
    coevolve: CoevolutionConfig | None = None  # co-evolved against a hall of fame founded by the built-in demo
    see_opponent: bool = False  # its players perceive the opponent (the opponent vocabulary)

    @property
    def key(self) -> str:
        """A stable, readable file-name stem identifying the configuration (shared across presets)."""
        # what does not change the evolution is no part of it: the seed (each trial has its own), the workers,
        # and counting behaviours (added after the first studies: their trial files keep their names)
        identity: list[Any] = [self.algorithm, self.ga.model_dump(exclude={"seed", "workers", "behaviour_seeds"})]
        if self.trial is not None:  # its options added since the first studies only when set, as below
            identity.append(self.trial.model_dump(exclude=self.trial.unset_later_options()))
        # only when set, so the chapter's settings keep the keys (and trial files) they always had
        identity += [{"games_per_evaluation": self.games_per_evaluation}] if self.games_per_evaluation != 1 else []
        identity += [{"restarts": self.restarts}] if self.restarts != 1 else []
        identity += [{"coevolve": self.coevolve.model_dump()}] if self.coevolve is not None else []
        identity += [{"see_opponent": True}] if self.see_opponent else []
        digest = hashlib.sha256(json.dumps(identity, sort_keys=True).encode()).hexdigest()
        where = "-rcss" if self.trial is not None else ""
        runs = f"x{self.restarts}" if self.restarts != 1 else ""
        games = f"-k{self.games_per_evaluation}" if self.games_per_evaluation != 1 else ""
        matches = ("-coevolved" + ("-seeing" if self.see_opponent else "")) if self.coevolve is not None else ""
        return (f"{self.algorithm}{where}-p{self.ga.population_size}-g{self.ga.max_generations}{runs}{games}"
                f"{matches}-{digest[:10]}")

    @property
    def evaluations(self) -> int:
        return self.ga.population_size * self.ga.max_generations * self.restarts

    @property
    def games(self) -> int:
        """Games a trial plays in its runs (its best's replays aside): what it costs. A co-evolution evaluation is
        a match (two halves of two players) against each opponent drawn: about four games each."""
        matches = 4 * self.coevolve.hall_sample if self.coevolve is not None else 1
        return self.evaluations * self.games_per_evaluation * matches


@dataclass(frozen=True)
class Preset:
    name: str
    title: str  # what is varied, for figure titles
    varied: str  # the parameter's display name
    settings: tuple[Setting, ...]
    trials: int
    per_trial: bool = False  # the chapter shows each trial's curve (Figs. 11-12, 26-27)
    figures: tuple[str, ...] = field(default=())  # figure kinds (soccer_lab.app.experiment.figures.FIGURE_KINDS)
    size: RunSize = CHAPTER_SIZE  # this run's Table 2 control
    chapter_size: RunSize = CHAPTER_SIZE  # the chapter's: the size its findings were read at
    chapter_trials: int = DEFAULT_TRIALS  # the chapter's trials per setting (20 initial, 10 otherwise)


def _config(options: ExperimentOptions, base: dict[str, Any], **changes: Any) -> GAConfig:
    values = {"population_size": options.scaled_population(CHAPTER_POPULATION),
              "max_generations": options.scaled_generations(CHAPTER_GENERATIONS),
              "target_fitness": EXPERIMENT_TARGET_FITNESS, "roulette_weighting": options.roulette_weighting,
              **base, **changes}
    return GAConfig(**values)


def _preset_settings(name: str, options: ExperimentOptions) -> tuple[Setting, ...]:
    if name == "initial":
        return (Setting("Table 2", GA, _config(options, {})),)
    if name == ROBOCUP:
        return (Setting("Table 2", GA, _config(options, {}), options.trial()),)
    if name == "max-length":
        return tuple(Setting(str(length), GA, _config(options, {}, max_length=length)) for length in MAX_LENGTHS)
    if name == "population":
        budget = POPULATION_EVALUATIONS * options.population_scale * options.generation_scale
        settings = []
        for size in POPULATION_SIZES:
            population = options.scaled_population(size)
            settings.append(Setting(str(population), GA, _config(options, {}, population_size=population,
                                                           max_generations=max(1, round(budget / population)))))
        return tuple(settings)
    if name == "selection":
        return tuple(Setting(method, GA, _config(options, {}, selection=method)) for method in SELECTIONS)
    if name == "crossover":
        return tuple(Setting(method, GA, _config(options, LATER_CONTROL, crossover=method)) for method in CROSSOVERS)
    if name == "mutation":
        return tuple(Setting(f"{rate:.0%}", GA, _config(options, LATER_CONTROL, mutation_rate=rate))
                     for rate in MUTATION_RATES)
    if name == "long":
        return (_long_setting(options),)
    if name == "random":
        ga = _long_setting(options)
        population = options.scaled_population(RANDOM_SEARCH_POPULATION)
        generations = max(1, round(ga.evaluations / population))
        search = _config(options, {}, population_size=population, max_generations=generations)
        return (Setting("GA", GA, ga.ga), Setting("random search", RANDOM_SEARCH, search))
    if name == "uniform-crossover":
        return tuple(Setting(method, GA, _config(options, LATER_CONTROL, crossover=method))
                     for method in BEYOND_CROSSOVERS)
    if name == "rule-pressure":
        generations = options.scaled_generations(LONG_GENERATIONS)
        return tuple(Setting(str(length), GA, _config(options, LATER_CONTROL, max_generations=generations,
                                                      max_length=length))
                     for length in RULE_PRESSURE_LENGTHS)
    if name == "games-per-evaluation":  # equal games played: the 1-game run has 5x the generations
        most = max(GAMES_PER_EVALUATION)
        return tuple(Setting(f"{games} game{'s' if games > 1 else ''}", GA,
                             _config(options, {}, max_generations=options.scaled_generations(
                                 CHAPTER_GENERATIONS * most // games)), games_per_evaluation=games)
                     for games in GAMES_PER_EVALUATION)
    if name == MATCHES:
        table_2 = _config(options, {})
        return (Setting(ALONE, GA, table_2), Setting(COEVOLVED, GA, table_2, coevolve=COEVOLUTION),
                Setting(SEEING, GA, table_2, coevolve=COEVOLUTION, see_opponent=True))
    if name == "restarts":  # equal evaluations: RESTARTS x G generations against one run of RESTARTS x G
        short = _config(options, LATER_CONTROL, max_generations=options.scaled_generations(CHAPTER_GENERATIONS))
        long = _long_setting(options)
        return (Setting(f"{RESTARTS} x {short.max_generations} generations", GA, short, restarts=RESTARTS),
                Setting(f"1 x {long.ga.max_generations} generations", GA, long.ga))
    raise KeyError(name)


def _long_setting(options: ExperimentOptions) -> Setting:
    return Setting(f"{LONG_GENERATIONS} generations", GA,
                   _config(options, LATER_CONTROL, max_generations=options.scaled_generations(LONG_GENERATIONS)))


# name -> (title, varied parameter, chapter's trials, per-trial curves, figure kinds)
PRESET_TABLE: dict[str, tuple[str, str, int, bool, tuple[str, ...]]] = {
    "initial": ("Initial trials (Table 2)", "trial", INITIAL_TRIALS, True,
                ("mean_fitness", "best_fitness", "goal_histogram", "composition", "gene_pools")),
    "max-length": ("Maximum chromosome length", "max length", DEFAULT_TRIALS, False,
                   ("mean_fitness", "best_fitness", "chromosome_length", "valid_rules")),
    "population": ("Population size (10,000 evaluations)", "population", DEFAULT_TRIALS, False,
                   ("mean_fitness", "best_fitness")),
    "selection": ("Selection method", "selection", DEFAULT_TRIALS, False, ("mean_fitness", "best_fitness")),
    "crossover": ("Crossover method", "crossover", DEFAULT_TRIALS, False, ("mean_fitness", "best_fitness")),
    "mutation": ("Mutation rate", "mutation rate", DEFAULT_TRIALS, False, ("mean_fitness", "best_fitness")),
    "long": ("100 generations", "trial", DEFAULT_TRIALS, True,
             ("mean_fitness", "best_fitness", "goal_histogram", "composition", "gene_pools")),
    "random": ("GA against random search", "search", DEFAULT_TRIALS, False, ("mean_fitness", "best_fitness")),
    ROBOCUP: ("RoboCup initial trials (Table 2 on rcssserver)", "trial", INITIAL_TRIALS, True,
              ("mean_fitness", "best_fitness", "goal_histogram")),
    # beyond the chapter: its future work
    "uniform-crossover": ("Uniform crossover", "crossover", DEFAULT_TRIALS, False,
                          ("mean_fitness", "best_fitness")),
    "rule-pressure": ("Rules per chromosome at their bound (100 generations)", "max length", DEFAULT_TRIALS, False,
                      ("rules_and_bound", "premises_per_rule", "chromosome_length")),
    "games-per-evaluation": ("Games per evaluation (equal games played)", "games per evaluation", DEFAULT_TRIALS,
                             False, ("mean_fitness", "best_fitness")),
    "restarts": ("Restarts against one long run (equal evaluations)", "runs", DEFAULT_TRIALS, False,
                 ("mean_fitness", "best_so_far")),
    MATCHES: ("Matches: evolved alone, co-evolved, co-evolved seeing the opponent", "evolved", DEFAULT_TRIALS, False,
              ("mean_fitness", "best_fitness")),
}
BEYOND_NAMES: tuple[str, ...] = ("uniform-crossover", "rule-pressure", "games-per-evaluation", "restarts")
# presets whose questions the report answers "beyond the chapter": its future work, and the matches study, a
# study of its own that `all-plus` leaves out
ANSWERED_NAMES: tuple[str, ...] = (*BEYOND_NAMES, MATCHES)
PRESET_NAMES: tuple[str, ...] = tuple(name for name in PRESET_TABLE if name not in (ROBOCUP, *ANSWERED_NAMES))  # `all`
CHOICES: tuple[str, ...] = (*PRESET_NAMES, ROBOCUP, *ANSWERED_NAMES, ALL, ALL_PLUS)


def preset(name: str, options: ExperimentOptions) -> Preset:
    """The preset at the size the options ask for; KeyError naming the choices for an unknown name."""
    if name not in PRESET_TABLE:
        raise KeyError(f"unknown preset {name!r}; choose one of {', '.join(CHOICES)}")
    title, varied, trials, per_trial, figures = PRESET_TABLE[name]
    robocup = name == ROBOCUP
    chapter = ExperimentOptions().size(robocup)
    return Preset(name, title, varied, _preset_settings(name, options), options.trials or trials, per_trial,
                  (*figures, "true_quality"), options.size(robocup), chapter, trials)


def presets(name: str, options: ExperimentOptions) -> list[Preset]:
    """`all` expands to every SimpleSoccer preset of the chapter, in its order; `all-plus` adds the chapter's
    future work (not `matches`, a study of its own)."""
    names = {ALL: PRESET_NAMES, ALL_PLUS: (*PRESET_NAMES, *BEYOND_NAMES)}.get(name, (name,))
    return [preset(n, options) for n in names]


def trial_seed(experiment_seed: int, setting: Setting, trial: int) -> int:
    """Each trial's seed, stable per (experiment seed, setting configuration, trial number)."""
    import numpy as np  # here, not at the top: `soccer-lab experiment --help` reads this module's defaults

    key = [int(setting.key.rsplit("-", 1)[1], 16), trial]
    state = np.random.SeedSequence(experiment_seed, spawn_key=key).generate_state(1, np.uint64)[0]
    return int(state) % SEED_BOUND
