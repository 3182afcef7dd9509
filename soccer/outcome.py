"""What the player did in the world after its fuzzy decision, in words: the skill's body command and why
it gave that command (soccer/skills.py reports both every tick, in SimpleSoccer and on rcssserver).

    Outcome("KICKTOWARDGOAL", NONE, 0.0, 0.0, GOAL_OUT_OF_VIEW).describe("sighted", vocabulary)
    -> "KickTowardGoal: no kick, the goal is not in view (sighted skills: the player knows where the goal is only while it sees it)"

Also the game's end reasons and the skill sets, each in one sentence, for the same audience.
"""

from __future__ import annotations

from dataclasses import dataclass

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.skills import (ACTED, AT_BALL, BALL_OUT_OF_VIEW, DASH, FETCHING, GOAL_OUT_OF_VIEW, HUNT_BALL,
                                      HUNT_LAST_SEEN, KICK, NO_DASH_NEEDED, NOT_KICKABLE, NOTHING, TURN, TURN_FIRST)

SKILL_SETS = {
    "strict": "each skill does only its own thing: a kick happens only with the ball within reach (1.085 m), "
              "otherwise nothing, as on the real server",
    "assisted": "a kicking skill first runs to the ball when it is out of reach, so one kicking rule is a whole striker",
    "sighted": "strict, and the player knows where the goal is only while it sees it (±45°): "
               "KickTowardGoal, DribbleTowardGoal and RunTowardGoal do nothing with the goal out of view",
}

END_REASONS = {
    "running": "the game is on",
    "max-ticks": "the time was up ({max_ticks} ticks)",
    "goal-cap": "the player reached the goal cap ({goal_cap} goals)",
    "idle": "the player neither moved nor kicked for {idle_ticks} ticks in a row",
    "out-of-play": "the ball went out of play",
}

# The same, in the few words a small pitch has room for (the UI's population and breeding grids).
END_REASON_LABELS = {
    "max-ticks": "time up",
    "goal-cap": "goal cap reached",
    "idle": "stood still too long",
    "out-of-play": "ball out of play",
}

# The ball or the goal, what a TURN_FIRST turn faces, by the action being performed.
_FACES_GOAL = {"RUNTOWARDGOAL"}


@dataclass(frozen=True)
class Outcome:
    """One tick's skill: the action performed (None: no rule fired, the hunt), the body command it sent
    (kind NONE/TURN/DASH/KICK of soccer/skills.py, its value: moment or power, and a kick's direction
    relative to the facing) and the reason code (soccer/skills.py, ACTED ... NOTHING plus FETCHING)."""

    action: str | None
    kind: int
    value: float
    direction: float
    reason: int

    @property
    def fetching(self) -> bool:
        return bool(self.reason & FETCHING)

    @property
    def why(self) -> int:
        return self.reason & ~FETCHING

    @property
    def refused(self) -> bool:
        """The skill could not do what the action asks (a kick without the ball in reach, or the goal unknown)."""
        return self.why in (NOT_KICKABLE, GOAL_OUT_OF_VIEW)

    def command_text(self) -> str:
        """The body command as sent, e.g. "dash 62", "turn -45°", "kick 100 toward 12°", "no command"."""
        if self.kind == TURN:
            return f"turn {self.value:+.0f}°"
        if self.kind == DASH:
            return f"dash {self.value:.0f}"
        if self.kind == KICK:
            return f"kick {self.value:.0f} toward {self.direction:+.0f}°"
        return "no command"

    def describe(self, skills: str, vocabulary: Vocabulary) -> str:
        """A sentence: the action, then what the player did and why."""
        name = vocabulary.display(self.action) if self.action else "No rule fired"
        return f"{name}: {self._what(skills)}"

    def _what(self, skills: str) -> str:
        why, command = self.why, self.command_text()
        if why == HUNT_BALL:
            return f"the player hunts: {command} to face the ball"
        if why == HUNT_LAST_SEEN:
            return f"the player hunts: {command} toward where it last saw the ball"
        fetch = "the ball is out of reach, so it goes to the ball first (assisted skills): " if self.fetching else ""
        if why == ACTED:
            if self.kind == KICK and self.action in ("KICKTOWARDGOAL", "DRIBBLETOWARDGOAL"):
                return f"{fetch}{command} (the goal's direction)"
            return f"{fetch}{command}"
        if why == TURN_FIRST:
            target = "the goal" if self.action in _FACES_GOAL else "the ball"
            return f"{fetch}{command} to face {target} first (it is more than 10° off)"
        if why == BALL_OUT_OF_VIEW:
            return f"{fetch}the ball is not in view: {command} toward where it was last seen"
        if why == NOT_KICKABLE:
            return f"no kick, the ball is not kickable (out of reach; {skills} skills do not fetch it)"
        if why == GOAL_OUT_OF_VIEW:
            verb = "no run" if self.action == "RUNTOWARDGOAL" else "no kick"
            return (f"{verb}, the goal is not in view ({skills} skills: the player knows where the goal is "
                    "only while it sees it)")
        if why == AT_BALL:
            return f"{fetch}stands still: the ball is within reach"
        if why == NO_DASH_NEEDED:
            return f"{fetch}no dash: it is already drifting onto the ball"
        if why == NOTHING:
            return "does nothing"
        return command


def skill_set_sentence(skills: str) -> str:
    return SKILL_SETS.get(skills, skills)


def end_reason_sentence(end_reason: str, max_ticks: int, goal_cap: int, idle_ticks: int) -> str:
    """Why a game ended, e.g. "the player neither moved nor kicked for 100 ticks in a row"."""
    template = END_REASONS.get(end_reason, end_reason)
    return template.format(max_ticks=max_ticks, goal_cap=goal_cap, idle_ticks=idle_ticks)
