"""GAConfig: every GA parameter in one validated object; defaults = the chapter's Table 2, and
for what it leaves open (the roulette weighting) the calibrated choice (docs/research/calibration.md)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator


SEED_BOUND = 2**63  # seeds (the run's and its games') lie in [0, SEED_BOUND)
MAX_BEHAVIOUR_SEEDS = 16
# Breeding a generation is not interrupted by a stop (evaluation is, between chunks): at this size it takes
# about a second, at 100,000 tens of seconds (docs/reference/limits.md, benchmarks/stop_latency.py)
MAX_POPULATION = 10_000
# Each worker is a process of about 180 MB (the game kernels): 32 take about 6 GB, two runs at once 12 GB
MAX_WORKERS = 32
RouletteWeighting = Literal["linear", "inverse"]  # ga/selection.py roulette_weights says what each does


FRESH_SEED_BOUND = 2**32  # a drawn seed: ten digits at most to type again, exact in JavaScript's numbers


def fresh_seed() -> int:
    """A new run seed in [0, FRESH_SEED_BOUND) from the operating system's entropy: what a run started from the UI or
    the API without a seed gets (thirty pupils breed thirty different players). The run records it; giving it
    again replays the run bit for bit."""
    import numpy as np  # here: the CLI's --help reads this module and stays light

    return int(np.random.SeedSequence().entropy % FRESH_SEED_BOUND)


class GAConfig(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")

    population_size: int = Field(200, ge=2, le=MAX_POPULATION, description="individuals per generation")
    max_generations: int = Field(25, ge=1, le=100_000,
                                 description="generations evaluated, the initial population (generation 0) included")
    max_length: int = Field(64, ge=2, le=10_000, description="maximum genes per chromosome")
    consequent_probability: float = Field(0.25, gt=0, lt=1,
                                          description="chance that an initial gene is a consequent")
    crossover: Literal["one-point", "two-point", "uniform"] = Field(
        "one-point", description="cut-and-splice at one or two points, or rule-wise uniform (ga/crossover.py)")
    crossover_probability: float = Field(0.8, ge=0, le=1)
    mutation_probability: float = Field(0.35, ge=0, le=1, description="chance that a child is mutated")
    mutation_rate: float = Field(0.10, ge=0, le=1, description="chance that each gene of a mutated child is hit")
    selection: Literal["roulette", "tournament", "elitist"] = "roulette"
    roulette_weighting: RouletteWeighting = Field(
        "linear", description="roulette weight of an individual: 1 - fitness (linear) or 1 / fitness (inverse); "
                               "roulette and elitist selection use it (ga/selection.py)")
    tournament_size: int = Field(2, ge=2, le=1_000)
    tournament_selector: float = Field(0.75, ge=0, le=1, description="chance that the better entrant wins")
    elite_fraction: float = Field(0.05, ge=0, lt=1, description="share of the population copied unchanged (elitist)")
    target_fitness: float = Field(0.05, ge=0, le=1, description="stop once the best fitness reaches this")
    seed: int = Field(0, ge=0, lt=SEED_BOUND,
                      description="the whole run's seed: the same seed plays the same run bit for bit; left out, "
                                  "the UI and the API draw a fresh one (fresh_seed), the CLI uses 0")
    workers: int = Field(1, ge=1, le=MAX_WORKERS, description="evaluation processes; results do not depend on it")
    behaviour_seeds: int = Field(0, ge=0, le=MAX_BEHAVIOUR_SEEDS,
                                 description="K: every generation each distinct chromosome also plays K common "
                                             "seeds, to count the distinct ways the population plays "
                                             "(ga/diversity.py); 0 = not measured. Costs K games per new chromosome; "
                                             "the evolution itself does not change")

    @model_validator(mode="after")
    def _elites_leave_room_to_breed(self) -> "GAConfig":
        if self.selection == "elitist" and self.elite_count >= self.population_size:
            raise ValueError("elite_fraction leaves no room to breed: elites must be fewer than the population")
        return self

    @property
    def elite_count(self) -> int:
        """Individuals copied unchanged each generation (elitist selection only; at least one)."""
        if self.selection != "elitist":
            return 0
        return max(1, round(self.elite_fraction * self.population_size))


MAX_HALL_SIZE = 100
MAX_HALL_SAMPLE = 20  # each is a match per evaluation: the cost grows with it


class CoevolutionConfig(BaseModel):
    """Co-evolution against a hall of fame of earlier bests (ga/hall_of_fame.py): how many bests it keeps
    (its founder, generation 0's opponent, besides) and how many of its members each generation is scored
    against."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    hall_size: int = Field(10, ge=1, le=MAX_HALL_SIZE, description="generation bests the hall of fame keeps")
    hall_sample: int = Field(3, ge=1, le=MAX_HALL_SAMPLE,
                             description="hall members each generation is scored against (a match each)")
