"""Classroom mode's run queue: runs waiting for a free core, started round-robin across their owners.

A class shares the machine's cores (one run per core, each run one worker process). A run started when
every core is busy waits here instead of being refused. Each owner (a pupil's account id; None: the
teacher) has a lane; the next run to start is the first of the next lane in turn, so a pupil who presses
Start again after a run ends waits behind everyone already waiting. Each pupil has one run queued or
running at a time (app/runs/manager.py), so for pupils the turn is simply the order they pressed Start in.

The estimate of a place is what a pupil needs to decide whether to wait: when their run starts and how long
it plays, from the games it may play (population x generations x (games per evaluation + behaviour seeds))
x the longest game's ticks, at the seconds per such tick the class's finished runs took (`RunPace`).
"""

from __future__ import annotations

import heapq
from collections import deque
from dataclasses import dataclass
from typing import Any, Iterator

from soccer_lab.app.runs.run import RunSettings
from soccer_lab.app.store import RunRecord

# Seconds per game-tick of a run's budget before any run has finished: a Table 2 run (5,000 games of at
# most 1,000 ticks) takes about 9 s on one core of the reference machine (docs/results/trial.json: 4.3 s
# on two), the games ending early as often as they do in the chapter's runs
DEFAULT_SECONDS_PER_BUDGET_TICK = 1.8e-6
RUN_OVERHEAD_SECONDS = 0.5  # a run's own start and end (its folder, recording, best player's replay), any size
PACE_WEIGHT = 0.5  # how much each finished run moves the estimate: the latest runs say most about the load


def budget_ticks(settings: RunSettings) -> int:
    """The game-ticks a run may play at most: its games x the longest game's ticks."""
    ga, game = settings.ga, settings.game
    return ga.population_size * ga.max_generations * (game.games_per_evaluation + ga.behaviour_seeds) * game.max_ticks


class RunPace:
    """Seconds per budget tick, learned from the class's finished runs (their cores shared as they were)."""

    def __init__(self, seconds_per_tick: float = DEFAULT_SECONDS_PER_BUDGET_TICK):
        self.seconds_per_tick = seconds_per_tick
        self._observed = False

    def observe(self, seconds: float, ticks: int) -> None:
        if ticks <= 0 or seconds <= 0:
            return
        latest = max(0.0, seconds - RUN_OVERHEAD_SECONDS) / ticks
        self.seconds_per_tick = latest if not self._observed else (
            PACE_WEIGHT * latest + (1 - PACE_WEIGHT) * self.seconds_per_tick)
        self._observed = True

    def seconds(self, settings: RunSettings) -> float:
        return RUN_OVERHEAD_SECONDS + budget_ticks(settings) * self.seconds_per_tick


@dataclass(frozen=True)
class QueuedRun:
    record: RunRecord
    settings: RunSettings
    resume_run: bool  # a stopped run resumed: it continues from its checkpoint once started

    @property
    def owner(self) -> int | None:
        return self.record.owner


@dataclass(frozen=True)
class QueuePlace:
    """Where a queued run stands: `position` 1 starts next; `wait_seconds` until it starts and
    `run_seconds` it then plays, both estimates."""

    position: int
    queued: int  # runs waiting in all
    wait_seconds: float
    run_seconds: float

    def to_dict(self) -> dict[str, Any]:
        return {"position": self.position, "queued": self.queued, "wait_seconds": round(self.wait_seconds, 1),
                "run_seconds": round(self.run_seconds, 1)}


class RunQueue:
    """Queued runs in lanes by owner, served round-robin. Not thread-safe: the run manager's lock guards it."""

    def __init__(self) -> None:
        self._lanes: dict[int | None, deque[QueuedRun]] = {}
        self._turns: deque[int | None] = deque()  # owners with a queued run, next to be served first

    def __len__(self) -> int:
        return sum(len(lane) for lane in self._lanes.values())

    def __contains__(self, run_id: int) -> bool:
        return self.get(run_id) is not None

    def get(self, run_id: int) -> QueuedRun | None:
        return next((queued for queued in self if queued.record.id == run_id), None)

    def __iter__(self) -> Iterator[QueuedRun]:
        """In the order they will start."""
        lanes = {owner: list(lane) for owner, lane in self._lanes.items()}
        for depth in range(max((len(lane) for lane in lanes.values()), default=0)):
            for owner in self._turns:
                if depth < len(lanes[owner]):
                    yield lanes[owner][depth]

    def push(self, queued: QueuedRun) -> None:
        if queued.owner not in self._lanes:
            self._lanes[queued.owner] = deque()
            self._turns.append(queued.owner)
        self._lanes[queued.owner].append(queued)

    def pop(self) -> QueuedRun | None:
        """The next run to start (its owner's lane goes to the back of the turn), or None."""
        if not self._turns:
            return None
        owner = self._turns.popleft()
        lane = self._lanes[owner]
        queued = lane.popleft()
        if lane:
            self._turns.append(owner)
        else:
            del self._lanes[owner]
        return queued

    def remove(self, run_id: int) -> QueuedRun | None:
        queued = self.get(run_id)
        if queued is None:
            return None
        lane = self._lanes[queued.owner]
        lane.remove(queued)
        if not lane:
            del self._lanes[queued.owner]
            self._turns.remove(queued.owner)
        return queued

    def clear(self) -> list[QueuedRun]:
        everything = list(self)
        self._lanes.clear()
        self._turns.clear()
        return everything

    def places(self, busy_for: list[float], slots: int, pace: RunPace) -> dict[int, QueuePlace]:
        """Each queued run's place, given the seconds each running run still needs (`busy_for`) on `slots`
        cores: every run starts on the first core to come free, in turn."""
        free_at = sorted(busy_for) + [0.0] * max(0, slots - len(busy_for))
        heapq.heapify(free_at)
        places, total = {}, len(self)
        for position, queued in enumerate(self, 1):
            start = heapq.heappop(free_at)
            run_seconds = pace.seconds(queued.settings)
            places[queued.record.id] = QueuePlace(position, total, start, run_seconds)
            heapq.heappush(free_at, start + run_seconds)
        return places
