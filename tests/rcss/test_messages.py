import math

import pytest

from soccer_lab.soccer.rcss.errors import RcssParseError
from soccer_lab.soccer.rcss.messages import (ErrorReply, Hear, Ok, Other, PlayerInit, PlayerParamMessage,
                                             PlayerTypeMessage, See, SeeGlobal, SenseBody, ServerParamMessage, Think,
                                             TrainerInit, WarningReply, parse_message)
from soccer_lab.soccer.rcss.sexp import Quoted, parse
from tests.rcss.replay import read_transcript

from .conftest import ALL_TRANSCRIPTS, received_messages


def test_sexp_reads_atoms_numbers_quoted_and_minus_zero():
    body = parse(b'(see 3 ((f r b) 38.1 -0 -0.27) ((p "12" 1) 2 3))\x00')
    assert body[0] == "see" and body[1] == 3
    assert body[2] == [["f", "r", "b"], 38.1, 0.0, -0.27]
    assert isinstance(body[2][2], (int, float)) and body[2][2] == 0  # -0 is a number, not a name
    assert body[3][0][1] == "12" and isinstance(body[3][0][1], Quoted)


def test_sexp_strips_trailing_newline_and_nul():
    assert parse(b"(ok team_names (team l LabTeam))\n\x00") == ["ok", "team_names", ["team", "l", "LabTeam"]]


@pytest.mark.parametrize("text", ["(see 1 ((b) 1 2)", "(see))", "see 1", "", "(a) (b)"])
def test_sexp_rejects_malformed(text):
    with pytest.raises(RcssParseError):
        parse(text)


def test_every_received_message_in_every_transcript_parses_to_a_known_kind():
    kinds = set()
    for path in ALL_TRANSCRIPTS:
        for line in read_transcript(path):
            if not line.sent:
                message = parse_message(line.text)
                assert not isinstance(message, Other), (path.name, line.number, line.text[:60])
                kinds.add(type(message))
    assert kinds == {
        PlayerInit, TrainerInit, ServerParamMessage, PlayerParamMessage, PlayerTypeMessage, Think, Ok,
        ErrorReply, WarningReply, Hear, SenseBody, See, SeeGlobal,
    }


def test_the_per_cycle_messages_read_as_the_s_expression_reader_reads_them():
    """sense_body, see and see_global are read with regular expressions: every recorded one holds the
    values the s-expression reader finds in it."""
    checked = 0
    for text in received_messages(("(sense_body ", "(see ", "(see_global ")):
        message, tree = parse_message(text), parse(text)
        items = {tuple(str(p) for p in item[0]) if isinstance(item[0], list) else item[0]: item[1:]
                 for item in tree[2:]}
        assert message.time == tree[1]
        if isinstance(message, SenseBody):
            assert (message.view_quality, message.view_width) == tuple(items["view_mode"])
            assert (message.speed, message.speed_direction, message.head_angle) == (*items["speed"],
                                                                                  *items["head_angle"])
            assert message.kick_count == items["kick"][0]
        elif isinstance(message, See):
            assert len(message.objects) == len(items)
            for seen in message.objects:
                numbers = [v for v in items[seen.name] if not isinstance(v, str)]
                values = (seen.direction,) if len(numbers) == 1 else (seen.distance, seen.direction)
                changes = (seen.distance_change, seen.direction_change) if len(numbers) >= 4 else ()
                assert [*values, *changes] == numbers[:len(values) + len(changes)]
        else:
            ball = items[("b",)]
            assert (message.ball.x, message.ball.y, message.ball.vx, message.ball.vy) == tuple(ball[:4])
            for player in message.players:
                values = items[("p", player.team, str(player.unum))]
                assert (player.x, player.y, player.vx, player.vy, player.body, player.neck) == tuple(values[:6])
                assert player.kicked == ("k" in values[6:])
        checked += 1
    assert checked > 1500


@pytest.mark.parametrize("text", ["(see 12 ((f c) 10 0) ((b) 3", "(sense_body 3 (view_mode high normal)",
                                  "(see_global x ((b) 1 2 0 0))", "(see x ((g r) 1 -3))"])
def test_a_malformed_per_cycle_message_is_a_parse_error(text):
    with pytest.raises(RcssParseError):
        parse_message(text)


@pytest.mark.parametrize("read", [lambda see: see.objects, lambda see: see.landmarks(), lambda see: see.ball])
def test_a_see_with_a_malformed_object_is_a_parse_error_when_that_object_is_read(read):
    see = parse_message("(see 4 ((g r) far -3) ((b) near 0))")  # a see is read only as far as it is used
    with pytest.raises(RcssParseError):
        read(see)


def test_hear_player_and_trainer_formats_give_the_same_goal():
    player = parse_message("(hear 78 referee goal_l_1)")
    trainer = parse_message("(hear referee 78 goal_l_1)")
    assert player == trainer == Hear(78, "referee", "goal_l_1")
    assert player.goal == ("l", 1)
    assert parse_message("(hear 12 referee kick_in_r)").goal is None


def test_sense_body_fields():
    body = parse_message(
        "(sense_body 5 (view_mode high normal) (stamina 7835 1 130465) (speed 0.37 1) (head_angle 0) (kick 2) "
        "(dash 3) (turn 1) (say 0) (arm (movable 0) (expires 0) (target 0 0) (count 0)) (focus_point 0 0))"
    )
    assert (body.time, body.view_width, body.speed, body.speed_direction, body.head_angle) == (5, "normal", 0.37, 1, 0)
    assert body.kick_count == 2


def test_see_objects_with_two_or_four_numbers_and_near_objects():
    see = parse_message("(see 78 ((f r b) 38.1 54) ((g r) 9.5 -4 -0.19 -0.2) ((B) 2.2 -160) ((l r) 9.7 68) "
                        "((f r b 50) 40))")
    assert see.find("f r b").distance_change is None
    goal = see.find("g r")
    assert (goal.distance, goal.direction, goal.distance_change, goal.direction_change) == (9.5, -4, -0.19, -0.2)
    assert see.ball is None and not see.find("B").in_view and see.near_ball == see.find("B")
    assert [s.key for s in see.flags] == ["f r b", "g r", "f r b 50"]
    assert see.landmarks() == [("f r b", 38.1, 54.0), ("g r", 9.5, -4.0)]  # those with a distance


def test_a_see_reads_its_ball_and_landmarks_as_its_objects_say():
    """The player reads the ball and the landmarks straight from a see's text: on every recorded see
    they are the objects the full reading gives."""
    checked = 0
    for text in received_messages(("(see ",)):
        see = parse_message(text)
        assert see.ball == see.find("b") and see.near_ball == see.find("B")
        assert see.landmarks() == [(s.key, s.distance, s.direction) for s in see.flags if s.in_view
                                   and not math.isnan(s.distance)]
        checked += 1
    assert checked > 200


def test_see_global_ball_player_and_kick_flag():
    seen = parse_message(
        '(see_global 28 ((g r) 52.5 0) ((g l) -52.5 0) ((b) 2.31434 -17.5169 2.17548 0.71735) '
        '((p "LabTeam" 1) 0.121786 -17.9228 0.0972024 -0.11277 -58 0 k))'
    )
    assert seen.ball.x == 2.31434 and seen.ball.vy == 0.71735
    me = seen.player("LabTeam", 1)
    assert (me.x, me.body, me.kicked) == (0.121786, -58, True)


def test_replies():
    assert parse_message("(init l 1 before_kick_off)") == PlayerInit("l", 1, "before_kick_off")
    assert parse_message("(init ok)") == TrainerInit()
    assert parse_message("(ok check_ball 0 in_field)") == Ok("check_ball", (0, "in_field"))
    assert parse_message("(error illegal_mode)") == ErrorReply("illegal_mode")
    assert parse_message("(warning message_not_null_terminated)") == WarningReply("message_not_null_terminated")


def test_malformed_known_message_names_its_kind():
    with pytest.raises(RcssParseError, match="sense_body"):
        parse_message("(sense_body 5 (speed 0.3))")


def test_a_see_of_nothing_has_its_time_and_no_objects():
    """A player facing off the pitch sees nothing: rcssserver sends the time alone (seen in a full-size run)."""
    see = parse_message("(see 870522)")
    assert see.time == 870522 and see.objects == () and see.ball is None and see.near_ball is None
    assert see.landmarks() == []
