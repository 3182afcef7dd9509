"""A rule's strength as a max of mins of its premises (its disjunctive normal form), to prove two
antecedents equal or ordered on every input.

The engines fold a rule's premises left to right with min (AND) and max (OR). min and max only ever
return one of their operands, and floats in [0, 1] are totally ordered, so the lattice laws of a
chain hold bit for bit: commutativity, associativity, idempotence (`x and x = x`), absorption
(`x or (x and y) = x`) and distributivity. Folding a premise at a time, the strength is exactly

    max over terms T of (min over the premises in T)

where AND adds its premise to every term and OR adds a term of its own, so a fold of n premises has
at most n terms. Within a term, a premise b is dropped when another premise a <= b (then
min(a, b) = a), and the term is dropped when two of its premises are exclusive (its min is 0, and
max with 0 changes nothing since degrees are >= 0); a term whose min never exceeds another term's is
dropped (absorption). The relations come from fuzzy/premise_relations.py. No term is ever constantly
1: a premise about an unseen object is 0, negated or not.

`at_most` is a sufficient test (a min is below a max of mins if it is below one of them; it is
below another min if every premise of that one has a premise of its own below it), so True is a
proof and False only means "not proved". Terms are bit masks of the premises' bits in one
PremiseRelations: compare only forms made with the same one.
"""

from __future__ import annotations

from dataclasses import dataclass

from soccer_lab.fuzzy.premise_relations import PremiseRelations
from soccer_lab.fuzzy.rule import AND, Rule


@dataclass(frozen=True)
class StrengthForm:
    terms: tuple[int, ...]  # each a bit mask of premises; empty: the rule never fires
    relations: PremiseRelations

    @classmethod
    def of(cls, rule: Rule, relations: PremiseRelations) -> "StrengthForm":
        terms = [relations.bit(rule.premises[0])]
        for connector, premise in zip(rule.connectors, rule.premises[1:]):
            bit = relations.bit(premise)
            if connector == AND:
                terms = [term | bit for term in terms]
            else:
                terms.append(bit)
        reduced = [term for term in (_reduced_term(t, relations) for t in terms) if term]
        return cls(tuple(_absorbed(reduced, relations)), relations)

    @property
    def never_fires(self) -> bool:
        return not self.terms

    def at_most(self, other: "StrengthForm") -> bool:
        """Proved: this strength never exceeds `other`'s, on any input."""
        return all(any(_term_at_most(t, u, self.relations) for u in other.terms) for t in self.terms)

    def equals(self, other: "StrengthForm") -> bool:
        """Proved: the two strengths are the same float on every input."""
        return self.at_most(other) and other.at_most(self)


def _bits(mask: int):
    while mask:
        low = mask & -mask
        yield low
        mask ^= low


def _term_at_most(t: int, u: int, relations: PremiseRelations) -> bool:
    """min(t) <= min(u): every premise of u has a premise of t below it."""
    return all(t & relations.below(b) for b in _bits(u))


def _reduced_term(term: int, relations: PremiseRelations) -> int:
    """The term without premises another of its premises lies below; 0 when it is always 0.
    Each premise dropped is above one still kept when it is dropped, so the min is unchanged."""
    if any(term & relations.exclusive_with(a) for a in _bits(term)):
        return 0
    kept = term
    for b in _bits(term):
        lower = kept & relations.below(b) & ~b
        # of two premises below each other (the same function), the lower bit stays
        if any(not (b < a and b & relations.below(a)) for a in _bits(lower)):
            kept &= ~b
    return kept


def _absorbed(terms: list[int], relations: PremiseRelations) -> list[int]:
    """The terms without those another kept term lies above (of two equal ones, the first stays).
    Each term dropped is below one still kept when it is dropped, so the max is unchanged."""
    kept = list(range(len(terms)))
    for i, t in enumerate(terms):
        if any(j != i and _term_at_most(t, terms[j], relations)
               and not (i < j and _term_at_most(terms[j], t, relations)) for j in kept):
            kept.remove(i)
    return [terms[i] for i in kept]
