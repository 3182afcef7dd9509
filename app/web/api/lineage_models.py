"""The JSON bodies of the lineage and breeding routes (what /openapi.json documents for them)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field, model_validator

from soccer_lab.app.web.api.models import RuleText, Strict
from soccer_lab.app.lineage.breeding import DEFAULT_MUTATION_RATE
from soccer_lab.app.lineage.family_tree import MAX_GENERATIONS_BACK
from soccer_lab.ga.config import MAX_POPULATION, SEED_BOUND, GAConfig
from soccer_lab.ga.crossover import CROSSOVERS

SQLITE_MAX_INTEGER = 2**63 - 1
MAX_GENERATION = 100_000  # GAConfig's largest max_generations
MAX_INDEX = MAX_POPULATION - 1  # the last place in the largest population GAConfig allows
MAX_POPULATION_PAGE = 500
CrossoverName = Literal[tuple(CROSSOVERS)]  # type: ignore[valid-type]


class PlaceOut(BaseModel):
    generation: int
    index: int


class AncestorOut(PlaceOut):
    fitness: float
    goals: int
    evaluations: int
    birth: str  # in a word or two: random, elite, copy, cut, cut + mutation, mutation
    how: str  # in a sentence: parents, cut points, what a mutation changed
    parents: list[PlaceOut]  # its parents in the tree: those that passed on genes the player carries
    genes: list[int]  # the player's genes (1-based positions in its chromosome) this ancestor held
    origin_of: str | None  # the letter of the player's rules that came from this ancestor
    colour: str | None
    record: dict[str, Any] | None  # the birth as recorded (ga/provenance.py), null where not recorded


class RuleOriginOut(BaseModel):
    number: int
    text: str
    compact: str  # its genes in the chapter's compact notation
    origin: PlaceOut  # the ancestor where it first stood whole
    via: PlaceOut | None  # the player's parent that passed it on (null: made in the player itself)
    letter: str
    colour: str
    how: str
    summary: str
    mutated: list[str]  # what a mutation at the player's own birth changed in it


class GeneOut(BaseModel):
    compact: str
    origin: str | None  # the letter of its rule's origin (null: in no rule)
    mutated: str | None


class GenerationOpponentsOut(BaseModel):
    generation: int
    opponents: list[str]  # the hall of fame members it played, e.g. "the built-in demo", "best of generation 3"


class FamilyTreeOut(BaseModel):
    """A player and the ancestors whose genes it carries, newest generation first."""

    player: PlaceOut
    best_so_far: PlaceOut | None
    oldest_generation: int
    title: str
    ancestors: list[AncestorOut]
    rules: list[RuleOriginOut]
    chromosome: list[GeneOut]
    opponents: list[GenerationOpponentsOut] = []  # co-evolution: whom each generation of the tree was scored against


class IndividualOut(BaseModel):
    index: int
    fitness: float
    goals: int
    evaluations: int
    birth: str
    record: dict[str, Any] | None
    chromosome: str  # compact notation
    rules: list[str]


class PopulationOut(BaseModel):
    generation: int
    size: int
    offset: int
    individuals: list[IndividualOut]


class ParentIn(Strict):
    """A parent: a run's individual (run_id, generation, index), a saved rulebase (rulebase_id) or rule text."""

    run_id: int | None = Field(None, ge=1, le=SQLITE_MAX_INTEGER)
    generation: int | None = Field(None, ge=0, le=MAX_GENERATION)
    index: int | None = Field(None, ge=0, le=MAX_INDEX)
    rulebase_id: int | None = Field(None, ge=1, le=SQLITE_MAX_INTEGER)
    text: RuleText | None = None

    @model_validator(mode="after")
    def one_source(self) -> "ParentIn":
        individual = (self.run_id, self.generation, self.index)
        sources = [all(v is not None for v in individual), self.rulebase_id is not None, self.text is not None]
        if sum(sources) != 1 or (not sources[0] and any(v is not None for v in individual)):
            raise ValueError("give exactly one of: run_id, generation and index (a run's individual); "
                             "rulebase_id; text")
        return self


class BreedRequest(Strict):
    parents: list[ParentIn] = Field(min_length=2, max_length=2)
    crossover: CrossoverName = GAConfig().crossover  # type: ignore[valid-type]
    seed: int = Field(0, ge=0, lt=SEED_BOUND)
    mutation_rate: float | None = Field(None, gt=0, le=1, description="mutate each child, every gene hit with "
                                        f"this chance (the GA's default {DEFAULT_MUTATION_RATE}); null: no mutation")
    max_length: int = Field(GAConfig().max_length, ge=2, le=10_000)


class ParentOut(BaseModel):
    name: str
    chromosome: list[str]  # gene by gene, compact notation
    cuts: list[int]  # the crossover cut after these genes
    rules: list[str]


class GeneCellOut(BaseModel):
    compact: str
    parent: int  # 0 or 1: the parent it came from
    mutated: str | None


class SegmentOut(BaseModel):
    parent: int
    first: int  # 1-based genes of that parent
    last: int


class ChildOut(BaseModel):
    segments: list[SegmentOut]
    crossed: list[GeneCellOut]  # after the crossover
    mutations: list[str]  # gene by gene
    chromosome: list[GeneCellOut]  # after the mutation (the same without one)
    rules: list[str]


class BreedResponse(BaseModel):
    crossover: str
    seed: int
    parents: list[ParentOut]
    children: list[ChildOut]


GENERATIONS_BACK = {"ge": 0, "le": MAX_GENERATIONS_BACK}
