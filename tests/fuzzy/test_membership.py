"""Membership functions and the soccer vocabulary's terms (fuzzy/data/soccer_vocabulary.json)."""

import pytest

from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.vocabulary import Vocabulary

VOCABULARY = Vocabulary.default()
VARIABLES = list(VOCABULARY.variables.values())


def test_triangle_feet_peak_and_slopes():
    near = VOCABULARY.variables["distance"].term("NEAR")  # (2, 4, 8)
    assert [near.membership(x) for x in (1.9, 2.0, 3.0, 4.0, 6.0, 8.0, 8.1)] == [0.0, 0.0, 0.5, 1.0, 0.5, 0.0, 0.0]


def test_shoulders_hold_one_to_the_universe_ends():
    distance = VOCABULARY.variables["distance"]
    at, very_far = distance.term("AT"), distance.term("VERYFAR")
    assert [at.membership(x) for x in (0.0, 1.0, 1.5, 2.0)] == [1.0, 1.0, 0.5, 0.0]
    assert [very_far.membership(x) for x in (40.0, 50.0, 60.0, 130.0)] == [0.0, 0.5, 1.0, 1.0]
    direction = VOCABULARY.variables["direction"]
    assert direction.term("LEFT180").membership(-180.0) == 1.0
    assert direction.term("LEFT180").membership(-135.0) == 0.5
    assert direction.term("RIGHT180").membership(180.0) == 1.0
    assert (at.kind, very_far.kind, distance.term("NEAR").kind) == ("left shoulder", "right shoulder", "triangle")


def test_inputs_outside_the_universe_are_clamped():
    distance = VOCABULARY.variables["distance"]
    assert distance.fuzzify(500.0)["VERYFAR"] == 1.0
    assert VOCABULARY.variables["direction"].fuzzify(-400.0)["LEFT180"] == 1.0


@pytest.mark.parametrize("variable", VARIABLES, ids=lambda v: v.name)
def test_adjacent_terms_cross_at_one_half(variable):
    for left, right in zip(variable.terms, variable.terms[1:]):
        crossing = (left.c + left.d) / 2
        assert left.membership(crossing) == pytest.approx(0.5)
        assert right.membership(crossing) == pytest.approx(0.5)


@pytest.mark.parametrize("variable", VARIABLES, ids=lambda v: v.name)
def test_every_point_of_the_universe_belongs_to_some_term(variable):
    for i in range(1001):
        x = variable.minimum + (variable.maximum - variable.minimum) * i / 1000
        assert max(variable.fuzzify(x).values()) >= 0.5


def test_alpha_cut_of_triangle_and_shoulder():
    power = VOCABULARY.variables["power"]
    assert power.term("HIGH").alpha_cut(0.5) == (77.5, 92.5)
    assert power.term("VERYLOW").alpha_cut(1.0) == (0.0, 10.0)
    assert power.term("VERYHIGH").alpha_cut(0.5) == (92.5, 100.0)


def test_term_rejects_unordered_vertices():
    with pytest.raises(ValueError, match="need a <= b <= c <= d"):
        Term("BAD", 3.0, 2.0, 4.0, 5.0)
