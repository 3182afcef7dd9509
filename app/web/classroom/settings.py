"""What the teacher may change for the class, and the bounds no one changes.

A student's run is bounded so that 30 students cannot starve a 2-core machine: at most `max_run_games`
games (population x generations x (games per evaluation + behaviour seeds): the chapter's 200 x 25 is 5,000;
counting behaviours plays each new chromosome on K more starts), games of at most
`max_run_ticks` ticks, on SimpleSoccer, in one worker process (the machine's cores are the class's), one
run at a time each. docs/reference/limits.md lists every bound and why.
"""

from __future__ import annotations

from dataclasses import replace

from pydantic import BaseModel, ConfigDict, Field

from soccer_lab.app.runs.environments import SIMPLE
from soccer_lab.app.runs.run import RunSettings
from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.soccer.config import MAX_TICKS, SkillSet

ENTRY_MAX_RULES = 100  # an evolved rulebase has at most max_length / 2 (32 by default) rules
ENTRY_MAX_CHARACTERS = 20_000
MAX_STUDENTS = 60  # names in a class: a pupil cannot join a hundred times to get a hundred runs and tabs
DISPLAY_NAME_MAX_LENGTH = 40  # a display name fits a table's cell on a projector
MAX_STARTS = 100  # starts per round: 30 entries x 100 starts is 3,000 games, a few seconds
MAX_ENTRIES = 100  # entries in a round
REQUESTS_PER_SECOND = 10.0  # each visitor's sustained HTTP rate (a page's load makes a handful of requests)
REQUEST_BURST = 60


class ClassSettings(BaseModel):
    """The class's settings (the teacher's to change: PUT /api/class/settings)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    max_run_games: int = Field(5_000, ge=1, le=1_000_000,
                               description="games a student's run plays at most: population x generations x "
                                           "(games per evaluation + behaviour seeds)")
    max_run_ticks: int = Field(1_000, ge=1, le=MAX_TICKS, description="the longest game a student's run may play")
    starts: int = Field(20, ge=1, le=MAX_STARTS, description="starts every entry plays in a round")
    skills: SkillSet = Field("sighted", description="the skill set rounds are played with")

    def check_student_run(self, settings: RunSettings) -> RunSettings:
        """`settings` as a student's run plays them (one worker process), or RunStateError saying which bound
        they pass."""
        if settings.env != SIMPLE:
            raise RunStateError("a student's run plays SimpleSoccer (rcssserver runs are the teacher's)")
        ga, game = settings.ga, settings.game
        # at most: every evaluation's games, and each new chromosome's behaviour games (ga/diversity.py); a match
        # is two halves, and a co-evolution evaluation a match against each opponent drawn
        matches = (2 * settings.coevolve.hall_sample if settings.coevolve is not None
                   else 2 if settings.opponent else 1)
        games = ga.population_size * ga.max_generations * (matches * game.games_per_evaluation + ga.behaviour_seeds)
        if games > self.max_run_games:
            behaviour = f" + {ga.behaviour_seeds} behaviour seeds" if ga.behaviour_seeds else ""
            halves = f"{matches} match halves x " if matches > 1 else ""
            raise RunStateError(
                f"this run would play up to {games:,} games (population {ga.population_size} x {ga.max_generations} "
                f"generations x ({halves}{game.games_per_evaluation} games per evaluation{behaviour})); a student's "
                f"run plays at most {self.max_run_games:,}: make it smaller")
        if game.max_ticks > self.max_run_ticks:
            raise RunStateError(f"max_ticks {game.max_ticks} is over the class's {self.max_run_ticks} for a "
                                "student's run")
        return replace(settings, ga=ga.model_copy(update={"workers": 1}))
