"""Play controls: play, pause, step one tick, speed, new random start and its seed, the score line, and a
link that reproduces the pitch (app/pitch_link.py)."""

from __future__ import annotations

from typing import Callable

import viser

from app.ui import style
from app.ui.panels.svg import escape


class PlayControls:
    def __init__(
        self,
        gui: viser.GuiApi,
        *,
        on_play: Callable[[bool], None],
        on_step: Callable[[], None],
        on_new_start: Callable[[int], None],
        on_reset_view: Callable[[], None],
        make_link: Callable[[], str] | None = None,
        notice: str | None = None,
    ):
        if notice:  # e.g. why the link this tab was opened with was not played: one line, as text
            gui.add_html(f'<div class="link-notice" style="{style.FONT}; color:{style.ERROR}">{escape(notice)}</div>')
        self.status = gui.add_html("")
        buttons = gui.add_button_group("Game", ("Play", "Pause", "Step one tick"))
        self.speed = gui.add_slider(
            "Speed (× real time)", min=style.SPEED_RANGE[0], max=style.SPEED_RANGE[1], step=0.25,
            initial_value=style.DEFAULT_SPEED,
        )
        self.seed = gui.add_number("Seed", initial_value=style.DEFAULT_SEED, min=0, step=1)
        starts = gui.add_button_group("Start", ("New random start", "Restart this seed"))
        reset_view = gui.add_button("Fit pitch to view", color="gray")
        if make_link is not None:
            share = gui.add_button("Link to this pitch", color="gray",
                                   hint="A link that opens this pitch as it is now (rules, seed, tick) for anyone "
                                        "on this server")
            self.link = gui.add_text("Link (select, copy)", initial_value="")

            @share.on_click
            def _(_: viser.GuiEvent) -> None:
                self.link.value = make_link()

        @buttons.on_click
        def _(event: viser.GuiEvent) -> None:
            if event.target.value == "Step one tick":
                on_play(False)
                on_step()
            else:
                on_play(event.target.value == "Play")

        @starts.on_click
        def _(event: viser.GuiEvent) -> None:
            # A new start takes the next seed and shows it, so any start can be replayed by typing it back.
            if event.target.value == "New random start":
                self.seed.value = int(self.seed.value) + 1
            on_new_start(int(self.seed.value))

        @reset_view.on_click
        def _(_: viser.GuiEvent) -> None:
            on_reset_view()

    def show_status(self, html: str) -> None:
        if self.status.content != html:
            self.status.content = html
