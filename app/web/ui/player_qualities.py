"""The population view's true quality: the players it shows re-played on the common fresh starts
(app/runs/true_quality.py), off every tab's frame loop, within a share of the wall time."""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections import OrderedDict
from typing import Callable, Sequence

from soccer_lab.app.runs.true_quality import TRUE_QUALITY_STARTS, TrueQuality, simple_soccer_batch_replayer
from soccer_lab.app.web.ui import style
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig

LOG = logging.getLogger(__name__)
KNOWN_QUALITIES = 4096  # players whose true quality is kept (an elite shown again is not re-played)
BatchReplayer = Callable[[Sequence[Rulebase]], list[TrueQuality]]


class PlayerQualities:
    """Re-plays the players the population view shows on the common fresh starts, for every tab of the app:
    one thread, one batch per generation shown, best-ranked first, each player once per run (an elite shown
    again, or the same generation in another tab, is not re-played). A player's 20 games cost about a tenth
    of a Table 2 generation, so the thread spends at most `share` of the wall time (style.POPULATION_REPLAY_SHARE;
    measured by benchmarks/true_quality.py): players it has no time for stay unknown until a user asks for them
    (`request(..., everyone=True)`: the view's "Measure these 12" button, at most a grid of players on `starts`
    games; `share` None: every shown player, whatever it costs). `replayer_for(game, vocabulary, starts)` makes
    the batch re-player of a game."""

    def __init__(self, vocabulary: Vocabulary, starts: int = TRUE_QUALITY_STARTS,
                 replayer_for: Callable[[GameConfig, Vocabulary, int], BatchReplayer] = simple_soccer_batch_replayer,
                 share: float | None = style.POPULATION_REPLAY_SHARE, clock: Callable[[], float] = time.perf_counter):
        self.vocabulary = vocabulary
        self.starts = starts
        self.replayer_for = replayer_for
        self.share = share
        self.clock = clock
        self.spent = 0.0  # seconds spent re-playing (benchmarks/true_quality.py)
        self._allowance = 0.0  # seconds the thread may still spend (negative: over budget, it waits)
        self._last: float | None = None  # when the previous request was served
        self._per_player: float | None = None  # seconds one player's re-play took last
        self._known: OrderedDict[tuple[int, Rulebase], TrueQuality] = OrderedDict()
        self._replayers: dict[str, BatchReplayer] = {}
        self._requests: queue.SimpleQueue = queue.SimpleQueue()
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()

    def request(self, run_id: int, game: GameConfig, rulebases: Sequence[Rulebase],
                done: Callable[[list[TrueQuality | None]], None], everyone: bool = False) -> None:
        """Re-play `rulebases` (a run's, in its `game`, best first) off the caller's thread; `done(qualities)`
        follows there (None: a player not re-played, the budget spent). `everyone`: all of them, outside the
        share (a user asked: the cost is theirs, `len(rulebases)` x `starts` games at most)."""
        with self._lock:
            if self._thread is None:
                self._thread = threading.Thread(target=self._serve, name="population-replays", daemon=True)
                self._thread.start()
        self._requests.put((run_id, game, tuple(rulebases), done, everyone))

    def known(self, run_id: int, rulebases: Sequence[Rulebase]) -> list[TrueQuality | None]:
        """The figures already re-played for `rulebases` of run `run_id` (None: not re-played), at no cost."""
        with self._lock:
            return [self._known.get((run_id, r)) for r in rulebases]

    def seconds_for(self, players: int) -> float | None:
        """About how long re-playing `players` takes, from the last re-play (None before the first)."""
        return None if self._per_player is None else players * self._per_player

    def _serve(self) -> None:
        while True:
            run_id, game, rulebases, done, everyone = self._requests.get()
            try:
                done(self._qualities(run_id, game, rulebases, everyone))
            except Exception:  # a failed re-play leaves its players' figures unknown; the thread goes on
                LOG.exception("re-playing the population view's players failed")

    def _qualities(self, run_id: int, game: GameConfig, rulebases: Sequence[Rulebase],
                   everyone: bool = False) -> list[TrueQuality | None]:
        missing = list(dict.fromkeys(r for r, q in zip(rulebases, self.known(run_id, rulebases)) if q is None))
        chosen = missing if everyone else missing[:self._affordable(len(missing))]
        if chosen:
            started = self.clock()
            qualities = self._replayer(game)(chosen)
            took = self.clock() - started
            with self._lock:
                for rulebase, quality in zip(chosen, qualities):
                    self._known[(run_id, rulebase)] = quality
                while len(self._known) > KNOWN_QUALITIES:
                    self._known.popitem(last=False)
            self.spent += took
            if not everyone:  # asked-for re-plays are the user's; the share is the background's
                self._allowance -= took
            self._per_player = took / len(chosen)
        return self.known(run_id, rulebases)

    def _affordable(self, wanted: int) -> int:
        """How many players the budget pays for now: `share` of the time since the last request, saved up to
        POPULATION_REPLAY_SAVED_SECONDS of it (an idle app saves no burst); the first player ever measures the cost."""
        if self.share is None:
            return wanted
        now = self.clock()
        if self._last is not None:
            self._allowance = min(self._allowance + self.share * (now - self._last),
                                  self.share * style.POPULATION_REPLAY_SAVED_SECONDS)
        self._last = now
        if self._per_player is None:
            return min(wanted, 1)
        return max(0, min(wanted, int(self._allowance / max(self._per_player, 1e-9))))

    def _replayer(self, game: GameConfig) -> BatchReplayer:
        key = game.model_dump_json()
        if key not in self._replayers:
            self._replayers[key] = self.replayer_for(game, self.vocabulary, self.starts)
        return self._replayers[key]
