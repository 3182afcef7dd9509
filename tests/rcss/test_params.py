import pytest

from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.rcss.errors import RcssConfigError
from soccer_lab.soccer.rcss.messages import parse_message
from soccer_lab.soccer.rcss.params import ServerParams
from tests.rcss.replay import read_transcript

from .conftest import GOALS


def recorded_server_param() -> dict:
    line = next(l for l in read_transcript(GOALS) if l.text.startswith("(server_param"))
    return parse_message(line.text).values


def test_params_come_from_the_servers_message(transcripts_available):
    params = ServerParams.from_message(recorded_server_param())
    world = params.world
    assert (world.dash_power_rate, world.kick_power_rate, world.player_decay, world.inertia_moment) == (
        0.006, 0.027, 0.4, 5.0)
    assert (world.max_power, params.min_power, world.max_moment, params.min_moment) == (100, -100, 180, -180)
    assert world.kickable_distance == pytest.approx(0.3 + 0.085 + 0.7)
    assert params.synch_mode and params.coach and params.coach_w_referee and params.coach_port == 6001
    params.check_usable()


def test_a_default_server_has_worldconfigs_defaults(transcripts_available):
    """WorldConfig's defaults are rcssserver 19's: the recorded server sent the same physics."""
    assert ServerParams.from_message(recorded_server_param()).world == WorldConfig()
    assert ServerParams().world == WorldConfig()


def test_a_server_with_other_values_is_honoured():
    params = ServerParams.from_message({"dash_power_rate": 0.01, "player_size": 0.5, "maxpower": 80,
                                        "minpower": -20, "unknown_thing": 3})
    world = params.world
    assert world.dash_power_rate == 0.01 and world.player_size == 0.5 and world.ball_size == WorldConfig().ball_size
    assert (world.max_power, params.min_power) == (80, -20)


def test_a_physics_value_the_player_cannot_use_is_one_clear_error():
    with pytest.raises(RcssConfigError, match="server_param holds values the player cannot use: player_decay 0"):
        ServerParams.from_message({"player_decay": 0})


def test_not_in_synch_mode_is_refused():
    with pytest.raises(RcssConfigError, match="synch_mode=true"):
        ServerParams.from_message({"synch_mode": 0}).check_usable()


def test_no_trainer_is_refused():
    with pytest.raises(RcssConfigError, match="without the offline trainer: start it with server::coach=true"):
        ServerParams.from_message({"synch_mode": 1, "coach": 0}).check_usable()


def test_coach_without_referee_is_refused():
    with pytest.raises(RcssConfigError, match="coach_w_referee=true"):
        ServerParams.from_message({"synch_mode": 1, "coach": 1, "coach_w_referee": 0}).check_usable()
