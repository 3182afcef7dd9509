"""Play controls: play, pause, step one tick, speed, new random start and its seed, and the score line."""

from __future__ import annotations

from typing import Callable

import viser

from app.ui import style


class PlayControls:
    def __init__(
        self,
        gui: viser.GuiApi,
        *,
        on_play: Callable[[bool], None],
        on_step: Callable[[], None],
        on_new_start: Callable[[int], None],
        on_reset_view: Callable[[], None],
    ):
        self.status = gui.add_html("")
        buttons = gui.add_button_group("Game", ("Play", "Pause", "Step one tick"))
        self.speed = gui.add_slider(
            "Speed (× real time)", min=style.SPEED_RANGE[0], max=style.SPEED_RANGE[1], step=0.25,
            initial_value=style.DEFAULT_SPEED,
        )
        self.seed = gui.add_number("Seed", initial_value=style.DEFAULT_SEED, min=0, step=1)
        starts = gui.add_button_group("Start", ("New random start", "Restart this seed"))
        reset_view = gui.add_button("Fit pitch to view", color="gray")

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
