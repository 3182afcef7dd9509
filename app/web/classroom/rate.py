"""Each visitor's request rate: a token bucket per visitor (a student, the teacher, or an address that has not
joined), so one student's script cannot starve the class. Memory is bounded: past MAX_VISITORS buckets, the
full ones (idle visitors) are forgotten."""

from __future__ import annotations

import threading
import time

MAX_VISITORS = 10_000


class RateLimiter:
    def __init__(self, per_second: float, burst: float, clock=time.monotonic):
        self.per_second = per_second
        self.burst = burst
        self._clock = clock
        self._buckets: dict[str, tuple[float, float]] = {}  # key -> (tokens, when)
        self._lock = threading.Lock()

    def take(self, key: str, cost: float = 1.0) -> float | None:
        """Spend `cost` of `key`'s tokens: None when it had them, else the seconds until it will."""
        now = self._clock()
        with self._lock:
            tokens, when = self._buckets.get(key, (self.burst, now))
            tokens = min(self.burst, tokens + (now - when) * self.per_second)
            if tokens < cost:
                self._buckets[key] = (tokens, now)
                return (cost - tokens) / self.per_second
            self._buckets[key] = (tokens - cost, now)
            if len(self._buckets) > MAX_VISITORS:
                self._forget_idle(now)
            return None

    def charge(self, key: str, cost: float) -> None:
        """Spend `cost` more of `key`'s tokens after the fact, into debt if need be: its next requests wait."""
        now = self._clock()
        with self._lock:
            tokens, when = self._buckets.get(key, (self.burst, now))
            self._buckets[key] = (min(self.burst, tokens + (now - when) * self.per_second) - cost, now)

    def _forget_idle(self, now: float) -> None:
        for key, (tokens, when) in list(self._buckets.items()):
            if tokens + (now - when) * self.per_second >= self.burst:
                del self._buckets[key]
