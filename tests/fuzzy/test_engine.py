"""The scalar reference engine against hand-computed examples (docs/reference/rules.md)."""

import pytest

from soccer_lab.fuzzy.defuzzifier import mean_of_maximum, sampled_error_bound
from soccer_lab.fuzzy.engine import Engine
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

VOCABULARY = Vocabulary.default()


def infer(text, **inputs):
    return Engine(parse_rulebase(text, VOCABULARY), VOCABULARY).infer(inputs)


BALL_3 = dict(ball_distance=3.0, ball_direction=0.0)  # Near 0.5, VeryNear 0.5, Far 0, Straight 1
GOAL_20 = dict(goal_distance=20.0, goal_direction=0.0)  # Near 0, MediumDistant 0.5, SlightlyFar 0.5


def test_premise_degrees_and_negation():
    result = infer("if Ball is Near or Ball is not Far or Ball is not Straight then Dash", **BALL_3)
    assert result.premise_degrees == [[0.5, 1.0, 0.0]]


def test_unseen_object_gives_zero_even_when_negated():
    result = infer("if Goal is not Far or Goal is Near then Dash\nif Ball is Near then Turn", **BALL_3)
    assert result.premise_degrees[0] == [0.0, 0.0]
    assert result.strengths == [0.0, 0.5]
    assert result.selected.action == "TURN"


def test_strict_left_to_right_grouping():
    # (Near or not Far) and Goal Near = (0.5 or 1) and 0 = 0; with AND-precedence it would be 0.5
    result = infer("if Ball is Near or Ball is not Far and Goal is Near then Dash", **BALL_3, **GOAL_20)
    assert result.strengths == [0.0]
    # ((1 and 1) or 0) and 0 = 0; with AND-precedence (1 and 1) or (0 and 0) = 1
    result = infer("if Ball is Straight and Ball is not Far or Goal is Near and Goal is At then Dash",
                   **BALL_3, **GOAL_20)
    assert result.strengths == [0.0]
    # (0 and 1) or 0.5 = 0.5; ((0.5 or 0) and 0.5) = 0.5
    result = infer("if Goal is Near and Ball is Straight or Goal is MediumDistant then Dash\n"
                   "if Ball is VeryNear or Goal is At and Goal is SlightlyFar then Dash", **BALL_3, **GOAL_20)
    assert result.strengths == [0.5, 0.5]


@pytest.mark.parametrize(
    "cuts, expected",
    [
        ([(10.0, 20.0)], 15.0),  # plateau
        ([(0.0, 10.0), (20.0, 40.0)], (10 * 5 + 20 * 30) / 30),  # union: length-weighted centre
        ([(0.0, 10.0), (5.0, 20.0)], 10.0),  # overlapping intervals merge
        ([(5.0, 5.0), (15.0, 15.0)], 10.0),  # points only: mean of the points
        ([(5.0, 5.0), (10.0, 20.0)], 15.0),  # a point has no weight beside an interval
        ([(-180.0, -180.0), (180.0, 180.0)], 0.0),  # Left180 and Right180 at level 1 average to 0
    ],
)
def test_mean_of_maximum_exact(cuts, expected):
    assert mean_of_maximum(cuts) == pytest.approx(expected)


def test_mean_of_maximum_of_empty_set_is_an_error():
    with pytest.raises(ValueError):
        mean_of_maximum([])


def test_clipping_plateau_shoulder_and_peak():
    # Near = 0.5: High clipped at 0.5 -> plateau [77.5, 92.5] -> 85; VeryHigh (shoulder) -> [92.5, 100]
    assert infer("if Ball is Near then Dash High", **BALL_3).selected.parameters == {"power": 85.0}
    assert infer("if Ball is Near then Dash VeryHigh", **BALL_3).selected.parameters == {"power": 96.25}
    # Straight = 1: a triangle at level 1 is its peak; VeryLow at 1 is [0, 10]
    assert infer("if Ball is Straight then Turn Right", **BALL_3).selected.parameters == {"direction": 45.0}
    assert infer("if Ball is Straight then Dash VeryLow", **BALL_3).selected.parameters == {"power": 5.0}


def test_only_the_strongest_sets_of_an_action_count():
    text = "if Ball is Straight then Kick Left Low\nif Ball is Near then Kick Right High"
    result = infer(text, **BALL_3)
    assert result.selected.parameters == {"direction": -45.0, "power": 25.0}
    assert result.selected.support == 1.0


def test_equal_strength_sets_are_unioned():
    text = "if Ball is Straight then Turn Left180\nif Ball is Straight then Turn Right180"
    assert infer(text, **BALL_3).selected.parameters == {"direction": 0.0}  # the documented quirk
    text = "if Ball is Near then Dash VeryLow\nif Ball is VeryNear then Dash High"
    # both at 0.5: VeryLow -> [0, 17.5], High -> [77.5, 92.5]; centre (17.5 * 8.75 + 15 * 85) / 32.5
    expected = (17.5 * 8.75 + 15 * 85) / 32.5
    assert infer(text, **BALL_3).selected.parameters["power"] == pytest.approx(expected)


def test_null_and_unused_fields():
    # Null power: default 55; Turn's power is kept but ignored; DoNothing has no parameters
    assert infer("if Ball is Straight then Kick Left", **BALL_3).selected.parameters == {"direction": -45.0,
                                                                                     "power": 55.0}
    assert infer("if Ball is Straight then Kick", **BALL_3).selected.parameters == {"direction": 0.0, "power": 55.0}
    assert infer("if Ball is Straight then Turn Left [power High]", **BALL_3).selected.parameters == {"direction": -45.0}
    assert infer("if Ball is Straight then DoNothing [power High]", **BALL_3).selected.parameters == {}


def test_tie_goes_to_the_action_whose_strongest_rule_comes_first():
    text = (
        "if Ball is Near then Turn Left\n"  # 0.5
        "if Ball is Straight then Kick Right High\n"  # 1.0 (Kick reaches 1 first, at rule 1)
        "if Ball is not Far then Turn Right"  # 1.0 (Turn reaches 1 at rule 2)
    )
    result = infer(text, **BALL_3)
    assert [(a.action, a.support, a.first_rule) for a in result.fired] == [("KICK", 1.0, 1), ("TURN", 1.0, 2)]
    assert result.selected.action == "KICK"


def test_no_rule_fired():
    result = infer("if Ball is Far then Kick\nif Goal is Near then Dash", **BALL_3)
    assert result.no_rule_fired and result.selected is None and result.fired == []
    assert result.strengths == [0.0, 0.0]


def test_sampled_error_bound():
    assert sampled_error_bound([(10.0, 20.0)], 0.1) == pytest.approx(0.05)
    assert sampled_error_bound([(5.0, 5.0), (15.0, 15.1)], 0.1) is None  # points: sampling cannot see them
    # two intervals of length 10 centred 20 apart: each may weigh one sample more or less
    assert sampled_error_bound([(0.0, 10.0), (20.0, 30.0)], 0.1) == pytest.approx(0.05 + 0.1 * 20 / 20)
