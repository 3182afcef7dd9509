"""The skill sets on the rcssserver side: the client's player acts on what it sees as the SimpleSoccer
engine's does (soccer/skills.py is shared), here one decision on a made-up view."""

import pytest

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.soccer.config import SOCCER_VOCABULARY
from soccer_lab.soccer.rcss.client import PlayerCycle
from soccer_lab.soccer.rcss.messages import SenseBody, parse_message
from soccer_lab.soccer.rcss.params import ServerParams
from soccer_lab.soccer.rcss.player import RcssPlayer

BODY = SenseBody(0, "high", "normal", 0.0, 0.0, 0.0)
# The ball at the player's feet, 10 m beyond the centre mark; facing its own goal, or the goal it attacks.
FACING_OWN_GOAL = "(see 0 ((f c) 10 0) ((g l) 62.5 0) ((b) 0.5 0))"
FACING_GOAL = "(see 0 ((f c) 10 0) ((g r) 62.5 0) ((b) 0.5 0))"


STRIKER = parse_rulebase("if Ball is At then KickTowardGoal High\nif Ball is not At then GoToBall VeryHigh",
                         SOCCER_VOCABULARY)


def decide(skills: str, see: str) -> list[str]:
    return RcssPlayer(STRIKER, ServerParams(), skills=skills).decide(PlayerCycle(BODY, parse_message(see)))


def test_strict_shoots_at_a_goal_behind_it_and_sighted_does_not():
    assert decide("strict", FACING_OWN_GOAL) == ["(kick 85.00 -180.00)"]  # steers by the goal it knows
    assert decide("sighted", FACING_OWN_GOAL) == []  # the goal is out of view: KickTowardGoal does nothing


@pytest.mark.parametrize("skills", ["strict", "assisted", "sighted"])
def test_every_skill_set_shoots_at_a_goal_in_view(skills):
    assert decide(skills, FACING_GOAL) == ["(kick 85.00 0.00)"]


def test_the_player_reports_what_it_sent_and_why_as_the_engine_does():
    """A refused shot is explained on the server as in SimpleSoccer (soccer/outcome.py's words)."""
    player = RcssPlayer(STRIKER, ServerParams(), skills="sighted")
    assert player.last_outcome() is None  # no decision yet
    player.decide(PlayerCycle(BODY, parse_message(FACING_OWN_GOAL)))
    assert player.last_sent is None
    assert player.last_outcome().describe("sighted", SOCCER_VOCABULARY).startswith(
        "KickTowardGoal: no kick, the goal is not in view")
    player.decide(PlayerCycle(BODY, parse_message(FACING_GOAL)))
    assert player.last_sent == "(kick 85.00 0.00)"
    assert player.last_outcome().describe("sighted", SOCCER_VOCABULARY) == (
        "KickTowardGoal: kick 85 toward +0° (the goal's direction)")
