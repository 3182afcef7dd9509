"""A link that reproduces a pitch: `/ui/?pitch=TOKEN` opens the same rules, seed, game rules, speed and tick
for anyone who opens it on the same server, and plays the same game bit for bit (a game depends only on its
rules, seed and game rules: docs/design.md, "A game does not depend on its batch").

The token is the pitch's state as compact JSON (the rule text itself, so a link does not depend on the
library staying as it was; only the game rules that differ from the app's), deflated and base64url-encoded:
a 10-rule rulebase makes a link of a few hundred characters. zlib's checksum catches a link cut short or
mistyped; whatever decodes is checked like any input (rules parsed, bounds, names as plain text), and a link
that fails any of it gives one line (LinkError) saying why.
"""

from __future__ import annotations

import base64
import binascii
import json
import re
import zlib
from dataclasses import dataclass, field
from typing import Any

from pydantic import ValidationError

from soccer_lab.app.store import StoreError, valid_name
from soccer_lab.app.web.ui.style import SPEED_RANGE
from soccer_lab.app.web.validation import describe_problems
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import MAX_TICKS, GameConfig

LINK_PARAMETER = "pitch"
VERSION = 1
MAX_TOKEN_LENGTH = 8_000  # what every browser and server takes in a URL
MAX_STATE_BYTES = 40_000  # the decoded state: a bound against a small link that inflates to gigabytes
MAX_RULE_CHARACTERS = 20_000
TOKEN_CHARACTERS = re.compile(r"[A-Za-z0-9_-]+")
GAME_FIELDS = ("max_ticks", "goal_cap", "idle_ticks", "fitness", "skills", "noise", "count_touches")


class LinkError(ValueError):
    """A link that cannot be opened: the one line to show."""


@dataclass(frozen=True)
class PitchLink:
    rules: str
    name: str
    seed: int
    tick: int = 0
    speed: float = 1.0
    paused: bool = False
    game: dict[str, Any] = field(default_factory=dict)  # the game rules that differ from the app's

    @classmethod
    def of(cls, rules: str, name: str, seed: int, tick: int, speed: float, paused: bool, game: GameConfig,
           app_game: GameConfig) -> "PitchLink":
        differences = {name_: getattr(game, name_) for name_ in GAME_FIELDS
                       if getattr(game, name_) != getattr(app_game, name_)}
        return cls(rules, name, seed, tick, speed, paused, differences)

    def game_config(self, app_game: GameConfig) -> GameConfig:
        """The game the link's pitch plays: the app's, with the link's differences (LinkError when invalid)."""
        try:
            return GameConfig(**{**app_game.model_dump(), **self.game})
        except ValidationError as exc:
            raise LinkError(f"its game rules are not valid ({describe_problems(exc.errors())})") from None

    def rulebase(self, vocabulary: Vocabulary) -> Rulebase:
        try:
            rulebase = parse_rulebase(self.rules, vocabulary)
        except RuleSyntaxError as exc:
            raise LinkError(f"its rules do not parse ({exc})") from None
        if not len(rulebase):
            raise LinkError("it has no rules")
        return rulebase

    def token(self) -> str:
        state = {"v": VERSION, "r": self.rules, "n": self.name, "s": self.seed, "t": self.tick, "x": self.speed,
                 "p": int(self.paused), "g": self.game}
        packed = zlib.compress(json.dumps(state, separators=(",", ":")).encode("utf-8"), 9)
        return base64.urlsafe_b64encode(packed).rstrip(b"=").decode("ascii")


def decode_link(token: str) -> PitchLink:
    """The pitch a link's token describes, checked; LinkError saying why it cannot be opened."""
    if len(token) > MAX_TOKEN_LENGTH:
        raise LinkError(f"it is longer than {MAX_TOKEN_LENGTH} characters")
    if not TOKEN_CHARACTERS.fullmatch(token):
        raise LinkError("it has characters a soccer-lab link never has (was it cut or changed when copied?)")
    try:
        packed = base64.urlsafe_b64decode(token + "=" * (-len(token) % 4))
        inflater = zlib.decompressobj()
        raw = inflater.decompress(packed, MAX_STATE_BYTES)
        if inflater.unconsumed_tail or not inflater.eof:
            raise LinkError("it is damaged or too large (was it cut short when copied?)")
        state = json.loads(raw.decode("utf-8"))
    except (binascii.Error, zlib.error, UnicodeDecodeError, json.JSONDecodeError, ValueError) as exc:
        if isinstance(exc, LinkError):
            raise
        raise LinkError("it is damaged (was it cut short or changed when copied?)") from None
    return _checked(state)


def _checked(state: Any) -> PitchLink:
    if not isinstance(state, dict) or state.get("v") != VERSION:
        raise LinkError("it was made by another version of soccer-lab")
    rules, name, seed, tick, speed, paused, game = (state.get(key) for key in "rnstxpg")
    if not isinstance(rules, str) or len(rules) > MAX_RULE_CHARACTERS:
        raise LinkError(f"its rules are missing or longer than {MAX_RULE_CHARACTERS} characters")
    try:
        name = valid_name(name)
    except StoreError as exc:
        raise LinkError(f"its player's name is not plain text ({exc})") from None
    if not _integer(seed) or not 0 <= seed < 2**63:
        raise LinkError("its seed is not a non-negative integer")
    if not _integer(tick) or not 0 <= tick <= MAX_TICKS:
        raise LinkError(f"its tick is not an integer from 0 to {MAX_TICKS}")
    if isinstance(speed, bool) or not isinstance(speed, (int, float)) or not SPEED_RANGE[0] <= speed <= SPEED_RANGE[1]:
        raise LinkError(f"its speed is not between {SPEED_RANGE[0]} and {SPEED_RANGE[1]}")
    if paused not in (0, 1) or isinstance(paused, bool):
        raise LinkError("it does not say whether the game is paused")
    if not isinstance(game, dict) or not set(game) <= set(GAME_FIELDS):
        raise LinkError("its game rules are not soccer-lab's")
    return PitchLink(rules, name, seed, tick, float(speed), bool(paused), game)


def _integer(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)
