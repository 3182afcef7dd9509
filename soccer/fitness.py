"""The three fitness functions of the chapter, 5.2 (Equations 1-3; lower is better, 1.0 = the ball was
never kicked). Each takes the game's counts and the length of the field it was played on.

Goals decide first. The equations list their cases as "kicks = 0", "kicks > 0", "goals > 0", which
overlap for a goal scored without a kick (a ball pushed over the line by the player's body: in
SimpleSoccer, as on rcssserver, a dashing player shoves the ball it runs into). The chapter settles
it in 5.2.3: "all fitness functions assign discrete values for goal-scoring, depending upon the number
of goals scored" (Table 1), and 1.0 "indicates no ball movement". So a goal counts as 1 / (2 x goals)
whether or not a kick scored it (about 1% of scoring games in an evolving population are such pushes)."""

from __future__ import annotations

from typing import Callable

WORST_FITNESS = 1.0


def goals_fitness(goals: int) -> float:
    """1 / (2 x goals): the chapter's Table 1 (0.5, 0.25, 0.1667, ..., 0.05 for 1..10 goals)."""
    return 1.0 / (2 * goals)


def simple_composite(goals: int, kicks: int, ticks: int, min_ball_goal_distance: float, field_length: float) -> float:
    if goals > 0:
        return goals_fitness(goals)
    if kicks == 0:
        return WORST_FITNESS
    # Equation 3: 0.5 + dist / (2 x fieldLen), dist the ball's closest approach to the goal
    return 0.5 + min_ball_goal_distance / (2.0 * field_length)


def goals_only(goals: int, kicks: int, ticks: int, min_ball_goal_distance: float, field_length: float) -> float:
    return goals_fitness(goals) if goals > 0 else WORST_FITNESS


def robocup_composite(goals: int, kicks: int, ticks: int, min_ball_goal_distance: float, field_length: float) -> float:
    if goals > 0:
        return goals_fitness(goals)
    if kicks == 0:
        return WORST_FITNESS
    return 1.0 - kicks / (2 * ticks)


FITNESS_FUNCTIONS: dict[str, Callable[[int, int, int, float, float], float]] = {
    "simple-composite": simple_composite,
    "goals-only": goals_only,
    "robocup-composite": robocup_composite,
}


def fitness(name: str, goals: int, kicks: int, ticks: int, min_ball_goal_distance: float, field_length: float) -> float:
    try:
        function = FITNESS_FUNCTIONS[name]
    except KeyError:
        raise ValueError(f"unknown fitness {name!r}; expected one of {', '.join(FITNESS_FUNCTIONS)}") from None
    return function(goals, kicks, ticks, min_ball_goal_distance, field_length)
