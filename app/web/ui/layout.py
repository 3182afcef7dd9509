"""The page's frame, the same for every tab: the theme, the left panel docked, the right panel docked
with its tabs. Set once on the server, it reaches a new tab in viser's initial state, before the
tab's session exists: the 3D canvas has its final shape from its first frame, so the camera the
session fits to it is right at once (a panel docked later resizes the canvas, which in a browser
without a GPU costs a second or more, and the pitch needs fitting again)."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

import viser

from soccer_lab.app.web.ui import style

RIGHT_TABS = ("Inference", "Policy map", "Population", "Lineage", "Breeding")


class Layout:
    def __init__(self, server: viser.ViserServer):
        gui = server.gui
        gui.configure_theme(dark_mode=False, show_logo=False, show_share_button=False, brand_color=style.BRAND)
        gui.main_panel.dock_left()
        gui.main_panel.set_width(style.LEFT_PANEL_WIDTH)
        right = gui.add_panel()
        self._right_tabs = {name: right.add_tab(name) for name in RIGHT_TABS}
        self.right_panel_id = right._impl.uuid  # the projector view folds it for one tab (app/web/ui/projector.py)
        right.dock_right()
        right.set_width(style.RIGHT_PANEL_WIDTH)
        # A tab is one `with` context at a time: sessions built at once take turns.
        self._lock = threading.Lock()

    @contextlib.contextmanager
    def right_tab(self, name: str) -> Iterator[None]:
        """Inside: a session's elements go into the right panel's tab `name` (on its own tab only)."""
        with self._lock, self._right_tabs[name]:
            yield
