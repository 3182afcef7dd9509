"""Our exports in the real readers (Debian's fuzzylite 6 command, pyfuzzylite 8), and our engine's
exact output sets as each reader samples them.

Both readers defuzzify by sampling an output's range at `resolution` midpoints. pyfuzzylite 8 (like
MATLAB and fuzzylite 7) takes the mean of every sample at the maximum; fuzzylite 6 takes the middle
of the first run of samples at the maximum, comparing within 1e-6. `reader_value` applies the
reader's rule to the max-aggregate of our engine's clipped sets: a reader that loaded the export
right gives that value, and its distance from our exact value is the reader's sampling error.
"""

from __future__ import annotations

import functools
import math
import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numba
import numpy as np

from soccer_lab.fuzzy.term import Term

FUZZYLITE = shutil.which("fuzzylite")
FUZZYLITE_EPSILON = 1e-6  # fuzzylite 6 compares scalars within this (fl::fuzzylite::macheps)
NOISE = 1e-9  # comparisons closer than this depend on float rounding order: the oracle does not decide them
DECIMALS = 9


@dataclass(frozen=True)
class Sampling:
    """How a reader defuzzifies one output variable."""

    minimum: float
    maximum: float
    resolution: int
    unfired: float  # its value when no rule fired for it: the default, or NaN
    first_plateau: bool  # fuzzylite 6's mean of maximum
    epsilon: float  # the tolerance of its comparisons (0: exact)
    # The reader's own membership functions by term name, where we can call them: an exact comparison
    # of two samples then sees the very same rounding the reader sees.
    shapes: dict[str, Callable[[np.ndarray], np.ndarray]] = field(default_factory=dict)
    _sampled: dict[str, np.ndarray] = field(default_factory=dict, compare=False, repr=False)

    def samples(self) -> np.ndarray:
        return _samples(self.minimum, self.maximum, self.resolution)

    def membership(self, term: Term) -> np.ndarray:
        """The term at every sample, by the reader's own shape where we have it."""
        if term.name not in self._sampled:
            shape = self.shapes.get(term.name)
            self._sampled[term.name] = (shape(self.samples()) if shape is not None
                                        else _sampled_term(term, self.minimum, self.maximum, self.resolution))
        return self._sampled[term.name]


@functools.cache
def _samples(minimum: float, maximum: float, resolution: int) -> np.ndarray:
    return minimum + (np.arange(resolution) + 0.5) * ((maximum - minimum) / resolution)


@functools.cache
def _sampled_term(term: Term, minimum: float, maximum: float, resolution: int) -> np.ndarray:
    return memberships(term, _samples(minimum, maximum, resolution))


@dataclass(frozen=True)
class EngineView:
    """What a reader made of an exported file: its input order and how it samples each output."""

    inputs: list[str]
    outputs: dict[str, Sampling]


class ReaderError(AssertionError):
    pass


# ---- Debian's fuzzylite command ---------------------------------------------------------------
def _fuzzylite(source: Path, fmt: str, *args: str) -> str:
    result = subprocess.run([FUZZYLITE, "-i", str(source), "-if", fmt, *args, "-decimals", str(DECIMALS)],
                            capture_output=True, text=True, timeout=120)
    said = result.stdout + result.stderr
    # fuzzylite reports errors in the text and still exits 0, and drops rules it cannot read.
    if result.returncode != 0 or "error]" in said:
        raise ReaderError(f"fuzzylite rejected {source.name}: {said.strip()[:2000]}")
    return result.stdout


def fuzzylite_view(text: str, fmt: str, folder: Path) -> EngineView:
    """Load `text` and read back fuzzylite's own FLL of it: input order, ranges, resolutions, defaults."""
    source = folder / f"engine.{fmt}"
    source.write_text(text)
    inputs, outputs, current = [], {}, None
    for line in _fuzzylite(source, fmt, "-of", "fll").splitlines():
        key, _, value = line.strip().partition(": ")
        if key == "InputVariable":
            inputs.append(value)
            current = None
        elif key == "OutputVariable":
            current = outputs.setdefault(value, {})
        elif current is not None and key in ("range", "defuzzifier", "default"):
            current[key] = value.split()
    view = {}
    for name, fields in outputs.items():
        kind, resolution = fields["defuzzifier"]
        if kind != "MeanOfMaximum":
            raise ReaderError(f"fuzzylite reads {name} with {kind}, expected MeanOfMaximum")
        view[name] = Sampling(float(fields["range"][0]), float(fields["range"][1]), int(resolution),
                              float(fields["default"][0]), first_plateau=True, epsilon=FUZZYLITE_EPSILON)
    return EngineView(inputs, view)


def fuzzylite_outputs(text: str, fmt: str, view: EngineView, rows: np.ndarray, folder: Path) -> list[dict[str, float]]:
    """fuzzylite's output values for each row of input values (columns in `view.inputs` order)."""
    source, data = folder / f"engine.{fmt}", folder / "inputs.fld"
    source.write_text(text)
    lines = [" ".join(view.inputs)] + [" ".join(repr(float(v)) for v in row) for row in rows]
    data.write_text("\n".join(lines) + "\n")
    lines = [line.split() for line in _fuzzylite(source, fmt, "-of", "fld", "-d", str(data), "-dheader", "true",
                                                  "-dinputs", "true").splitlines() if line.strip()]
    header, values = lines[0], lines[1:]
    if len(values) != len(rows):
        raise ReaderError(f"fuzzylite answered {len(values)} rows for {len(rows)} inputs")
    return [dict(zip(header, map(float, row))) for row in values]


# ---- pyfuzzylite ---------------------------------------------------------------------------------
def pyfuzzylite_view(engine) -> EngineView:
    outputs = {
        v.name: Sampling(v.minimum, v.maximum, v.defuzzifier.resolution, v.default_value, first_plateau=False,
                         epsilon=0.0, shapes={t.name: t.membership for t in v.terms})
        for v in engine.output_variables
    }
    return EngineView([v.name for v in engine.input_variables], outputs)


def pyfuzzylite_outputs(engine, view: EngineView, rows: np.ndarray) -> list[dict[str, float]]:
    for j, name in enumerate(view.inputs):
        engine.input_variable(name).value = rows[:, j]
    engine.process()
    values = {v.name: np.broadcast_to(v.value, (len(rows),)) for v in engine.output_variables}
    return [{name: float(column[i]) for name, column in values.items()} for i in range(len(rows))]


# ---- our sets through a reader's sampling --------------------------------------------------------
def memberships(term: Term, x: np.ndarray) -> np.ndarray:
    """Term.membership over an array, branch for branch."""
    a, b, c, d = term.parameters
    with np.errstate(divide="ignore", invalid="ignore"):
        rising = (x - a) / (b - a)
        falling = (d - x) / (d - c)
    return np.select([(x < a) | (x > d), x < b, x <= c], [0.0, rising, 1.0], falling)


@numba.njit(cache=True)
def _first_plateau(x, y, epsilon, noise):
    """fuzzylite 6's MeanOfMaximum loop; nan when a comparison falls within `noise` of its threshold."""
    ymax, smallest, largest, plateau = -1.0, x[0], x[-1], False
    for i in range(len(x)):
        gap = y[i] - ymax
        if abs(abs(gap) - epsilon) < noise:
            return math.nan
        if gap >= epsilon:
            ymax, smallest, largest, plateau = y[i], x[i], x[i], True
        elif plateau and abs(gap) < epsilon:
            largest = x[i]
        elif gap <= -epsilon:
            plateau = False
    return 0.5 * (smallest + largest)


INDETERMINATE = None


def reader_value(sets: list[tuple[Term, float]], sampling: Sampling) -> float | None:
    """What the reader outputs for the max-aggregate of the clipped `sets` ((term, strength) pairs);
    INDETERMINATE when that hangs on a comparison closer than float noise."""
    if sampling.epsilon and any(abs(s - sampling.epsilon) < NOISE for _, s in sets):
        return INDETERMINATE
    # fuzzylite 6 triggers a rule only when its strength exceeds 0 by its tolerance
    active = [(t, s) for t, s in sets if s >= sampling.epsilon and s > 0.0]
    if not active:
        return sampling.unfired
    x = sampling.samples()
    shapes = [(sampling.membership(term), strength) for term, strength in active]
    y = np.zeros_like(x)
    for membership, strength in shapes:
        y = np.maximum(y, np.minimum(strength, membership))
    if sampling.first_plateau:
        value = _first_plateau(x, y, sampling.epsilon, NOISE)
        return INDETERMINATE if math.isnan(value) else float(value)
    top = y.max()
    if top <= 0.0:
        return sampling.unfired
    near = np.abs(y - top) < NOISE
    if sampling.shapes:
        # Its own shapes round as the reader does; only our strengths may differ from its activation
        # degrees by rounding: two strengths that close, or a sample at the edge of a cut, are undecided.
        levels = sorted({strength for _, strength in active})
        if any(b - a < NOISE for a, b in zip(levels, levels[1:])):
            return INDETERMINATE
        for membership, strength in shapes:
            if np.any(near & (np.abs(membership - strength) < NOISE) & (membership != strength)):
                return INDETERMINATE
    elif np.any(near & (y != top)):
        return INDETERMINATE
    return float(x[y == top].mean())
