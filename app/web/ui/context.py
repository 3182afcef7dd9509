"""What every browser session shares: the store, the run manager, the vocabulary, the world."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.app.web.ui.frame_share import FrameShare
from soccer_lab.soccer.demo import demo_rules_text

if TYPE_CHECKING:
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui.player_qualities import PlayerQualities

DEMO_NAME = "demo (built in)"


@dataclass(frozen=True)
class UiContext:
    store: Store
    runs: RunManager
    vocabulary: Vocabulary
    game: GameConfig

    demo_name: str = DEMO_NAME
    api_url: str | None = None  # the JSON API, for links to files it serves (experiment reports)
    viewer_problem: str | None = None  # why the app serves no rerun viewer (None: it does, at /viewer/)
    frames: FrameShare = field(default_factory=FrameShare)  # each tab's share of the server's drawing
    player_qualities: PlayerQualities | None = None  # re-plays the population view's players for every tab

    def demo_rulebase(self) -> Rulebase:
        return parse_rulebase(demo_rules_text(), self.vocabulary)
