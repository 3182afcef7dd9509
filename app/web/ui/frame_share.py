"""How many frames a second each open tab draws: the server's drawing shared out among its tabs.

Drawing a frame (the pitch, the decision and its outcome, the membership degrees, the policy map's marker,
and sending them) costs the server's Python a few milliseconds, under one interpreter lock for every tab.
A class of 30 tabs at 20 ticks a second each would need several cores, and every game slowed to a quarter
of its speed (benchmarks/classroom.py). Past ALL_TABS_FRAME_RATE frames a second in all, each tab draws
fewer frames and plays several ticks a frame: every game keeps its speed, and the server keeps time for the
API and the class's round.
"""

from __future__ import annotations

from soccer_lab.app.web.ui import style


class FrameShare:
    def __init__(self, total: float = style.ALL_TABS_FRAME_RATE, most: float = style.FRAME_RATE):
        self.total = total
        self.most = most
        self.tabs = 0  # the UI server sets it as tabs open and close

    @property
    def rate(self) -> float:
        """Frames a second one tab may draw now."""
        return min(self.most, self.total / max(1, self.tabs))
