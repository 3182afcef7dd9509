"""The built-in example rulebases a teacher can pick (soccer/data/examples/*.rules), each with a title and
a sentence on what it shows, read from the file's `# title:` and `# shows:` lines. The demo is the player
every tab opens with."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import GameBatch

EXAMPLES_DIR = Path(__file__).parent / "data" / "examples"
ORDER = ("demo", "striker", "dribbler", "hunter")  # as a teacher meets them
DEMO = "demo"


@dataclass(frozen=True)
class Example:
    name: str  # the file's stem
    title: str
    shows: str  # one or two sentences: what the example teaches
    text: str  # the whole file: rules and comments, as the parser reads it

    def rulebase(self, vocabulary: Vocabulary) -> Rulebase:
        return parse_rulebase(self.text, vocabulary)


def _header(text: str, key: str, path: Path) -> str:
    for line in text.splitlines():
        if line.startswith(f"# {key}:"):
            return line.split(":", 1)[1].strip()
    raise ValueError(f"{path}: no '# {key}:' line")


@functools.cache
def examples() -> tuple[Example, ...]:
    found = []
    for name in ORDER:
        path = EXAMPLES_DIR / f"{name}.rules"
        text = path.read_text(encoding="utf-8")
        found.append(Example(name, _header(text, "title", path), _header(text, "shows", path), text))
    return tuple(found)


def example(name: str) -> Example:
    """KeyError naming the examples when there is none of that name."""
    for candidate in examples():
        if candidate.name == name:
            return candidate
    raise KeyError(f"no example {name!r} (the examples are {', '.join(ORDER)})")


AT_THE_BALL = 5.0  # metres: a game that ends idle with the ball this close stalled at it, not lost it


def games_stalled_at_ball(rulebase: Rulebase, seeds: list[int], config: GameConfig, vocabulary: Vocabulary) -> list[int]:
    """The seeds whose game (one batch of all) ended by the idle limit with the ball within AT_THE_BALL metres
    of the player: a player standing still at the ball it does not kick."""
    batch = GameBatch([rulebase] * len(seeds), seeds, config, vocabulary)
    results = batch.run()
    gaps = batch.state.last_ball - batch.state.last_player
    return [seed for seed, result, (dx, dy) in zip(seeds, results, gaps)
            if result.end_reason == "idle" and (dx * dx + dy * dy) ** 0.5 < AT_THE_BALL]
