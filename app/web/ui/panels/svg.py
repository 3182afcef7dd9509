"""Small helpers the panels share for drawing membership functions and axes as SVG."""

from __future__ import annotations

import html
import math

from soccer_lab.app.web.ui import style
from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.variable import LinguisticVariable

SQRT_SCALED_UNITS = ("m",)  # distances: a square-root axis gives the near terms room to be read


def escape(text: object) -> str:
    return html.escape(str(text), quote=True)


class Axis:
    """Maps a variable's universe onto [left, right] pixels (square-root scale for distances)."""

    def __init__(self, variable: LinguisticVariable, left: float, right: float):
        self.variable = variable
        self.left = left
        self.right = right
        self.sqrt = variable.unit in SQRT_SCALED_UNITS and variable.minimum >= 0.0

    def _warp(self, x: float) -> float:
        return math.sqrt(x) if self.sqrt else x

    def __call__(self, x: float) -> float:
        lo, hi = self._warp(self.variable.minimum), self._warp(self.variable.maximum)
        x = self.variable.clamp(x)
        return self.left + (self._warp(x) - lo) / (hi - lo) * (self.right - self.left)

    def ticks(self) -> list[float]:
        """Tick positions at the terms' peaks and shoulders, which are the values people talk about."""
        points = {self.variable.minimum, self.variable.maximum}
        for term in self.variable.terms:
            points.update((term.b, term.c))
        return sorted(points)


def term_points(term: Term, axis: Axis, top: float, bottom: float, level: float = 1.0) -> str:
    """SVG polygon points of `term` clipped at `level`, as drawn on `axis` (sampled where the axis bends)."""
    xs = sorted({term.a, term.b, term.c, term.d} | _bend_samples(term, axis))
    height = bottom - top
    points = [f"{axis(term.a):.1f},{bottom:.1f}"]
    points += [f"{axis(x):.1f},{bottom - min(term.membership(x), level) * height:.1f}" for x in xs]
    points.append(f"{axis(term.d):.1f},{bottom:.1f}")
    return " ".join(points)


def _bend_samples(term: Term, axis: Axis) -> set[float]:
    if not axis.sqrt:
        return set()
    samples = 24
    xs = set()
    for lo, hi in ((term.a, term.b), (term.c, term.d)):
        xs.update(lo + (hi - lo) * i / samples for i in range(1, samples))
    return xs


def format_value(value: float, unit: str) -> str:
    suffix = "°" if unit == "deg" else (f" {unit}" if unit else "")
    return f"{value:.1f}{suffix}"


def svg_open(width: float, height: float) -> str:
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="100%" viewBox="0 0 {width:.0f} {height:.0f}" '
        f'style="{style.FONT}; display:block">'
    )
