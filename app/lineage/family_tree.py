"""A run's lineage, read from its folder (lineage.jsonl) or the store, and a player's family tree described
for people: each ancestor with its fitness, goals and birth in words, each rule of the player with the
ancestor it came from (a letter and a colour), its genes in the chapter's compact notation, and what a
mutation changed. The CLI, the API and the UI's Lineage tab all show this description
(app/lineage/drawing.py draws it as text, SVG and DOT)."""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from soccer_lab.app.runs.outputs import LineageFile, RunFolder
from soccer_lab.app.words import plural
from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.checkpoint import CheckpointError, load_checkpoint
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.genes import FIELD_NAMES, KIND, GeneSpace
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.lineage import (CUT, DRAWN, EARLIER, MUTATED, Ancestor, FamilyTree, Lineage, LineageError,
                                   NotRecorded, Place, RecordedPopulation, RuleOrigin, best_place,
                                   generation_best_index, record_opponents)
from soccer_lab.ga.notation import CompactNotation
from soccer_lab.ga.provenance import COPY, Birth, Mutation, Splice

# One colour per ancestor a rule came from (cycled): strong enough for a projector, told apart by letter too.
ORIGIN_COLOURS = ("#1976d2", "#e65100", "#2e7d32", "#8e24aa", "#c62828", "#00838f", "#6d4c41", "#ad1457",
                  "#558b2f", "#283593")
MUTATED_COLOUR = "#d50000"
MAX_GENERATIONS_BACK = 1000  # the most generations one tree follows (each costs a generation's record)


class RunLineage:
    """`population_of(g)`: generation g's recorded population (LookupError when none); `bests`: (generation,
    best fitness) of every finished generation; `opponents_of(g)`: whom generation g was scored against
    (co-evolution's hall of fame members; None for a fixed evaluation or when not recorded)."""

    def __init__(self, population_of: Callable[[int], Sequence[Individual]], bests: Sequence[tuple[int, float]],
                 vocabulary: Vocabulary, opponents_of: Callable[[int], list[str] | None] = lambda g: None):
        self.bests = list(bests)
        self.lineage = Lineage(population_of, 1 + max((g for g, _ in self.bests), default=-1))
        self.vocabulary = vocabulary
        self.opponents_of = opponents_of

    @classmethod
    def from_folder(cls, path: str | Path) -> "RunLineage":
        """A run folder's lineage; LineageError (with one line) when it has none."""
        folder = RunFolder(Path(path))
        if not folder.manifest.is_file():
            raise LineageError(f"{folder.path} is not a run folder (no {folder.manifest.name})")
        lines = LineageFile.read(folder.lineage)
        if not lines:
            raise LineageError(f"{folder.path} has no lineage records ({folder.lineage.name}): the run finished no "
                               "generation, or was made before soccer-lab recorded lineage")
        vocabulary = Vocabulary.default()
        try:
            state = load_checkpoint(folder.checkpoint)
            vocabulary = state.vocabulary
        except CheckpointError:
            pass  # the records alone are enough; the rules read in the default vocabulary
        return cls(lambda g: RecordedPopulation.from_text(lines[g]), _bests(folder, lines), vocabulary,
                   lambda g: record_opponents(lines[g]) if g in lines else None)

    @classmethod
    def from_store(cls, store: Any, run_id: int, vocabulary: Vocabulary) -> "RunLineage":
        """A stored run's lineage (NotFound for an unknown run). Generations are those with statistics."""
        from soccer_lab.app.store import NotFound

        def population_of(generation: int) -> list[Individual]:
            try:
                return RecordedPopulation.from_text(store.lineage_text(run_id, generation))
            except NotFound:
                raise LookupError(generation) from None

        def opponents_of(generation: int) -> list[str] | None:
            try:
                return record_opponents(store.lineage_text(run_id, generation))
            except NotFound:
                return None

        bests = [(row["generation"], row["best"]) for row in store.statistics(run_id)]
        return cls(population_of, bests, vocabulary, opponents_of)

    # ---- which player ---------------------------------------------------------------------------
    def place(self, generation: int | None = None, index: int | None = None) -> Place:
        """The player asked for: `index` of `generation`; without an index, that generation's best; without
        either, the best so far (as the GA keeps it). LineageError for a place the run does not have."""
        if not self.bests:
            raise LineageError("the run has finished no generation yet")
        if generation is None:
            if index is not None:
                raise LineageError("an individual's index needs its generation")
            return best_place(self.bests, self.lineage.population)
        population = self.lineage.population(generation)
        place = Place(generation, generation_best_index(population) if index is None else index)
        self.lineage.individual(place)  # refuses an index out of range
        return place

    def family_tree(self, place: Place, generations: int | None = None) -> "FamilyTreeView":
        if generations is not None and not 0 <= generations <= MAX_GENERATIONS_BACK:
            raise LineageError(f"generations back: between 0 and {MAX_GENERATIONS_BACK}, not {generations}")
        tree = self.lineage.family_tree(place, generations)
        try:
            best = best_place(self.bests, self.lineage.population)
        except NotRecorded:
            best = None  # the best so far is in a generation played before lineage was recorded
        opponents = {g: labels for g in range(tree.oldest, place.generation + 1)
                     if (labels := self.opponents_of(g)) is not None}
        return FamilyTreeView(tree, self.vocabulary, best, opponents)


def _bests(folder: RunFolder, lines: dict[int, str]) -> list[tuple[int, float]]:
    """(generation, best fitness) of every finished generation: statistics.csv's, and for a generation it
    lacks (cut short by a kill), its record's."""
    bests: dict[int, float] = {}
    try:
        with folder.statistics.open(newline="") as handle:
            for row in csv.DictReader(handle):
                bests[int(row["generation"])] = float(row["best"])
    except (OSError, KeyError, ValueError):
        pass
    for generation, line in lines.items():
        if generation not in bests:
            bests[generation] = min(RecordedPopulation.from_text(line).fitnesses())
    return sorted(bests.items())


# ---- the tree in words ------------------------------------------------------------------------
@dataclass(frozen=True)
class GeneView:
    compact: str  # the gene in compact notation
    origin: str | None  # the letter of the ancestor its rule came from (None: in no rule)
    mutated: str | None  # what a mutation at the player's own birth changed in it


@dataclass(frozen=True)
class RuleView:
    number: int  # 1-based, as the rules are listed
    text: str
    genes: str  # its genes in compact notation
    letter: str  # of the ancestor it came from
    colour: str
    origin: Place
    via: Place | None
    how: str  # DRAWN, CUT, MUTATED or EARLIER
    summary: str  # where it came from, in a sentence
    mutated: tuple[str, ...]  # changes a mutation made in it at the player's own birth


class FamilyTreeView:
    """A FamilyTree described for people (see the module's docstring)."""

    def __init__(self, tree: FamilyTree, vocabulary: Vocabulary, best: Place | None = None,
                 opponents: dict[int, list[str]] | None = None):
        self.tree = tree
        self.opponents = opponents or {}  # generation -> whom it was scored against (co-evolution)
        self.vocabulary = vocabulary
        self.best = best  # the run's best so far, named when it is in the tree
        self.notation = CompactNotation(vocabulary)
        self.codec = ChromosomeCodec(vocabulary)
        self.letters = {place: chr(ord("A") + i) if i < 26 else str(i) for i, place in enumerate(tree.origins())}
        self.rules = [self._rule(number, rule) for number, rule in enumerate(tree.rules, start=1)]

    @property
    def chosen(self) -> Place:
        return self.tree.chosen

    def colour(self, place: Place) -> str | None:
        letter_index = list(self.letters).index(place) if place in self.letters else None
        return None if letter_index is None else ORIGIN_COLOURS[letter_index % len(ORIGIN_COLOURS)]

    def title(self) -> str:
        individual = self.tree.individual
        what = " (the best so far)" if self.chosen == self.best else ""
        return (f"Generation {self.chosen.generation}, individual #{self.chosen.index}{what}: "
                f"fitness {individual.fitness:.3f}, {plural(individual.goals, 'goal')}")

    def rows(self) -> list[list[Ancestor]]:
        return self.tree.generations()

    def birth_text(self, ancestor: Ancestor) -> str:
        """How an ancestor came to be, in a sentence (parents named by their place in the generation before)."""
        return describe_birth(ancestor.birth, ancestor.place.generation, self.vocabulary,
                              self.tree.individual.chromosome if ancestor.place == self.chosen else None)

    def short_birth(self, ancestor: Ancestor) -> str:
        """One or two words: elite, copy, cut, cut + mutation, mutation, random."""
        return short_birth(ancestor.birth)

    def genes(self) -> list[GeneView]:
        """The player's chromosome gene by gene: compact notation, the origin of its rule, any mutation."""
        chromosome = self.tree.individual.chromosome
        letters: dict[int, str] = {}
        for origin in self.tree.rules:
            for gene in range(origin.first, origin.last + 1):
                letters[gene] = self.letters[origin.origin]
        changes = _changes_by_gene(self.tree.ancestors[self.chosen].mutations)
        return [GeneView(self.notation.format_gene(row), letters.get(gene),
                         "; ".join(describe_change(chromosome, gene, change, self.vocabulary) for change in changes[gene])
                         if gene in changes else None)
                for gene, row in enumerate(chromosome.tolist())]

    def _rule(self, number: int, origin: RuleOrigin) -> RuleView:
        chromosome = self.tree.individual.chromosome
        rulebase = self.codec.decode(chromosome[origin.first:origin.last + 1])
        text = format_rule(rulebase.rules[0], self.vocabulary) if len(rulebase) else ""
        letter = self.letters[origin.origin]
        mutated = tuple(describe_change(chromosome, gene, (column, old, new), self.vocabulary)
                        for gene, column, old, new in origin.mutations)
        return RuleView(number, text, self.notation.format(chromosome[origin.first:origin.last + 1]), letter,
                        self.colour(origin.origin), origin.origin, origin.via, origin.how,
                        self._summary(origin), mutated)

    def _summary(self, origin: RuleOrigin) -> str:
        via = f"from parent #{origin.via.index}" if origin.via is not None else "new in this player"
        operator = f" ({origin.operator})" if origin.operator else ""
        if origin.origin == self.chosen:
            where = {DRAWN: "drawn at random", CUT: f"made by the crossover's cut{operator}",
                     MUTATED: "made by a mutation", EARLIER: "(not followed further)"}[origin.how]
            return f"{via}: {where}"
        if origin.how == EARLIER:
            return f"{via}; already whole in {origin.origin}, the oldest generation followed"
        return f"{via}; first whole in {origin.origin}, {origin.how}{operator}"


def _changes_by_gene(mutations: Sequence[tuple[int, int, int, int]]) -> dict[int, list[tuple[int, int, int]]]:
    changes: dict[int, list[tuple[int, int, int]]] = {}
    for gene, column, old, new in mutations:
        changes.setdefault(gene, []).append((column, old, new))
    return changes


def describe_change(chromosome: Any, gene: int, change: tuple[int, int, int], vocabulary: Vocabulary) -> str:
    """One mutation of `chromosome` in words, e.g. "gene 9, term: Near → Far" (genes counted from 1)."""
    column, old, new = change
    kind = int(chromosome[gene, KIND])
    space = GeneSpace.from_vocabulary(vocabulary)

    def name(value: int) -> str:
        return vocabulary.display(space.value_name(kind, column, value))

    return f"gene {gene + 1}, {FIELD_NAMES[kind][column]}: {name(old)} → {name(new)}"


def short_birth(birth: Birth | None) -> str:
    if birth is None:
        return "not recorded"
    if not birth.parents:
        return "random"
    if birth.elite:
        return "elite"
    words = ["cut" if isinstance(operation, Splice) else "mutation" if isinstance(operation, Mutation)
             else operation.kind for operation in birth.operations]
    return " + ".join(words) or COPY


def describe_birth(birth: Birth | None, generation: int, vocabulary: Vocabulary, chromosome: Any = None) -> str:
    """How an individual came to be, e.g. "one-point crossover of #12 (cut after gene 7) and #40 (cut after
    gene 15), then 2 genes mutated". `chromosome`: the individual's, to name what a mutation changed."""
    if birth is None:
        return "birth not recorded (the run predates lineage records)"
    if not birth.parents:
        return "drawn at random" + (" (generation 0)" if generation == 0 else "")
    if birth.elite:
        return f"elite: #{birth.parents[0]} of generation {generation - 1} copied unchanged"
    parts = []
    for operation in birth.operations:
        if isinstance(operation, Splice):
            cuts = [f"#{parent} (cut{'s' if len(c) > 1 else ''} after gene{'s' if len(c) > 1 else ''} "
                    f"{' and '.join(str(x) for x in c)})" for parent, c in zip(birth.parents, operation.cuts)]
            parts.append(f"{operation.operator} crossover of {' and '.join(cuts)}")
        elif isinstance(operation, Mutation):
            changed = (": " + "; ".join(describe_change(chromosome, gene, (column, old, new), vocabulary)
                                        for gene, column, old, new in operation.changes)
                       if chromosome is not None else "")
            parts.append(f"{plural(len(operation.changes), 'gene')} mutated{changed}")
        else:
            parts.append(operation.kind)
    if not any(isinstance(operation, Splice) for operation in birth.operations):
        parts.insert(0, f"#{birth.parents[0]} of generation {generation - 1}, selected"
                     + ("" if birth.operations else " and passed on unchanged"))
    return ", then ".join(parts)


# ---- as data (the API) ------------------------------------------------------------------------
def tree_data(view: FamilyTreeView) -> dict[str, Any]:
    """The family tree as plain data: the player, every ancestor (newest generation first) and every rule."""
    def place(p: Place | None) -> dict[str, int] | None:
        return None if p is None else {"generation": p.generation, "index": p.index}

    return {
        "player": place(view.chosen),
        "best_so_far": place(view.best),
        "oldest_generation": view.tree.oldest,
        "title": view.title(),
        "ancestors": [
            {**place(a.place), "fitness": a.individual.fitness, "goals": a.individual.goals,
             "evaluations": a.individual.evaluations, "birth": short_birth(a.birth), "how": view.birth_text(a),
             "parents": [place(p) for p in a.parents], "genes": [g + 1 for g in a.genes],
             "origin_of": view.letters.get(a.place), "colour": view.colour(a.place),
             "record": None if a.birth is None else a.birth.to_dict()}
            for row in view.rows() for a in row],
        "rules": [
            {"number": r.number, "text": r.text, "compact": r.genes, "origin": place(r.origin), "via": place(r.via),
             "letter": r.letter, "colour": r.colour, "how": r.how, "summary": r.summary, "mutated": list(r.mutated)}
            for r in view.rules],
        "chromosome": [{"compact": g.compact, "origin": g.origin, "mutated": g.mutated} for g in view.genes()],
        "opponents": [{"generation": g, "opponents": labels} for g, labels in sorted(view.opponents.items())],
    }


def player_quality_line(run_dir: Path, rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    """One line: a run's player re-played on the common fresh starts (app/runs/true_quality.py), in the run's own
    SimpleSoccer games, as `soccer-lab lineage` prints it under the tree."""
    from soccer_lab.app.runs.environments import SIMPLE
    from soccer_lab.app.runs.run import RunSettings
    from soccer_lab.app.runs.outputs import RunFolderError
    from soccer_lab.app.runs.true_quality import simple_soccer_replayer

    try:
        settings = RunSettings.from_dict(RunFolder(run_dir).read_manifest())
    except (RunFolderError, ValueError):
        return "true quality: not re-played (the run's settings cannot be read)"
    if settings.env != SIMPLE:
        return "true quality: not re-played (the run played on rcssserver)"
    return f"true quality of this player: {simple_soccer_replayer(settings.game, vocabulary)(rulebase).text()}"
