"""Who hears what happens: the functions told of a run's events (app/runs/manager.py) or a class's
(app/web/classroom/tournament.py). They are called from the thread where it happened, so each must be
quick; one that fails (a browser tab that closed) is logged and the others still hear."""

from __future__ import annotations

import logging
import threading
from typing import Callable, Generic, TypeVar

Event = TypeVar("Event")
log = logging.getLogger(__name__)


class Listeners(Generic[Event]):
    def __init__(self, what: str):
        self._what = what  # whose listener failed, for the log
        self._listeners: list[Callable[[Event], None]] = []
        self._lock = threading.Lock()

    def add(self, listener: Callable[[Event], None]) -> Callable[[], None]:
        """Call `listener(event)` on every event; returns the function that removes it."""
        with self._lock:
            self._listeners.append(listener)

        def remove() -> None:
            with self._lock:
                if listener in self._listeners:
                    self._listeners.remove(listener)

        return remove

    def notify(self, event: Event) -> None:
        with self._lock:
            listeners = list(self._listeners)
        for listener in listeners:
            try:
                listener(event)
            except Exception:
                log.exception("%s listener failed", self._what)
