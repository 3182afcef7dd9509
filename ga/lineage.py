"""A run's recorded generations followed back from one player: the ancestors whose genes it carries (its
family tree), and where each of its rules came from.

A generation's record is its evaluated population in order, each individual with its birth
(ga/provenance.py); so individual i of generation g is `Place(g, i)` everywhere, and a birth's parents are
places in generation g - 1. A gene is followed back through its holders' births: a copy or an elite keeps
it where it is, a splice says which stretch of which parent it came from, a mutation may change it. The
family tree keeps only the ancestors that passed on genes the player still carries (every parent of
every parent is, after a few generations, most of the population). A rule comes from the ancestor in
which it first stood whole: drawn at random, made by a crossover's cut, or changed by a mutation.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, NamedTuple, Sequence

import numpy as np

from soccer_lab.ga.diversity import rule_spans
from soccer_lab.ga.genes import CONNECTOR, CONSEQUENT, GENE_DTYPE, GENE_WIDTH, KIND
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.provenance import Birth, Mutation, Splice

# How a rule came to be in the ancestor where it first stood whole (RuleOrigin.how).
DRAWN, CUT, MUTATED, EARLIER = "drawn at random", "made by a crossover's cut", "changed by a mutation", "earlier"


class LineageError(LookupError):
    """A place the records do not hold (no such generation or individual, or no records at all)."""


class NotRecorded(LineageError):
    """A generation the run finished without a record (it was played before soccer-lab recorded lineage)."""


class Place(NamedTuple):
    generation: int
    index: int

    def __str__(self) -> str:
        return f"gen {self.generation} #{self.index}"


# ---- the record of a generation ---------------------------------------------------------------
def generation_record(generation: int, population: Sequence[Individual],
                      opponents: Sequence[str] | None = None) -> dict[str, Any]:
    """One generation as the run folder's lineage.jsonl and the store keep it. A chromosome is written as
    hex: its int8 gene fields row by row, GENE_WIDTH bytes a gene (ga/genes.py). `opponents`: whom the
    generation was scored against (co-evolution's hall of fame members), last, after the individuals."""
    record = {"generation": generation, "individuals": [
        {"chromosome": individual.chromosome.tobytes().hex(), "evaluations": individual.evaluations,
         "fitness_sum": individual.fitness_sum, "goals": individual.goals, "first_seed": individual.first_seed,
         "birth": None if individual.birth is None else individual.birth.to_dict()}
        for individual in population]}
    if opponents is not None:
        record["opponents"] = list(opponents)
    return record


OPPONENTS_AT_END = re.compile(r',\s*"opponents":\s*(\[[^\]]*\])\s*\}\s*$')


def record_opponents(text: str) -> list[str] | None:
    """Whom a record's generation was scored against (None: a fixed evaluation, or not recorded), read from
    the end of its text without parsing the individuals."""
    found = OPPONENTS_AT_END.search(text)
    return [str(label) for label in json.loads(found.group(1))] if found else None


def read_generation_record(record: dict[str, Any]) -> tuple[int, "RecordedPopulation"]:
    """(generation, population) of a record; ValueError (or KeyError, TypeError) for a malformed one. Its
    individuals are decoded as they are read (a family tree or a page of the population reads a few of
    thousands: decoding every birth of a generation of 10,000 took seconds)."""
    rows = record["individuals"]
    if not isinstance(rows, list):
        raise TypeError("a lineage record's individuals are a list")
    return int(record["generation"]), RecordedPopulation(rows)


# A record's text as generation_record's dict is written (its keys' order; compact separators or json's
# default ones): where each individual's object starts, and its evaluations and fitness sum, found without
# parsing the whole record
RECORD_START = re.compile(r'\{"generation":\s*\d+,\s*"individuals":\s*\[')
ROW_START = re.compile(r'\{"chromosome":\s*"')
ROW_FITNESS = re.compile(r'"evaluations":\s*(\d+),\s*"fitness_sum":\s*(-?[0-9.eE+-]+|-?Infinity|NaN)')


class RecordedPopulation(Sequence[Individual]):
    """A generation's recorded individuals, each decoded on first access (then kept): from the record's
    rows, or from its text, where only the individuals read are parsed (a 10,000-individual record is
    5 MB of JSON: parsing all of it took longer than a lineage request may)."""

    def __init__(self, rows: list[dict[str, Any]]):
        self._rows: Sequence[Any] = rows
        self._text = ""
        self._decoded: dict[int, Individual] = {}

    @classmethod
    def from_text(cls, text: str) -> "RecordedPopulation":
        """The population of a record's JSON text (ValueError for a malformed one)."""
        starts = [match.start() for match in ROW_START.finditer(text)]
        fitness = ROW_FITNESS.findall(text)
        if not RECORD_START.match(text) or len(fitness) != len(starts):  # not as written: parse it all
            return read_generation_record(json.loads(text))[1]
        population = cls([])
        population._rows, population._text = starts, text
        population._fitness = [float(total) / int(n) if int(n) else math.inf for n, total in fitness]
        return population

    def __len__(self) -> int:
        return len(self._rows)

    def __getitem__(self, index):  # type: ignore[override]
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        index = range(len(self))[index]  # IndexError out of range; negative indices count from the end
        if index not in self._decoded:
            row = self._rows[index]
            self._decoded[index] = _individual(_DECODER.raw_decode(self._text, row)[0] if self._text else row)
        return self._decoded[index]

    def fitnesses(self) -> list[float]:
        """Every individual's fitness (its running mean), without decoding the individuals."""
        if self._text:
            return list(self._fitness)
        return [float(row["fitness_sum"]) / int(row["evaluations"]) if int(row["evaluations"]) else math.inf
                for row in self._rows]


_DECODER = json.JSONDecoder()


def _individual(row: dict[str, Any]) -> Individual:
    chromosome = np.frombuffer(bytes.fromhex(row["chromosome"]), dtype=GENE_DTYPE).reshape(-1, GENE_WIDTH).copy()
    birth = row.get("birth")
    first_seed = row.get("first_seed")
    return Individual(chromosome, int(row["evaluations"]), float(row["fitness_sum"]), int(row["goals"]),
                      None if first_seed is None else int(first_seed), None if birth is None else Birth.from_dict(birth))


# ---- following genes back ---------------------------------------------------------------------
def parent_position(birth: Birth, position: int) -> tuple[int, int, tuple[tuple[int, int, int], ...]]:
    """Where gene `position` of a child came from: (the parent's slot in `birth.parents`, its position
    there, the changes (field column, old, new) mutations made to it at this birth). The birth must have
    parents."""
    changes: list[tuple[int, int, int]] = []
    slot = 0
    for operation in reversed(birth.operations):
        if isinstance(operation, Mutation):
            changes += [(column, old, new) for gene, column, old, new in operation.changes if gene == position]
        elif isinstance(operation, Splice):
            slot, position = _spliced_from(operation, position)
        else:
            raise ValueError(f"cannot follow a gene through a {operation.kind} operation")
    return slot, position, tuple(reversed(changes))


def _spliced_from(splice: Splice, position: int) -> tuple[int, int]:
    offset = 0
    for slot, start, stop in splice.segments:
        if position < offset + stop - start:
            return slot, start + position - offset
        offset += stop - start
    raise ValueError(f"gene {position} lies beyond the splice's {offset} genes")


@dataclass(frozen=True)
class Ancestor:
    """One member of a family tree: where it is, what it was, which of the chosen player's genes it held
    (positions in the chosen chromosome), the mutations its own birth made to those genes (gene in the
    chosen chromosome, field column, old, new) and its parents in the tree."""

    place: Place
    individual: Individual
    genes: tuple[int, ...]
    parents: tuple[Place, ...]
    mutations: tuple[tuple[int, int, int, int], ...]

    @property
    def birth(self) -> Birth | None:
        return self.individual.birth


@dataclass(frozen=True)
class RuleOrigin:
    """A rule of the chosen player (genes `first`..`last` of its chromosome): the parent that passed it on
    (`via`; None when it was made in the chosen player itself), the ancestor where it first stood whole
    (`origin`) and how it came to be there (DRAWN, CUT, MUTATED, or EARLIER: already whole in the oldest
    generation followed), the chain of its holders from the chosen player to the origin, and the changes
    (gene, field column, old, new) a mutation at the chosen player's own birth made inside it."""

    first: int
    last: int
    via: Place | None
    origin: Place
    how: str
    operator: str | None
    path: tuple[Place, ...]
    mutations: tuple[tuple[int, int, int, int], ...] = ()


@dataclass(frozen=True)
class FamilyTree:
    chosen: Place
    oldest: int  # the oldest generation followed
    ancestors: dict[Place, Ancestor]  # the chosen player included, newest generation first
    rules: tuple[RuleOrigin, ...] = field(default=())

    @property
    def individual(self) -> Individual:
        return self.ancestors[self.chosen].individual

    def generations(self) -> list[list[Ancestor]]:
        """The tree's rows, newest first; each row ordered by the first of the chosen genes each holds."""
        rows: dict[int, list[Ancestor]] = {}
        for ancestor in self.ancestors.values():
            rows.setdefault(ancestor.place.generation, []).append(ancestor)
        return [sorted(rows[g], key=lambda a: (min(a.genes, default=0), a.place.index))
                for g in sorted(rows, reverse=True)]

    def origins(self) -> list[Place]:
        """The ancestors the rules came from, in the order of the rules (each once)."""
        return list(dict.fromkeys(rule.origin for rule in self.rules))


class Lineage:
    """A run's records: `population_of(g)` gives generation g's recorded population (LookupError when it
    has none); `generations` is how many the run has finished. Records are read as the walk needs them."""

    def __init__(self, population_of: Callable[[int], Sequence[Individual]], generations: int):
        self._population_of = population_of
        self.generations = generations
        self._populations: dict[int, Sequence[Individual]] = {}

    def population(self, generation: int) -> Sequence[Individual]:
        if not 0 <= generation < self.generations:
            raise LineageError(f"the run has generations 0 to {self.generations - 1}, not {generation}")
        if generation not in self._populations:
            try:
                self._populations[generation] = self._population_of(generation)
            except LookupError:
                raise NotRecorded(f"generation {generation} has no lineage record (the run was made before "
                                   "soccer-lab recorded lineage)") from None
        return self._populations[generation]

    def individual(self, place: Place) -> Individual:
        population = self.population(place.generation)
        if not 0 <= place.index < len(population):
            raise LineageError(f"generation {place.generation} has individuals 0 to {len(population) - 1}, "
                               f"not {place.index}")
        return population[place.index]

    def family_tree(self, chosen: Place, generations: int | None = None) -> FamilyTree:
        """The chosen player and the ancestors whose genes it carries, back `generations` generations (None:
        to generation 0 or the oldest recorded generation), with the origin of each of its rules within them."""
        oldest = self._oldest_recorded(chosen.generation, 0 if generations is None else
                                       max(0, chosen.generation - generations))
        chromosome = self.individual(chosen).chromosome
        holders = {gene: (chosen, gene) for gene in range(len(chromosome))}  # chosen gene -> (place, position)
        held: dict[Place, list[int]] = {chosen: list(range(len(chromosome)))}
        parents: dict[Place, set[Place]] = {}
        mutations: dict[Place, list[tuple[int, int, int, int]]] = {}
        for generation in range(chosen.generation, oldest, -1):
            following = {}
            for gene, (place, position) in holders.items():
                birth = self.individual(place).birth
                if birth is None or not birth.parents:
                    continue  # drawn at random here, or not recorded: the gene's line ends
                slot, from_position, changes = parent_position(birth, position)
                mutations.setdefault(place, []).extend((gene, *change) for change in changes)
                parent = Place(generation - 1, birth.parents[slot])
                parents.setdefault(place, set()).add(parent)
                held.setdefault(parent, []).append(gene)
                following[gene] = (parent, from_position)
            holders = following
        ancestors = {place: Ancestor(place, self.individual(place), tuple(sorted(genes)),
                                     tuple(sorted(parents.get(place, ()))), tuple(mutations.get(place, ())))
                     for place, genes in held.items()}
        tree = FamilyTree(chosen, oldest, ancestors)
        return FamilyTree(chosen, oldest, ancestors, tuple(self._rule_origins(tree)))

    def _oldest_recorded(self, newest: int, oldest: int) -> int:
        """`oldest`, or the generation after the newest one in newest..oldest without a record (a run resumed
        from a checkpoint made before lineage was recorded)."""
        for generation in range(newest, oldest - 1, -1):
            try:
                self.population(generation)
            except NotRecorded:
                if generation == newest:
                    raise
                return generation + 1
        return oldest

    def _rule_origins(self, tree: FamilyTree) -> Iterable[RuleOrigin]:
        chromosome = tree.individual.chromosome
        own = tree.ancestors[tree.chosen].mutations
        for first, last in zip(*rule_spans(chromosome[:, KIND], np.array([0]))):
            first, last = int(first), int(last)
            path, how, operator = self._rule_path(tree.chosen, first, last, tree.oldest)
            inside = tuple(change for change in own if first <= change[0] <= last)
            yield RuleOrigin(first, last, path[1] if len(path) > 1 else None, path[-1], how, operator, tuple(path),
                             inside)

    def _rule_path(self, place: Place, first: int, last: int, oldest: int) -> tuple[list[Place], str, str | None]:
        """The holders of the rule at genes first..last of `place`'s chromosome, back to where it first stood
        whole; how it came to be there, and the crossover's operator when a cut made it."""
        path = [place]
        while True:
            birth = self.individual(place).birth
            if birth is not None and not birth.parents:
                return path, DRAWN, None
            if birth is None or place.generation <= oldest:
                return path, EARLIER, None
            positions = [parent_position(birth, position) for position in range(first, last + 1)]
            if any(_changes_meaning(changes, position == last - 1)
                   for position, (_, _, changes) in zip(range(first, last + 1), positions)):
                return path, MUTATED, None
            slots = {slot for slot, _, _ in positions}
            starts = [position for _, position, _ in positions]
            parent = Place(place.generation - 1, birth.parents[positions[0][0]])
            parent_kinds = self.individual(parent).chromosome[:, KIND]
            whole = (len(slots) == 1 and starts == list(range(starts[0], starts[0] + len(starts)))
                     and (starts[0] == 0 or parent_kinds[starts[0] - 1] == CONSEQUENT))
            if not whole:
                splice = next(operation for operation in birth.operations if isinstance(operation, Splice))
                return path, CUT, splice.operator
            place, first, last = parent, starts[0], starts[-1]
            path.append(place)


def _changes_meaning(changes: Sequence[tuple[int, int, int]], last_premise: bool) -> bool:
    """Whether mutations of a rule's gene change the rule: any change but to its last premise's connector,
    which decoding ignores."""
    return any(not (last_premise and column == CONNECTOR) for column, _, _ in changes)


def best_place(bests: Iterable[tuple[int, float]], population_of: Callable[[int], Sequence[Individual]]) -> Place:
    """The best player so far, as the GA keeps it: the generation whose best fitness is lowest (the earliest of
    equals; `bests`: (generation, best fitness)), and in it the first individual of that fitness."""
    generation, fitness = min(bests, key=lambda best: (best[1], best[0]))
    return Place(generation, generation_best_index(population_of(generation)))


def generation_best_index(population: Sequence[Individual]) -> int:
    """A generation's best individual, as the GA's: the lowest running mean, the first of equals."""
    fitness = population.fitnesses() if isinstance(population, RecordedPopulation) else [i.fitness for i in population]
    return min(range(len(fitness)), key=fitness.__getitem__)
