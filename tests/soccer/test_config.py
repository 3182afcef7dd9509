import pytest
from pydantic import ValidationError

from soccer_lab.soccer.config import GameConfig, WorldConfig


def test_defaults_are_rcssserver_and_chapter_values():
    world = WorldConfig()
    assert world.kickable_distance == pytest.approx(1.085)
    assert (world.ball_decay, world.player_decay, world.inertia_moment) == (0.94, 0.4, 5.0)
    game = GameConfig()
    assert (game.max_ticks, game.goal_cap, game.idle_ticks, game.fitness) == (1000, 10, 100, "simple-composite")
    assert GameConfig.model_validate(game.model_dump()) == game  # publishable as a dict and back


@pytest.mark.parametrize("bad", [{"max_ticks": 0}, {"fitness": "fast"}, {"idle_distance": -1}, {"turbo": True}])
def test_bad_game_config_is_rejected(bad):
    with pytest.raises(ValidationError):
        GameConfig(**bad)


def test_goal_must_fit_the_pitch():
    with pytest.raises(ValidationError, match="goal_width"):
        WorldConfig(goal_width=70.0)
