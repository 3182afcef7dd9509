"""Co-evolution's opponents: a hall of fame of earlier generations' bests (Rosin and Belew's, as Luke's
co-evolved soccer teams faced earlier champions). Generation 0 plays the founder (a fixed player the run
starts from: the built-in demo, or the player given); after each generation its best joins the hall,
unless a member already has its chromosome, and the oldest of them leaves when more than `size` are in it
(the founder stays: the one fixed point that keeps a run from going round in circles). Each generation's
players are scored against `sample` members drawn without replacement with the run's own Generator
(all of them while the hall holds fewer), so one seed fixes the run and the hall is part of the run's
state (ga/state.py, saved in every checkpoint)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from soccer_lab.ga.config import MAX_HALL_SAMPLE, MAX_HALL_SIZE
from soccer_lab.ga.genes import GENE_DTYPE, GENE_WIDTH


@dataclass(frozen=True, eq=False)
class HallMember:
    """A player in the hall: its chromosome and who it is, e.g. "the demo" or "best of generation 3"."""

    chromosome: np.ndarray
    label: str

    def to_dict(self) -> dict[str, Any]:
        return {"chromosome": self.chromosome.tolist(), "label": self.label}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "HallMember":
        return cls(np.array(data["chromosome"], dtype=GENE_DTYPE).reshape(-1, GENE_WIDTH), str(data["label"]))

    def same_player(self, chromosome: np.ndarray) -> bool:
        return self.chromosome.shape == chromosome.shape and bool(np.array_equal(self.chromosome, chromosome))


@dataclass(frozen=True)
class HallOfFame:
    size: int  # generation bests kept (the founder besides)
    sample: int  # members each generation is scored against
    founder: HallMember
    bests: tuple[HallMember, ...] = ()  # oldest first
    drawn: tuple[HallMember, ...] = ()  # the members the last generation was scored against (one may have left)

    def __post_init__(self) -> None:
        if not 1 <= self.size <= MAX_HALL_SIZE:
            raise ValueError(f"hall size: between 1 and {MAX_HALL_SIZE}, not {self.size}")
        if not 1 <= self.sample <= MAX_HALL_SAMPLE:
            raise ValueError(f"hall sample: between 1 and {MAX_HALL_SAMPLE}, not {self.sample}")

    @property
    def members(self) -> tuple[HallMember, ...]:
        return (self.founder, *self.bests)

    def draw(self, rng: np.random.Generator) -> tuple["HallOfFame", list[HallMember]]:
        """The members this generation is scored against (in the hall's order), and the hall that remembers
        them. Draws from `rng` only when there is a choice to make."""
        members = self.members
        if len(members) <= self.sample:
            chosen = list(members)
        else:
            chosen = [members[i] for i in sorted(rng.choice(len(members), size=self.sample, replace=False))]
        return replace(self, drawn=tuple(chosen)), chosen

    def with_best(self, chromosome: np.ndarray, generation: int) -> "HallOfFame":
        """The hall after a generation whose best is `chromosome`."""
        if any(member.same_player(chromosome) for member in self.members):
            return self
        bests = (*self.bests, HallMember(np.array(chromosome, copy=True), f"best of generation {generation}"))
        return replace(self, bests=bests[-self.size:])

    def to_dict(self) -> dict[str, Any]:
        return {"size": self.size, "sample": self.sample, "founder": self.founder.to_dict(),
                "bests": [member.to_dict() for member in self.bests], "drawn": [m.to_dict() for m in self.drawn]}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "HallOfFame":
        return cls(int(data["size"]), int(data["sample"]), HallMember.from_dict(data["founder"]),
                   tuple(HallMember.from_dict(m) for m in data["bests"]),
                   tuple(HallMember.from_dict(m) for m in data["drawn"]))


def founded_hall(founder: np.ndarray, label: str, size: int, sample: int) -> HallOfFame:
    """A hall holding only its founder (generation 0's opponent), as a run starts."""
    return HallOfFame(size, sample, HallMember(np.array(founder, copy=True), label))
