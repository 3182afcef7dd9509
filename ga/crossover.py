"""Crossover for variable-length chromosomes (the chapter, 4): parents may differ in length.

Cut-and-splice (the chapter's one- and two-point): each parent gets its own cut points. Cuts fall
strictly inside a parent (between genes 1..n-1), so every head and tail is non-empty and children
keep at least MIN_LENGTH genes. Children longer than `max_length` are truncated.

Uniform (beyond the chapter, which asks whether "a much more disruptive crossover method, such as
uniform crossover" would matter): uniform crossover swaps positions of equal-length strings, which a
messy chromosome does not have, so it works on rules instead of genes. Each parent is cut into its
rules (a run of premises closed by a consequent; premises after the last consequent form a last,
incomplete segment), the rules are paired by position, and a fair coin gives each pair's two rules to
the two children; a rule of the longer parent without a partner goes to either child by a fair coin.
Every child is made only of whole segments of its parents: their rules in the parents' order, then any
trailing premises it received (kept last, so they never join a rule of the other parent: a child holds
only rules its parents had). It keeps as many segments, from the front, as fit in `max_length` (never
less than one: a segment is never longer than its parent). A child left with fewer than MIN_LENGTH
genes (a lone consequent) is its parent instead. Unlike cut-and-splice it never splits or joins a rule,
however much it shuffles them.

Each operator returns its two children as `Splice` records (ga/provenance.py: which stretch of which
parent, in order, and each parent's cut points); a child's chromosome is its splice applied to the
parents, `splice.apply(a, (a, b))`, so what is recorded is what was done.
"""

from __future__ import annotations

import numpy as np

from soccer_lab.ga.genes import CONSEQUENT, KIND, MIN_LENGTH
from soccer_lab.ga.provenance import Splice

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


def uniform(a: np.ndarray, b: np.ndarray, max_length: int, rng: np.random.Generator) -> tuple[Splice, Splice]:
    """Rule-wise uniform crossover (see above): each rule goes to one child or the other."""
    parents = (a, b)
    spans = (rule_spans(a), rule_spans(b))
    children: tuple[list[tuple[int, int, int]], list[tuple[int, int, int]]] = ([], [])
    for position in range(max(len(spans[A]), len(spans[B]))):
        pair = [(slot, *spans[slot][position]) for slot in (A, B) if position < len(spans[slot])]
        if len(pair) == 1:  # the longer parent's rule without a partner
            children[int(rng.integers(2))].append(pair[0])
            continue
        first = int(rng.integers(2))  # which child gets a's rule
        children[first].append(pair[0])
        children[1 - first].append(pair[1])
    cuts = tuple(tuple(stop for _, stop in parent_spans[:-1]) for parent_spans in spans)
    splices = []
    for slot, segments in zip((A, B), children):
        kept = _joined(segments, parents, max_length)
        if sum(stop - start for _, start, stop in kept) < MIN_LENGTH:  # a lone consequent: the parent instead
            kept = [(slot, 0, len(parents[slot]))]
        splices.append(Splice.of("uniform", cuts, kept, max_length))
    return splices[0], splices[1]


def rule_spans(chromosome: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) of the chromosome's rules, cut after every consequent, then of any trailing premises."""
    ends = [int(end) for end in np.flatnonzero(chromosome[:, KIND] == CONSEQUENT) + 1]
    bounds = [0, *ends] + ([len(chromosome)] if not ends or ends[-1] < len(chromosome) else [])
    return [(start, stop) for start, stop in zip(bounds, bounds[1:]) if stop > start]


def rule_segments(chromosome: np.ndarray) -> list[np.ndarray]:
    """The chromosome cut after every consequent: its rules, then any trailing premises."""
    return [chromosome[start:stop] for start, stop in rule_spans(chromosome)]


def _joined(segments: list[tuple[int, int, int]], parents: tuple[np.ndarray, np.ndarray],
            max_length: int) -> list[tuple[int, int, int]]:
    """The rules in order, then trailing premises; as many from the front as fit in max_length."""
    closed = lambda segment: parents[segment[0]][segment[2] - 1, KIND] == CONSEQUENT
    segments = sorted(segments, key=lambda segment: not closed(segment))  # stable: rules keep their order
    lengths = np.cumsum([stop - start for _, start, stop in segments])
    kept = max(1, int(np.searchsorted(lengths, max_length, side="right")))
    return segments[:kept]


def _cuts(parent: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    if len(parent) < MIN_LENGTH:
        raise ValueError(f"crossover needs parents of at least {MIN_LENGTH} genes, got {len(parent)}")
    return np.sort(rng.integers(1, len(parent), size=count))


CROSSOVERS = {"one-point": one_point, "two-point": two_point, "uniform": uniform}
