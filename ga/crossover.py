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
"""

from __future__ import annotations

import numpy as np

from ga.genes import CONSEQUENT, KIND, MIN_LENGTH


def one_point(a: np.ndarray, b: np.ndarray, max_length: int,
              rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """child 1 = head of a + tail of b, child 2 = head of b + tail of a."""
    i, j = _cuts(a, 1, rng)[0], _cuts(b, 1, rng)[0]
    return (np.concatenate((a[:i], b[j:]))[:max_length],
            np.concatenate((b[:j], a[i:]))[:max_length])


def two_point(a: np.ndarray, b: np.ndarray, max_length: int,
              rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The middle segments, between each parent's two cuts, are swapped."""
    i1, i2 = _cuts(a, 2, rng)
    j1, j2 = _cuts(b, 2, rng)
    return (np.concatenate((a[:i1], b[j1:j2], a[i2:]))[:max_length],
            np.concatenate((b[:j1], a[i1:i2], b[j2:]))[:max_length])


def uniform(a: np.ndarray, b: np.ndarray, max_length: int,
            rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Rule-wise uniform crossover (see above): each rule goes to one child or the other."""
    rules_a, rules_b = rule_segments(a), rule_segments(b)
    children: tuple[list[np.ndarray], list[np.ndarray]] = ([], [])
    for position in range(max(len(rules_a), len(rules_b))):
        pair = [rules[position] for rules in (rules_a, rules_b) if position < len(rules)]
        if len(pair) == 1:  # the longer parent's rule without a partner
            children[int(rng.integers(2))].append(pair[0])
            continue
        first = int(rng.integers(2))  # which child gets a's rule
        children[first].append(pair[0])
        children[1 - first].append(pair[1])
    return tuple(child if len(child) >= MIN_LENGTH else parent  # type: ignore[return-value]
                 for child, parent in zip((_joined(segments, max_length) for segments in children), (a, b)))


def rule_segments(chromosome: np.ndarray) -> list[np.ndarray]:
    """The chromosome cut after every consequent: its rules, then any trailing premises."""
    ends = np.flatnonzero(chromosome[:, KIND] == CONSEQUENT) + 1
    return [segment for segment in np.split(chromosome, ends) if len(segment)]


def _joined(segments: list[np.ndarray], max_length: int) -> np.ndarray:
    """The rules in order, then trailing premises; as many from the front as fit in max_length."""
    segments = sorted(segments, key=lambda segment: segment[-1, KIND] != CONSEQUENT)  # stable: rules keep order
    lengths = np.cumsum([len(segment) for segment in segments])
    kept = max(1, int(np.searchsorted(lengths, max_length, side="right")))
    return np.concatenate(segments[:kept])


def _cuts(parent: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    if len(parent) < MIN_LENGTH:
        raise ValueError(f"crossover needs parents of at least {MIN_LENGTH} genes, got {len(parent)}")
    return np.sort(rng.integers(1, len(parent), size=count))


CROSSOVERS = {"one-point": one_point, "two-point": two_point, "uniform": uniform}
