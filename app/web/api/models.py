"""The JSON API's request and response bodies (pydantic): what /openapi.json documents."""

from __future__ import annotations

import math
import types
from typing import Annotated, Any, Union, get_args, get_origin

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from soccer_lab.app.runs.environments import SIMPLE, EnvName
from soccer_lab.app.rule_inspection import DEFAULT_USAGE_GAMES, MAX_GAMES
from soccer_lab.app.runs.run import AlgorithmName
from soccer_lab.app.store import NAME_MAX_LENGTH, BestIndividual, RulebaseRecord, RunRecord
from soccer_lab.ga.config import CoevolutionConfig, GAConfig
from soccer_lab.ga.state import GA
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.rcss.servers import MAX_SERVERS
from soccer_lab.soccer.rcss.trial import TrialConfig

RULE_TEXT_MAX_LENGTH = 200_000  # far above any evolved rulebase (64 genes make at most 16 rules)

Name = Annotated[str, Field(min_length=1, max_length=NAME_MAX_LENGTH, pattern=r"\S")]
RuleText = Annotated[str, Field(max_length=RULE_TEXT_MAX_LENGTH)]


class Strict(BaseModel):
    """Requests name every field they mean: an unknown field is an error, not silently dropped. A number is
    a JSON number: "5" or true for a number is an error too (pydantic's lax mode would take them), here and in
    the settings models a request holds (ga, game, trial)."""

    model_config = ConfigDict(extra="forbid")

    @model_validator(mode="before")
    @classmethod
    def numbers_are_numbers(cls, data: Any) -> Any:
        if wrong := not_numbers(cls, data):
            raise ValueError("; ".join(wrong[:5]))
        return data


def not_numbers(model: type[BaseModel], data: Any, place: tuple[str, ...] = ()) -> list[str]:
    """Where `data` (a request's JSON) gives something other than a number for a number of `model`'s, looking
    into the models it holds (the outermost request names the whole path: "ga.population_size")."""
    if not isinstance(data, dict):
        return []
    found = []
    for name, field in model.model_fields.items():
        key = field.alias or name
        if key not in data:
            continue
        value, where = data[key], ".".join((*place, key))
        kind = _number_kind(field.annotation)
        if kind is not None and (isinstance(value, (str, bool)) or (kind is int and isinstance(value, float))):
            found.append(f"{where}: {'a whole number' if kind is int else 'a number'}, not {value!r:.40}")
        nested = field.annotation if isinstance(field.annotation, type) else None
        if nested is not None and issubclass(nested, BaseModel):
            found += not_numbers(nested, value, (*place, key))
    return found


def _number_kind(annotation: Any) -> type | None:
    """int or float when a field holds a number (or null), else None."""
    if get_origin(annotation) in (Union, types.UnionType):
        kinds = [_number_kind(a) for a in get_args(annotation) if a is not type(None)]
        return kinds[0] if len(kinds) == 1 else None
    return annotation if annotation in (int, float) else None


# ---- errors ------------------------------------------------------------------------------
class ErrorBody(BaseModel):
    """At most 16 KB (app/web/api/errors.py): the first 20 problems in `errors`, all of them counted."""

    detail: str
    errors: list[dict[str, Any]] = []
    error_count: int = 0


# ---- rules -------------------------------------------------------------------------------
class PremiseOut(BaseModel):
    object: str
    term: str
    negated: bool


class ConsequentOut(BaseModel):
    action: str
    direction: str | None
    power: str | None


class RuleOut(BaseModel):
    text: str
    premises: list[PremiseOut]
    connectors: list[str]
    consequent: ConsequentOut


class ParseRequest(Strict):
    text: RuleText


class ParseResponse(BaseModel):
    rules: list[RuleOut]
    text: str  # the rulebase printed back in canonical form


class CrispInputs(Strict):
    """Crisp inputs; leave both inputs of an object out (or null) when it is not in view."""

    ball_distance: float | None = Field(None, ge=0.0)
    ball_direction: float | None = Field(None, ge=-180.0, le=180.0)
    goal_distance: float | None = Field(None, ge=0.0)
    goal_direction: float | None = Field(None, ge=-180.0, le=180.0)

    @field_validator("*")
    @classmethod
    def finite(cls, value: float | None) -> float | None:
        if value is not None and not math.isfinite(value):
            raise ValueError("must be a finite number")
        return value


class RulebaseSource(Strict):
    """Rule text or a saved rulebase's id (exactly one)."""

    text: RuleText | None = None
    rulebase_id: int | None = Field(None, ge=1, le=2**62)

    @model_validator(mode="after")
    def one_source(self) -> "RulebaseSource":
        if (self.text is None) == (self.rulebase_id is None):
            raise ValueError("give exactly one of 'text' and 'rulebase_id'")
        return self


class EvaluateRequest(RulebaseSource):
    """Rule text or a saved rulebase's id (exactly one), and the crisp inputs."""

    inputs: CrispInputs = CrispInputs()


class RuleEvaluation(BaseModel):
    text: str
    premise_degrees: list[float]
    strength: float


class FiredAction(BaseModel):
    action: str
    support: float
    parameters: dict[str, float]


class EvaluateResponse(BaseModel):
    visible: list[str]
    rules: list[RuleEvaluation]
    fired: list[FiredAction]
    selected: FiredAction | None  # null: no rule fired and the player hunts (turns to find the ball)


# ---- rule usage and simplification --------------------------------------------------------
class GamesRequest(RulebaseSource):
    """Games of SimpleSoccer: game i starts from seed + i; `game` sets the rules of every game."""

    games: int = Field(DEFAULT_USAGE_GAMES, ge=1, le=MAX_GAMES)
    seed: int = Field(0, ge=0, le=2**62)
    game: GameConfig = GameConfig()


class UsageRequest(GamesRequest):
    """The rulebase and the games to count its rules' usage in."""


class SimplifyRequest(GamesRequest):
    """games 0 (the default): only the exact steps."""

    games: int = Field(0, ge=0, le=MAX_GAMES)
    drop_unused_fields: bool = False


class RuleUsageOut(BaseModel):
    rule: int  # from 1, in rulebase order
    text: str
    action: str
    fired: int  # ticks its strength was above 0
    won: int  # ticks it fired and its action was performed
    decided: int  # ticks it was the performed action's strongest rule (the first among equals)
    mean_strength: float | None  # over the ticks it fired
    fired_share: float
    won_share: float


class ActionUsageOut(BaseModel):
    action: str
    performed: int
    share: float


class GameOut(BaseModel):
    seed: int
    goals: float
    kicks: float
    ticks: float
    fitness: float


class GamesOut(BaseModel):
    mean_goals: float | None
    mean_fitness: float | None
    games: list[GameOut]


class UsageResponse(BaseModel):
    games: int
    seeds: list[int]
    ticks: int  # decisions made, over all games
    rules: list[RuleUsageOut]
    actions: list[ActionUsageOut]
    hunt: int  # ticks no rule fired
    hunt_share: float
    results: GamesOut


class ChangeOut(BaseModel):
    rule: int  # its number in the original rulebase, from 1
    before: str
    after: str | None  # null: the rule is dropped
    reason: str


class StepOut(BaseModel):
    name: str
    kind: str  # "exact" (proved on every input) or "checked" (replayed on `games` games)
    applied: bool
    summary: str
    games: int
    changes: list[ChangeOut]


class SizeOut(BaseModel):
    rules: int
    premises: int


class ResultsBeforeAfter(BaseModel):
    before: GamesOut
    after: GamesOut


class SimplifyResponse(BaseModel):
    text: str  # the simplified rulebase
    origins: list[int]  # per rule of `text`, its number in the original
    before: SizeOut
    after: SizeOut
    steps: list[StepOut]
    games: int
    results: ResultsBeforeAfter | None = None


# ---- rulebases ---------------------------------------------------------------------------
class RulebaseCreate(Strict):
    name: Name
    text: RuleText
    run_id: int | None = Field(None, ge=1, le=2**63 - 1, description="the run whose best so far `text` is: its one-game fitness "
                               "and true quality are kept beside the rules (422 when `text` is not that best)")


class RulebaseUpdate(Strict):
    name: Name | None = None
    text: RuleText | None = None

    @model_validator(mode="after")
    def _name_or_text(self) -> "RulebaseUpdate":
        if self.name is None and self.text is None:
            raise ValueError("give 'name', 'text' or both")
        return self


class BestOfOut(BaseModel):
    """The run's best a saved rulebase is, with the figures it was measured at."""

    run_id: int
    generation: int
    fitness_seen: float = Field(description="the fitness the GA saw: its running mean, often one game")
    true_quality: "TrueQualityOut | None" = Field(
        None, description="its true quality, beside `fitness_seen`; null when not re-played (an rcssserver run)")


class RulebaseOut(BaseModel):
    id: int
    name: str
    text: str
    created: str
    updated: str
    best_of: BestOfOut | None = Field(None, description="saved from a run's best: its figures; null otherwise")

    @classmethod
    def of(cls, record: RulebaseRecord) -> "RulebaseOut":
        data = record.to_dict()
        del data["owner"], data["best_of"]
        try:
            best_of = BestOfOut.model_validate(record.best_of) if record.best_of else None
        except ValueError:  # a damaged record: the rules are still listed
            best_of = None
        return cls(**data, best_of=best_of)


# ---- runs --------------------------------------------------------------------------------
class RunStart(Strict):
    """A new run of the GA or of random search (the baseline: the same evaluations spent on fresh random
    rulebases); every GA and game parameter defaults to the chapter's. `name` defaults to what the run is
    (e.g. "GA 200x25 roulette/inverse assisted seed 0"). env "rcss" plays trials (`trial`) on real
    rcssservers instead of SimpleSoccer games (`game`), with ga.workers 1: on `start_servers` servers the
    run starts itself (default 1, from the app's rcssserver: `serve --rcssserver PATH`) or on `servers`
    you run (HOST:PORT); several play in parallel."""

    name: Name | None = None
    algorithm: AlgorithmName = GA
    ga: GAConfig = GAConfig()
    game: GameConfig = GameConfig()
    env: EnvName = SIMPLE
    servers: list[Annotated[str, Field(max_length=300)]] = Field([], max_length=64)
    start_servers: int | None = Field(None, ge=1, le=MAX_SERVERS)
    trial: TrialConfig = TrialConfig()
    opponent: RuleText | None = Field(None, description="rule text of a fixed player every evaluation is a match "
                                      "against (SimpleSoccer); with coevolve, the hall of fame's founder")
    coevolve: CoevolutionConfig | None = Field(None, description="co-evolve against a hall of fame of earlier "
                                               "bests, founded by the opponent or the built-in demo")

    @model_validator(mode="after")
    def playable(self) -> "RunStart":
        from soccer_lab.app.runs.run import RunSettings  # the one place the rules for env, servers and workers live

        # The opponent's rules are parsed by the route, in a thread: this runs on the event loop, and 200,000
        # characters of rules take a second to parse. Given with an rcss env it is refused here, unparsed.
        RunSettings.build(self.ga, self.game, self.env, self.servers, self.trial, self.algorithm, self.start_servers,
                          None if self.env == SIMPLE else self.opponent, self.coevolve)
        return self


class RunRename(Strict):
    name: Name


class GenerationProgressOut(BaseModel):
    """How far a running run's current generation is: `evaluated` of its `population` individuals (each
    evaluation games_per_evaluation games, or one rcssserver trial)."""

    generation: int
    evaluated: int
    population: int


class QueuePlaceOut(BaseModel):
    """Where a queued run stands (classroom mode): `position` 1 starts next, of `queued` waiting;
    `wait_seconds` until it starts and `run_seconds` it then plays, estimated from the class's finished runs."""

    position: int
    queued: int
    wait_seconds: float
    run_seconds: float


class RunOut(BaseModel):
    id: int
    name: str
    status: str
    created: str
    finished: str | None
    error: str | None
    config: dict[str, Any]
    generations: int  # finished generations stored
    best_fitness: float | None
    resumable: bool
    recording: str | None  # URL of the rerun recording, once there is one
    progress: GenerationProgressOut | None = None  # while running: the generation being evaluated
    queue: QueuePlaceOut | None = None  # while queued (status "queued"): its place and estimates

    @classmethod
    def of(cls, record: RunRecord, statistics: list[dict[str, Any]], recording: str | None,
           progress: Any = None, place: Any = None) -> "RunOut":
        bests = [s["best"] for s in statistics if isinstance(s.get("best"), (int, float))]
        return cls(
            queue=QueuePlaceOut(**place.to_dict()) if place is not None else None,
            progress=GenerationProgressOut(generation=progress.generation, evaluated=progress.evaluated,
                                           population=progress.population) if progress is not None else None,
            id=record.id,
            name=record.name,
            status=str(record.status),
            created=record.created,
            finished=record.finished,
            error=record.error,
            config=record.config,
            generations=len(statistics),
            best_fitness=min(bests) if bests else None,
            resumable=record.status.resumable,
            recording=recording,
        )


class TrueQualityOut(BaseModel):
    """The best re-played on `starts` fresh starts, the same for every player (app/runs/true_quality.py)."""

    starts: int
    fitness: float = Field(description="mean fitness over the starts")
    fitness_std: float
    goals: float = Field(description="mean goals a game")
    scoring: float = Field(description="share of the games with a goal")


class BestOut(BaseModel):
    run_id: int
    generation: int
    rules: str
    chromosome: str
    fitness: float = Field(description="the fitness the GA saw: its running mean, often one game")
    true_quality: TrueQualityOut | None = Field(
        None, description="its true quality, beside `fitness`; null until re-played (and on rcssserver)")

    @classmethod
    def of(cls, best: BestIndividual, quality: Any = None) -> "BestOut":
        return cls(**best.to_dict(), true_quality=quality.to_dict() if quality is not None else None)


# ---- experiments -------------------------------------------------------------------------
class FigureOut(BaseModel):
    name: str
    caption: str
    url: str


class TrialRecordingOut(BaseModel):
    trial: str  # <setting key>-<trial number>
    url: str  # the .rrd (open it in the rerun viewer)


class ExperimentOut(BaseModel):
    """A recorded `soccer-lab experiment`: its summary, and links to the files still in its folder
    (null or empty when the folder or file is gone)."""

    id: int
    preset: str
    created: str
    folder: str  # the folder's name (the API returns no filesystem path)
    available: bool  # the folder is still there
    presets: list[str]
    trials: int | None
    options: dict[str, Any]
    verdicts: dict[str, int]
    report: str | None  # URL of report.html (figures inline)
    report_markdown: str | None
    statistics: str | None  # URL of statistics.csv
    figures: list[FigureOut]
    recordings: list[TrialRecordingOut]


class ServerInfo(BaseModel):
    ui: str | None
    viewer: str | None  # rerun's web viewer, served by the app (/viewer/)
    viewer_home: str | None  # the viewer without rerun's welcome screen; a recording: `<viewer_home>&url=<recording URL>`
    docs: str
    classroom: bool = False  # serve --class: the class's routes (/api/class...) exist and the pages show them


BestOfOut.model_rebuild()  # its true quality is defined below it, with the runs
RulebaseOut.model_rebuild()
