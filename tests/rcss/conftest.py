"""Transcripts recorded from a real rcssserver 19 (copied here from the team's shared recordings, with
their NOTES.md) and a player rulebase for replays."""

from __future__ import annotations

from pathlib import Path
from typing import Iterator

import pytest

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from tests.rcss.replay import Line, read_transcript, with_fresh_start

VOCABULARY = Vocabulary.default()

TRANSCRIPTS = Path(__file__).parent / "transcripts"
GOALS = TRANSCRIPTS / "trial_goals.txt"
OUT_OF_PLAY = TRANSCRIPTS / "trial_out_of_play.txt"
ALL_TRANSCRIPTS = sorted(TRANSCRIPTS.glob("*.txt")) + sorted((TRANSCRIPTS / "extra").glob("*.txt"))


def received_messages(starting: tuple[str, ...] = ("",)) -> Iterator[str]:
    """The text of every message the server sent in every transcript (only those starting so, if given)."""
    for path in ALL_TRANSCRIPTS:
        for line in read_transcript(path):
            if not line.sent and line.text.startswith(starting):
                yield line.text

CHASER = """
if Ball is not At then GoToBall High
if Ball is At then KickTowardGoal VeryHigh
"""


def without_error_probes(lines: list[Line]) -> list[Line]:
    """The recordings start with deliberately bad commands; our client sends none, so drop their replies."""
    return [line for line in lines if line.sent or not line.text.startswith("(error")]


def player_thinks(lines: list[Line]) -> int:
    return sum(1 for line in lines if not line.sent and line.role == "P" and line.text == "(think)")


@pytest.fixture(scope="session")
def transcripts_available() -> None:
    if not GOALS.exists():
        pytest.skip(f"rcssserver transcripts not found in {TRANSCRIPTS}")


@pytest.fixture
def goals_lines(transcripts_available) -> list[Line]:
    """The goals recording, as our client (starting each trial fresh) meets it."""
    return with_fresh_start(without_error_probes(read_transcript(GOALS)))


@pytest.fixture
def out_of_play_lines(transcripts_available) -> list[Line]:
    return with_fresh_start(without_error_probes(read_transcript(OUT_OF_PLAY)))


@pytest.fixture(scope="session")
def chaser():
    return parse_rulebase(CHASER, VOCABULARY)
