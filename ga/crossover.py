"""Cut-and-splice crossover (the chapter, 4): parents may differ in length, so each gets its own cut points.

Cuts fall strictly inside a parent (between genes 1..n-1), so every head and tail is non-empty and
children keep at least MIN_LENGTH genes. Children longer than `max_length` are truncated.

Each operator returns its two children as `Splice` records (ga/provenance.py: which stretch of which
parent, in order, and each parent's cut points); a child's chromosome is its splice applied to the
parents, `splice.apply(a, (a, b))`, so what is recorded is what was done.
"""

from __future__ import annotations

import numpy as np

from ga.genes import MIN_LENGTH
from ga.provenance import Splice

A, B = 0, 1  # the parents' slots in a splice's segments


def one_point(a: np.ndarray, b: np.ndarray, max_length: int, rng: np.random.Generator) -> tuple[Splice, Splice]:
    """child 1 = head of a + tail of b, child 2 = head of b + tail of a."""
    i, j = _cuts(a, 1, rng)[0], _cuts(b, 1, rng)[0]
    cuts = ((i,), (j,))
    return (Splice.of("one-point", cuts, [(A, 0, i), (B, j, len(b))], max_length),
            Splice.of("one-point", cuts, [(B, 0, j), (A, i, len(a))], max_length))


def two_point(a: np.ndarray, b: np.ndarray, max_length: int, rng: np.random.Generator) -> tuple[Splice, Splice]:
    """The middle segments, between each parent's two cuts, are swapped."""
    i1, i2 = _cuts(a, 2, rng)
    j1, j2 = _cuts(b, 2, rng)
    cuts = ((i1, i2), (j1, j2))
    return (Splice.of("two-point", cuts, [(A, 0, i1), (B, j1, j2), (A, i2, len(a))], max_length),
            Splice.of("two-point", cuts, [(B, 0, j1), (A, i1, i2), (B, j2, len(b))], max_length))


def _cuts(parent: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    if len(parent) < MIN_LENGTH:
        raise ValueError(f"crossover needs parents of at least {MIN_LENGTH} genes, got {len(parent)}")
    return np.sort(rng.integers(1, len(parent), size=count))


CROSSOVERS = {"one-point": one_point, "two-point": two_point}
