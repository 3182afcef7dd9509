"""Mean of maximum, computed exactly, not on a sampled grid (docs/design.md,
"The mean of maximum, exactly"; the chapter, 3.1.4).

After clipping and max aggregation the maximum level M is the largest strength among the
contributing rules, and the set where the aggregate reaches M is the union of the alpha-cuts
at level M of the terms of the rules whose strength equals M. Its mean is the length-weighted
centre of the merged intervals, or, when the set has no length, the mean of its points.
The numba kernel (fuzzy/batched.py) performs the same operations in the same order.
"""

from __future__ import annotations


def merge_intervals(cuts: list[tuple[float, float]]) -> list[list[float]]:
    """The union of closed intervals as disjoint [lo, hi] in increasing order."""
    ordered = sorted(cuts)
    merged: list[list[float]] = [list(ordered[0])]
    for lo, hi in ordered[1:]:
        if lo <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    return merged


def mean_of_maximum(cuts: list[tuple[float, float]]) -> float:
    """Mean of the union of closed intervals `cuts` (each lo <= hi); points count when no interval has length."""
    if not cuts:
        raise ValueError("mean of maximum of an empty set")
    merged = merge_intervals(cuts)
    total = 0.0
    weighted = 0.0
    for lo, hi in merged:
        total += hi - lo
        weighted += (hi - lo) * (lo + hi) * 0.5
    if total > 0.0:
        return weighted / total
    points = 0.0
    for lo, _ in merged:
        points += lo
    return points / len(merged)


def sampled_error_bound(cuts: list[tuple[float, float]], step: float) -> float | None:
    """How far a tool that samples the universe every `step` (midpoint rule, as fuzzylite and
    scikit-fuzzy do) may put the mean of maximum from the exact value; None when the maximum set is
    (nearly) made of points, which sampling cannot see. Each merged interval gains or loses at
    most one sample and its sampled centre moves by at most half a step."""
    merged = merge_intervals(cuts)
    length = sum(hi - lo for lo, hi in merged)
    if length < 2 * step:
        return None
    mean = sum((hi - lo) * (lo + hi) / 2 for lo, hi in merged) / length
    return step / 2 + step * sum(abs((lo + hi) / 2 - mean) for lo, hi in merged) / length
