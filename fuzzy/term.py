"""A linguistic term: a trapezoidal membership function (triangles and shoulders are special cases)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Term:
    """Membership 0 below `a`, rising to 1 at `b`, 1 up to `c`, falling to 0 at `d`.

    A triangle has b == c; a left shoulder has a == b (1 from the universe's lower end);
    a right shoulder has c == d. One shape for all keeps the scalar path and the numba
    kernel on the same four numbers per term.
    """

    name: str
    a: float
    b: float
    c: float
    d: float

    def __post_init__(self) -> None:
        if not (self.a <= self.b <= self.c <= self.d):
            raise ValueError(f"term {self.name}: need a <= b <= c <= d, got {self.parameters}")

    @property
    def parameters(self) -> tuple[float, float, float, float]:
        return (self.a, self.b, self.c, self.d)

    @property
    def kind(self) -> str:
        """'triangle', 'trapezoid', 'left shoulder' or 'right shoulder' (for display and export)."""
        if self.a == self.b and self.b != self.d:
            return "left shoulder"
        if self.c == self.d and self.a != self.c:
            return "right shoulder"
        return "triangle" if self.b == self.c else "trapezoid"

    def membership(self, x: float) -> float:
        return trapezoid_membership(x, self.a, self.b, self.c, self.d)

    def alpha_cut(self, level: float) -> tuple[float, float]:
        """The interval where membership >= level (0 < level <= 1)."""
        return alpha_cut(level, self.a, self.b, self.c, self.d)


def trapezoid_membership(x: float, a: float, b: float, c: float, d: float) -> float:
    # fuzzy/batched.py compiles this very function (and alpha_cut) with numba, so the scalar path
    # and the kernels agree bit for bit.
    if x < a or x > d:
        return 0.0
    if x < b:
        return (x - a) / (b - a)
    if x <= c:
        return 1.0
    return (d - x) / (d - c)


def alpha_cut(level: float, a: float, b: float, c: float, d: float) -> tuple[float, float]:
    return (a + level * (b - a), d - level * (d - c))
