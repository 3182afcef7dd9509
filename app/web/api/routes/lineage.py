"""/api/runs/{id}/lineage, /api/runs/{id}/population and /api/breed: where a run's players came from, the
population of any generation, and one breeding step by step (app/lineage/family_tree.py, app/lineage/breeding.py)."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query, Response

from soccer_lab.app.web.api.lineage_models import (GENERATIONS_BACK, MAX_GENERATION, MAX_INDEX, MAX_POPULATION_PAGE,
                                                   BreedRequest, BreedResponse, FamilyTreeOut, IndividualOut, ParentIn,
                                                   PopulationOut)
from soccer_lab.app.web.api.models import ErrorBody
from soccer_lab.app.web.api.routes.dependencies import RecordId, StoreDependency
from soccer_lab.app.web.api.rule_text import VOCABULARY, parse
from soccer_lab.app.lineage.breeding import BreedingDescription, BreedingError, Parent, breed
from soccer_lab.app.lineage.family_tree import RunLineage, short_birth, tree_data
from soccer_lab.app.lineage.drawing import tree_svg
from soccer_lab.app.web.access import ScopedStore
from soccer_lab.app.store import NotFound, StoreError
from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.lineage import LineageError, Place
from soccer_lab.ga.notation import format_compact

router = APIRouter(tags=["lineage"], responses={404: {"model": ErrorBody}, 422: {"model": ErrorBody}})
CODEC = ChromosomeCodec(VOCABULARY)

Generation = Annotated[int | None, Query(ge=0, le=MAX_GENERATION, description="the player's generation "
                                         "(default: the generation of the best so far)")]
Index = Annotated[int | None, Query(ge=0, le=MAX_INDEX, description="its place in the generation (default: the generation's best)")]
GenerationsBack = Annotated[int | None, Query(**GENERATIONS_BACK, description="generations to follow back "
                                              "(default: to generation 0)")]


def _tree(store: ScopedStore, run_id: int, generation: int | None, index: int | None, generations: int | None):
    lineage = RunLineage.from_store(store, run_id, VOCABULARY)
    try:
        return lineage.family_tree(lineage.place(generation, index), generations)
    except LineageError as exc:
        raise NotFound("lineage", run_id, str(exc)) from None


@router.get("/runs/{run_id}/lineage", summary="A player's family tree: its ancestors (fitness, goals, how each was "
            "made) and where each of its rules came from")
def family_tree(run_id: RecordId, store: StoreDependency, generation: Generation = None, index: Index = None,
                generations: GenerationsBack = None) -> FamilyTreeOut:
    return FamilyTreeOut(**tree_data(_tree(store, run_id, generation, index, generations)))


@router.get("/runs/{run_id}/lineage.svg", summary="A player's family tree drawn as SVG, with its rules",
            response_class=Response, responses={200: {"content": {"image/svg+xml": {}}}})
def family_tree_svg(run_id: RecordId, store: StoreDependency, generation: Generation = None, index: Index = None,
                    generations: GenerationsBack = None) -> Response:
    view = _tree(store, run_id, generation, index, generations)
    return Response(tree_svg(view, with_rules=True), media_type="image/svg+xml")


@router.get("/runs/{run_id}/population", summary="A generation's individuals, each with how it was made")
def population(run_id: RecordId, store: StoreDependency,
               generation: Annotated[int, Query(ge=0, le=MAX_GENERATION)],
               offset: Annotated[int, Query(ge=0)] = 0,
               limit: Annotated[int, Query(ge=1, le=MAX_POPULATION_PAGE)] = 50) -> PopulationOut:
    lineage = RunLineage.from_store(store, run_id, VOCABULARY)
    try:
        individuals = lineage.lineage.population(generation)
    except LineageError as exc:
        raise NotFound("lineage", run_id, str(exc)) from None
    page = range(offset, min(offset + limit, len(individuals)))
    return PopulationOut(generation=generation, size=len(individuals), offset=offset, individuals=[
        IndividualOut(index=i, fitness=individuals[i].fitness, goals=individuals[i].goals,
                      evaluations=individuals[i].evaluations, birth=short_birth(individuals[i].birth),
                      record=None if individuals[i].birth is None else individuals[i].birth.to_dict(),
                      chromosome=format_compact(individuals[i].chromosome, VOCABULARY),
                      rules=[format_rule(rule, VOCABULARY) for rule in CODEC.decode(individuals[i].chromosome)])
        for i in page])


@router.post("/breed", summary="Cross two parents (and mutate the children), step by step and seeded")
def breed_parents(body: BreedRequest, store: StoreDependency) -> BreedResponse:
    parents = [_parent(store, parent, n) for n, parent in enumerate(body.parents, start=1)]
    try:
        breeding = breed(*parents, body.crossover, body.seed, VOCABULARY, mutation_rate=body.mutation_rate,
                         max_length=body.max_length)
    except BreedingError as exc:
        raise StoreError(str(exc)) from None  # answered 422, like any value the app refuses
    described = BreedingDescription(breeding, VOCABULARY)
    return BreedResponse(
        crossover=breeding.crossover, seed=breeding.seed,
        parents=[{"name": p.name, "chromosome": described.parent_genes(slot), "cuts": list(described.cuts(slot)),
                  "rules": described.rules(p.chromosome)} for slot, p in enumerate(breeding.parents)],
        children=[{"segments": [{"parent": s, "first": a, "last": b} for s, a, b in described.segments(c)],
                   "crossed": [vars(g) for g in described.child_genes(c, mutated=False)],
                   "mutations": described.changes(c),
                   "chromosome": [vars(g) for g in described.child_genes(c, mutated=True)],
                   "rules": described.rules(child.chromosome)} for c, child in enumerate(breeding.children)])


def _parent(store: ScopedStore, parent: ParentIn, number: int) -> Parent:
    if parent.text is not None:
        return Parent(f"parent {number} (rule text)", CODEC.encode(parse(parent.text)))
    if parent.rulebase_id is not None:
        record = store.get_rulebase(parent.rulebase_id)
        return Parent(record.name, CODEC.encode(parse(record.text)))
    lineage = RunLineage.from_store(store, parent.run_id, VOCABULARY)
    place = Place(parent.generation, parent.index)
    try:
        individual = lineage.lineage.individual(place)
    except LineageError as exc:
        raise NotFound("lineage", parent.run_id, str(exc)) from None
    return Parent(f"run {parent.run_id} {place}", individual.chromosome)
