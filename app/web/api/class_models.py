"""The classroom API's bodies (/api/class, classroom mode only): joining, entries, rounds, knockouts, settings."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, Field, model_validator

from soccer_lab.app.web.api.models import Name, Strict
from soccer_lab.app.web.classroom.settings import ENTRY_MAX_CHARACTERS, MAX_STARTS, ClassSettings
from soccer_lab.app.store import EntryRecord, KnockoutRecord, RoundRecord
from soccer_lab.app.web.classroom.knockout import DEFAULT_BEST_OF, MAX_BEST_OF, champion, rounds_of
from soccer_lab.soccer.config import MAX_TICKS


class JoinRequest(Strict):
    code: str = Field(max_length=100)
    name: str = Field(max_length=1000, description="the display name the class sees (at most 40 characters)")


class TeacherRequest(Strict):
    token: str = Field(max_length=1000)


class SettingsChange(ClassSettings, Strict):
    """The class's settings as the teacher sends them: numbers as JSON numbers."""

    def settings(self) -> ClassSettings:
        return ClassSettings(**self.model_dump())


class VisitorOut(BaseModel):
    name: str
    teacher: bool


class ClassOut(BaseModel):
    address: str  # what students open (and the QR code says)
    join_code: str
    you: VisitorOut
    settings: dict[str, Any]
    playing: bool  # a round is being played
    entries: int
    rounds: int


class EntrySubmit(Strict):
    """A rulebase entered: rule `text`, or a saved rulebase (`rulebase_id`), or a run's best so far (`run_id`).
    A student's entry is under their name; the teacher names theirs (`name`)."""

    text: str | None = Field(None, max_length=ENTRY_MAX_CHARACTERS)
    rulebase_id: int | None = Field(None, ge=1)
    run_id: int | None = Field(None, ge=1)
    name: Name | None = None

    @model_validator(mode="after")
    def _one_source(self) -> "EntrySubmit":
        if sum(value is not None for value in (self.text, self.rulebase_id, self.run_id)) != 1:
            raise ValueError("give exactly one of text, rulebase_id and run_id")
        return self


class EntryOut(BaseModel):
    id: int
    name: str
    source: str
    submitted: str
    mine: bool
    text: str | None  # the rules: the teacher's and the entrant's to read before a round

    @classmethod
    def of(cls, record: EntryRecord, *, mine: bool, readable: bool) -> "EntryOut":
        return cls(id=record.id, name=record.name, source=record.source, submitted=record.submitted, mine=mine,
                   text=record.text if readable else None)


class RoundStart(Strict):
    starts: int | None = Field(None, ge=1, le=MAX_STARTS, description="default: the class's setting")
    seed: int | None = Field(None, ge=0, lt=2**63, description="default: the round's number")


class RoundStarted(BaseModel):
    entries: int
    starts: int
    seed: int
    game: dict[str, Any]


class RoundOut(BaseModel):
    id: int
    created: str
    seed: int
    starts: int
    game: dict[str, Any]
    results: list[dict[str, Any]]
    csv: str  # the table as CSV

    @classmethod
    def of(cls, record: RoundRecord, csv_url: str) -> "RoundOut":
        return cls(**record.to_dict(), csv=csv_url)


class StudentOut(BaseModel):
    id: int
    name: str
    created: str


class KnockoutStart(Strict):
    """A class knockout of every entry (the teacher's)."""

    best_of: int = Field(DEFAULT_BEST_OF, ge=1, le=MAX_BEST_OF, description="matches per tie: an odd number")
    seed: int | None = Field(None, ge=0, lt=2**63, description="the draw's and the matches' seed; default: a "
                                                                 "fresh one, shown and recorded")
    max_ticks: int | None = Field(None, ge=1, le=MAX_TICKS, description="ticks a half at most; default and bound: "
                                                                         "the class's max_run_ticks")


class DrawPlace(BaseModel):
    draw: int  # the place in the seeded draw: 1 first
    entry_id: int
    name: str
    source: str


class KnockoutOut(BaseModel):
    """A knockout: its seeded draw, its ties as played so far (`ties`: round, tie, draw numbers a and b (None:
    a bye), the matches with their seeds and goals (A's, B's), matches won, goals, the winner's draw number
    and what decided it), and its champion once the final is played."""

    id: int
    created: str
    seed: int
    best_of: int
    game: dict[str, Any]
    status: str  # playing, finished, failed, interrupted
    finished: str | None
    error: str | None
    rounds: int
    draw: list[DrawPlace]
    ties: list[dict[str, Any]]
    champion: str | None
    csv: str  # every match as CSV

    @classmethod
    def of(cls, record: KnockoutRecord, csv_url: str) -> "KnockoutOut":
        winner = champion(record)
        return cls(**{**record.to_dict(), "draw": [DrawPlace(**{k: place[k] for k in DrawPlace.model_fields})
                                                   for place in record.draw]},
                   rounds=rounds_of(len(record.draw)), champion=winner["name"] if winner else None, csv=csv_url)
