"""Which premises are provably ordered or exclusive, on every input, as the engines compute them.

Two premises can only be related when they read the same input (same object, same variable:
`Ball is Near` and `Ball is not Far` both read ball_distance). When that object is out of view both
are 0, which keeps `<=` and "never both above 0" true. So the proof is over the variable's universe
(inputs are clamped into it), cut at every term parameter into points and the open intervals
between them:

- at a point, both degrees are computed exactly as the engines compute them;
- inside an open interval no parameter of either term lies, so each degree is exactly 0 there (left
  of its term's a, right of its d), exactly 1 (between its b and c), or a ramp whose value is not
  pinned down. Negation swaps 0 and 1.

`a <= b` is proved when on every piece a is 0 or b is 1 (points: compared exactly); exclusion when on
every piece one of them is 0. A ramp against a ramp is never claimed, even where the real-valued
lines are ordered, because rounding could break the order. Premises of different objects or
variables are never related: the inputs are independent, and one object can be out of view while
the other is seen. In particular nothing is ever constantly 1, so `p or not p` is not simplified.
"""

from __future__ import annotations

from functools import lru_cache

from soccer_lab.fuzzy.rule import Premise
from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.vocabulary import Vocabulary

ZERO, ONE, RAMP = "zero", "one", "ramp"
_NEGATED = {ZERO: ONE, ONE: ZERO, RAMP: RAMP}


class PremiseRelations:
    """`at_most(a, b)`: a's degree never exceeds b's; `exclusive(a, b)`: min(a, b) is always 0
    (`exclusive(a, a)`: a never fires).

    For the lattice computations in fuzzy/strength_form.py each premise seen gets a bit (`bit`), and
    `below(p)` / `exclusive_with(p)` are the bit masks of the premises seen so far that are at most p
    (p included) / exclusive with p."""

    def __init__(self, vocabulary: Vocabulary):
        self._terms = {  # premise term -> (its variable, the Term, the universe)
            name: (kind, variable.term(name), variable.minimum, variable.maximum)
            for kind in vocabulary.premise_variables
            for variable in [vocabulary.variables[kind]]
            for name in variable.term_names
        }
        self._premises: list[Premise] = []
        self._bits: dict[Premise, int] = {}
        self._below: list[int] = []
        self._exclusive: list[int] = []

    def at_most(self, a: Premise, b: Premise) -> bool:
        if a == b:
            return True
        pair = self._same_input(a, b)
        return pair is not None and _at_most(*pair)

    def exclusive(self, a: Premise, b: Premise) -> bool:
        pair = self._same_input(a, b)
        return pair is not None and _exclusive(*pair)

    def bit(self, premise: Premise) -> int:
        """The premise's bit (1 << its number), registering it on first sight."""
        if premise not in self._bits:
            k = len(self._premises)
            self._premises.append(premise)
            self._bits[premise] = 1 << k
            self._below.append(0)
            self._exclusive.append(0)
            for j, other in enumerate(self._premises):
                if self.at_most(other, premise):
                    self._below[k] |= 1 << j
                if self.at_most(premise, other):
                    self._below[j] |= 1 << k
                if self.exclusive(premise, other):
                    self._exclusive[k] |= 1 << j
                    self._exclusive[j] |= 1 << k
        return self._bits[premise]

    def below(self, bit: int) -> int:
        return self._below[bit.bit_length() - 1]

    def exclusive_with(self, bit: int) -> int:
        return self._exclusive[bit.bit_length() - 1]

    def _same_input(self, a: Premise, b: Premise) -> tuple | None:
        """The two premises as the proofs take them, or None when they read different inputs."""
        kind, ta, minimum, maximum = self._terms[a.term]
        if a.object != b.object or self._terms[b.term][0] != kind:
            return None
        return ta, a.negated, self._terms[b.term][1], b.negated, minimum, maximum


# The proofs depend only on the two terms, their negations and the universe: cached across rulebases.
@lru_cache(maxsize=None)
def _at_most(ta: Term, na: bool, tb: Term, nb: bool, minimum: float, maximum: float) -> bool:
    return all((va <= vb) if point else (va == ZERO or vb == ONE)
               for point, va, vb in _pieces(ta, na, tb, nb, minimum, maximum))


@lru_cache(maxsize=None)
def _exclusive(ta: Term, na: bool, tb: Term, nb: bool, minimum: float, maximum: float) -> bool:
    return all((min(va, vb) == 0.0) if point else ZERO in (va, vb)
               for point, va, vb in _pieces(ta, na, tb, nb, minimum, maximum))


def _pieces(ta: Term, na: bool, tb: Term, nb: bool, minimum: float, maximum: float):
    """(is_point, a's degree or class, b's degree or class) over the universe, left to right."""
    cuts = sorted({minimum, maximum, *ta.parameters, *tb.parameters})
    for i, x in enumerate(cuts):
        yield True, _degree(ta, na, x), _degree(tb, nb, x)
        if i + 1 < len(cuts):
            lo, hi = x, cuts[i + 1]
            yield False, _interval_class(ta, na, lo, hi), _interval_class(tb, nb, lo, hi)


def _degree(term: Term, negated: bool, x: float) -> float:
    degree = term.membership(x)  # the engines' own function, on a point of the universe (no clamping needed)
    return 1.0 - degree if negated else degree


def _interval_class(term: Term, negated: bool, lo: float, hi: float) -> str:
    """ZERO, ONE or RAMP for every x in (lo, hi), an interval no parameter of `term` lies in."""
    if hi <= term.a or lo >= term.d:
        kind = ZERO  # x < a or x > d: the membership function returns 0.0
    elif lo >= term.b and hi <= term.c:
        kind = ONE  # b < x < c: it returns 1.0
    else:
        kind = RAMP
    return _NEGATED[kind] if negated else kind
