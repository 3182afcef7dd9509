"""How each individual came to be: its parents in the previous generation and the operations that made
its chromosome from theirs, recorded as data as the GA breeds, so that every child can be rebuilt bit for
bit (`rebuild`) and every gene followed back to where it was drawn (ga/lineage.py).

Two kinds of operation describe the GA's operators:

- `Splice`: the child is stretches of its parents' genes, joined in order. Every cut-and-splice crossover
  is one (one-point, two-point: the chapter, 4), and so is any crossover that takes its parents' genes
  without changing them; it names its operator and each parent's cut points, for the reader.
- `Mutation`: single-allele changes, each (gene, field column, old value, new value).

The operators return these records (ga/crossover.py, ga/mutation.py) and make their children by applying
them, so a record cannot say something other than what happened. A new operator returns a Splice or a
Mutation, or a new Operation class with `apply`, `to_dict` and a `kind` registered in OPERATIONS; `rebuild`
does not change.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, Sequence

import numpy as np

RANDOM, ELITE, COPY = "random", "elite", "copy"


class Operation(Protocol):
    kind: ClassVar[str]

    def apply(self, chromosome: np.ndarray, parents: Sequence[np.ndarray]) -> np.ndarray:
        """The chromosome after this operation (`chromosome`: before it; `parents`: the birth's parents')."""

    def to_dict(self) -> dict[str, Any]: ...


@dataclass(frozen=True)
class Splice:
    """The child is `segments` of its parents joined in order: (parent slot, start, stop), the slot
    indexing the birth's parents. `cuts[p]`: where the operator cut parent p (before the child was cut
    to the maximum length)."""

    kind: ClassVar[str] = "splice"
    operator: str
    cuts: tuple[tuple[int, ...], ...]
    segments: tuple[tuple[int, int, int], ...]

    @classmethod
    def of(cls, operator: str, cuts: Sequence[Sequence[int]], segments: Sequence[tuple[int, int, int]],
           max_length: int) -> "Splice":
        """The splice of `segments`, cut short where the child reaches `max_length` genes."""
        kept, room = [], max_length
        for parent, start, stop in segments:
            stop = min(stop, start + room)
            if stop > start:
                kept.append((parent, start, stop))
                room -= stop - start
        return cls(operator, tuple(tuple(int(c) for c in parent_cuts) for parent_cuts in cuts),
                   tuple((int(p), int(a), int(b)) for p, a, b in kept))

    def apply(self, chromosome: np.ndarray, parents: Sequence[np.ndarray]) -> np.ndarray:
        return np.concatenate([parents[p][start:stop] for p, start, stop in self.segments])

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "operator": self.operator, "cuts": [list(c) for c in self.cuts],
                "segments": [list(s) for s in self.segments]}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "Splice":
        return cls(str(data["operator"]), tuple(tuple(int(c) for c in cuts) for cuts in data["cuts"]),
                   tuple((int(p), int(a), int(b)) for p, a, b in data["segments"]))


@dataclass(frozen=True)
class Mutation:
    """Single-allele changes: (gene, field column, old value, new value), in the order they were drawn."""

    kind: ClassVar[str] = "mutation"
    changes: tuple[tuple[int, int, int, int], ...]

    def apply(self, chromosome: np.ndarray, parents: Sequence[np.ndarray]) -> np.ndarray:
        mutant = chromosome.copy()
        for gene, column, old, new in self.changes:
            if mutant[gene, column] != old:
                raise ValueError(f"gene {gene} field {column} is {mutant[gene, column]}, the mutation recorded {old}")
            mutant[gene, column] = new
        return mutant

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "changes": [list(change) for change in self.changes]}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "Mutation":
        return cls(tuple((int(g), int(c), int(o), int(n)) for g, c, o, n in data["changes"]))


OPERATIONS: dict[str, Any] = {Splice.kind: Splice, Mutation.kind: Mutation}


@dataclass(frozen=True)
class Birth:
    """How an individual entered its generation. `parents`: indices into the previous generation (none for a
    random draw); `operations`: applied in order to the first parent's chromosome (none: a copy of it);
    `elite`: copied as an elite (elitist selection) rather than selected as a parent."""

    parents: tuple[int, ...] = ()
    operations: tuple[Operation, ...] = ()
    elite: bool = False

    @property
    def kind(self) -> str:
        """random, elite, copy (selected, neither crossed nor mutated), or the operations' kinds joined by +
        (e.g. "splice+mutation")."""
        if not self.parents:
            return RANDOM
        if self.elite:
            return ELITE
        return "+".join(operation.kind for operation in self.operations) or COPY

    def with_operation(self, operation: Operation) -> "Birth":
        return Birth(self.parents, (*self.operations, operation), self.elite)

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {}
        if self.parents:
            data["parents"] = list(self.parents)
        if self.operations:
            data["operations"] = [operation.to_dict() for operation in self.operations]
        if self.elite:
            data["elite"] = True
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "Birth":
        operations = []
        for operation in data.get("operations", ()):
            if operation.get("kind") not in OPERATIONS:
                raise ValueError(f"unknown operation {operation.get('kind')!r}")
            operations.append(OPERATIONS[operation["kind"]].from_dict(operation))
        return cls(tuple(int(p) for p in data.get("parents", ())), tuple(operations), bool(data.get("elite", False)))


RANDOM_DRAW = Birth()


def rebuild(birth: Birth, parents: Sequence[np.ndarray]) -> np.ndarray:
    """The child's chromosome from its parents' (`parents[k]` the chromosome of `birth.parents[k]`) and its
    recorded operations. ValueError for a random draw, which has nothing to be rebuilt from."""
    if not birth.parents:
        raise ValueError("a random draw has no parents to rebuild it from")
    if len(parents) != len(birth.parents):
        raise ValueError(f"the birth names {len(birth.parents)} parents, {len(parents)} chromosomes were given")
    chromosome = parents[0]
    for operation in birth.operations:
        chromosome = operation.apply(chromosome, parents)
    return chromosome
