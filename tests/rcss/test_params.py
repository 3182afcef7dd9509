import pytest

from soccer.rcss.errors import RcssConfigError
from soccer.rcss.messages import parse_message
from soccer.rcss.params import ServerParams
from soccer.rcss.transcript import read_transcript

from .conftest import GOALS


def test_params_come_from_the_servers_message(transcripts_available):
    line = next(l for l in read_transcript(GOALS) if l.text.startswith("(server_param"))
    params = ServerParams.from_message(parse_message(line.text).values)
    assert (params.dash_power_rate, params.kick_power_rate, params.player_decay, params.inertia_moment) == (
        0.006, 0.027, 0.4, 5.0)
    assert params.kickable_distance == pytest.approx(0.3 + 0.085 + 0.7)
    assert params.synch_mode and params.coach and params.coach_w_referee
    params.check_usable()


def test_a_server_with_other_values_is_honoured():
    params = ServerParams.from_message({"dash_power_rate": 0.01, "player_size": 0.5, "unknown_thing": 3})
    assert params.dash_power_rate == 0.01 and params.player_size == 0.5 and params.ball_size == 0.085


def test_not_in_synch_mode_is_refused():
    with pytest.raises(RcssConfigError, match="synch_mode=true"):
        ServerParams.from_message({"synch_mode": 0}).check_usable()


def test_coach_without_referee_is_refused():
    with pytest.raises(RcssConfigError, match="coach_w_referee=true"):
        ServerParams.from_message({"synch_mode": 1, "coach": 1, "coach_w_referee": 0}).check_usable()
