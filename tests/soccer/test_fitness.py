import pytest

from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.fitness import fitness, goals_only, robocup_composite, simple_composite

FIELD = WorldConfig().pitch_length  # 105 m, as rcssserver's

TABLE_1 = {1: 0.5, 2: 0.25, 3: 0.1667, 4: 0.125, 5: 0.1, 6: 0.0833, 7: 0.0714, 8: 0.0625, 9: 0.0556, 10: 0.05}


@pytest.mark.parametrize("goals, value", TABLE_1.items())
def test_table_1(goals, value):
    for function in (simple_composite, goals_only, robocup_composite):
        assert round(function(goals, 5, 100, 0.0, FIELD), 4) == value
    assert simple_composite(goals, 5, 100, 0.0, FIELD) == 1 / (2 * goals)


@pytest.mark.parametrize("goals", [1, 3])
def test_a_goal_without_a_kick_still_counts_as_table_1_says(goals):
    # A ball pushed over the line by the player's body: Table 1 gives goals their value whatever moved the ball.
    for function in (simple_composite, goals_only, robocup_composite):
        assert function(goals, 0, 400, 0.0, FIELD) == 1 / (2 * goals)


def test_no_kick_is_worst():
    assert simple_composite(0, 0, 1000, 3.0, FIELD) == 1.0
    assert robocup_composite(0, 0, 1000, 3.0, FIELD) == 1.0
    assert goals_only(0, 12, 1000, 3.0, FIELD) == 1.0


def test_composites_without_goals():
    assert simple_composite(0, 3, 1000, 21.0, FIELD) == pytest.approx(0.5 + 21.0 / 210.0)
    assert robocup_composite(0, 50, 1000, 21.0, FIELD) == pytest.approx(1 - 50 / 2000)


def test_ball_movement_is_measured_against_the_field_played_on():
    # Equation 3's fieldLen: the same closest approach counts for more on a longer field
    assert simple_composite(0, 3, 1000, 21.0, 2 * FIELD) == pytest.approx(0.5 + 21.0 / 420.0)
    assert simple_composite(0, 3, 1000, 21.0, FIELD) > simple_composite(0, 3, 1000, 21.0, 2 * FIELD)


def test_unknown_fitness_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown fitness 'fast'"):
        fitness("fast", 1, 1, 1, 0.0, FIELD)
