import math
import re
import statistics

import pytest

from soccer_lab.soccer.rcss.localisation import LANDMARKS, Pose, goal_relative, localise
from soccer_lab.soccer.rcss.messages import parse_message
from tests.rcss.replay import read_transcript

from .conftest import GOALS, OUT_OF_PLAY, received_messages


def test_landmarks_follow_the_server_axes():
    assert LANDMARKS["f b 0"] == (0.0, 39.0)  # +y is "bottom"
    assert LANDMARKS["f t r 10"] == (10.0, -39.0)
    assert LANDMARKS["g r"] == (52.5, 0.0)
    assert LANDMARKS["f p r b"] == (36.0, 20.16)
    assert LANDMARKS["f l b 30"] == (-57.5, 30.0)
    assert len(LANDMARKS) == 55


def test_localise_exact_synthetic_view():
    pose = Pose(-15.0, 4.0, 30.0)
    objects = []
    for key in ("f c", "g r", "f p r c", "f t r 10"):
        distance, direction = pose.relative(*LANDMARKS[key])
        objects.append(f"(({key}) {distance!r} {direction!r})")  # repr: the exact numbers
    found = localise(parse_message(f"(see 1 {' '.join(objects)})"))
    assert found.x == pytest.approx(-15.0) and found.y == pytest.approx(4.0) and found.body == pytest.approx(30.0)


def test_localise_needs_two_landmarks_in_view_with_their_distance():
    assert localise(parse_message("(see 1 ((f c) 10 0) ((b) 3 5))")) is None
    assert localise(parse_message("(see 1 ((f c) 10 0) ((F) 1 120) ((f r t 10) 40))")) is None
    assert localise(parse_message("(see 1 ((f c) 10 0) ((f r t 10) 50 4))")) is not None


def test_goal_relative_hand_computed():
    distance, direction = goal_relative(Pose(42.5, 10.0, 0.0))  # goal 10 m ahead and 10 m to the left
    assert distance == pytest.approx(math.hypot(10, 10))
    assert direction == pytest.approx(-45.0)


@pytest.mark.parametrize("path", [GOALS, OUT_OF_PLAY], ids=lambda p: p.name)
def test_localisation_against_see_global(path, transcripts_available):
    position_errors, facing_errors = [], []
    pending = None
    for line in read_transcript(path):
        if line.sent:
            continue
        if line.text.startswith("(see "):
            pending = parse_message(line.text)
        elif line.text.startswith("(see_global") and pending is not None:
            truth = parse_message(line.text).players[0]
            pose = localise(pending)
            position_errors.append(math.hypot(pose.x - truth.x, pose.y - truth.y))
            facing_errors.append(abs((pose.body - truth.body + 180) % 360 - 180))
            pending = None
    assert len(position_errors) > 50
    assert statistics.median(position_errors) < 0.1
    assert max(position_errors) < 0.5
    assert statistics.median(facing_errors) < 1.0  # see_global reports whole degrees


def test_the_see_text_reader_gives_the_general_readings_pose_on_every_recorded_see(transcripts_available):
    """Localisation reads the landmarks' plain decimals straight from a see's text; a number written
    otherwise (here 38.1 as 38.1e0, the same value) sends the see to `See.landmarks()`: both give the
    very same pose on every recorded see."""
    compared = 0
    for text in received_messages(("(see ",)):
        see = parse_message(text)
        if not see.landmarks():
            continue
        name, distance, _ = see.landmarks()[0]
        written = re.search(rf"\(\({name}\) (\S+) ", text).group(1)
        irregular = parse_message(text.replace(f"(({name}) {written} ", f"(({name}) {written}e0 ", 1))
        assert irregular.landmarks() == see.landmarks()
        assert localise(irregular, 10.0) == localise(see, 10.0)
        compared += 1
    assert compared > 200
