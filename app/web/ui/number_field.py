"""A number the user types, shown exactly as the server reads it.

viser's number input keeps its own text: after "abc", or an emptied field, it shows nothing while the
server still holds the last number it received, and a Start would silently use that. So numbers are
typed into a text input that the server reads on every change: the field always shows what the server
has, the server either uses that number or refuses with a line under the field naming the limit.

    seed = NumberField(gui, "Seed", 1, minimum=0, integer=True)
    seed.value          # the number, or FieldError("Seed: expected a whole number ≥ 0, got 'abc'")
    seed.value = 7      # shown at once
"""

from __future__ import annotations

import math
from typing import Any, Callable

import annotated_types
import viser

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape


class FieldError(ValueError):
    """A field holds no usable number: the message names the field and what it needs."""


class NumberField:
    """`minimum`/`maximum`: the bounds, each excluded itself when `open_minimum`/`open_maximum`. `optional`:
    the field may be left empty (its value is then None; its label or hint says what that means)."""

    def __init__(self, gui: viser.GuiApi, label: str, initial: float | None, *, minimum: float | None = None,
                 maximum: float | None = None, open_minimum: bool = False, open_maximum: bool = False,
                 integer: bool = False, hint: str | None = None, on_change: Callable[[float], None] | None = None,
                 optional: bool = False):
        self.label = label
        self.optional = optional
        self.minimum, self.maximum, self.integer = minimum, maximum, integer
        self.open_minimum, self.open_maximum = open_minimum, open_maximum
        self.text = gui.add_text(label, _format(initial, integer), hint=hint or f"{label}: {self.needs()}")
        self.problem_html = gui.add_html("")
        self._value: float | None = initial

        @self.text.on_update
        def _(_: viser.GuiEvent) -> None:
            if self._read() is None and on_change is not None:
                on_change(self._value)

    @classmethod
    def for_field(cls, gui: viser.GuiApi, label: str, field: Any, **kwargs: Any) -> "NumberField":
        """A field for a pydantic model field: its default, its bounds, whole or not."""
        bounds: dict[str, Any] = {}
        for constraint in field.metadata:
            if isinstance(constraint, annotated_types.Ge):
                bounds["minimum"] = constraint.ge
            elif isinstance(constraint, annotated_types.Gt):
                bounds.update(minimum=constraint.gt, open_minimum=True)
            elif isinstance(constraint, annotated_types.Le):
                bounds["maximum"] = constraint.le
            elif isinstance(constraint, annotated_types.Lt):
                bounds.update(maximum=constraint.lt, open_maximum=True)
        integer = isinstance(field.default, int) and not isinstance(field.default, bool)
        return cls(gui, label, field.default, integer=integer, **bounds, **kwargs)

    @property
    def value(self) -> float | None:
        """The number shown (None: an optional field left empty); FieldError when the field holds none the
        server can use."""
        problem = self._read()
        if problem is not None:
            raise FieldError(problem)
        return self._value

    @value.setter
    def value(self, number: float | None) -> None:
        self._value = number
        self.text.value = _format(number, self.integer)
        self._show(None)

    @property
    def problem(self) -> str | None:
        return self._read()

    @property
    def visible(self) -> bool:
        return self.text.visible

    @visible.setter
    def visible(self, shown: bool) -> None:
        self.text.visible = shown
        self.problem_html.visible = shown

    def needs(self) -> str:
        """What the field takes, e.g. "a whole number ≥ 2 and ≤ 20000"."""
        kind = "a whole number" if self.integer else "a number"
        low = "" if self.minimum is None else f"{'>' if self.open_minimum else '≥'} {_format(self.minimum, self.integer)}"
        high = "" if self.maximum is None else f"{'<' if self.open_maximum else '≤'} {_format(self.maximum, self.integer)}"
        return " ".join([kind, " and ".join(part for part in (low, high) if part)]).strip()

    def _read(self) -> str | None:
        """Read the text: None and the value kept when it is a number within bounds, else the problem."""
        typed = self.text.value.strip()
        if self.optional and not typed:
            self._value = None
            self._show(None)
            return None
        try:  # a whole number as typed: a 19-digit seed loses its last digits as a float
            number = int(typed) if self.integer and typed.lstrip("+-").isdigit() else float(typed)
        except ValueError:
            number = math.nan
        finite = isinstance(number, int) or math.isfinite(number)  # math.isfinite overflows on a huge int
        if not (finite and (not self.integer or number == int(number)) and self._within(number)):
            problem = f"{self.label}: expected {self.needs()}, got {typed!r}"
        else:
            problem = None
            self._value = int(number) if self.integer else number
        self._show(problem)
        return problem

    def _within(self, number: float) -> bool:
        if self.minimum is not None and (number < self.minimum or (self.open_minimum and number == self.minimum)):
            return False
        return self.maximum is None or not (number > self.maximum or (self.open_maximum and number == self.maximum))

    def _show(self, problem: str | None) -> None:
        content = "" if problem is None else (
            f'<div class="field-problem" style="{style.FONT}; font-size:{style.SMALL_FONT_SIZE + 1}px; '
            f'color:{style.ERROR}; margin:-4px 0 4px">{escape(problem)}</div>')
        if self.problem_html.content != content:
            self.problem_html.content = content


def _format(number: float | None, integer: bool) -> str:
    if number is None:
        return ""
    if integer:
        return str(int(number))
    return f"{number:g}"
