"""Play controls: play, pause, step one tick, speed, new random start and its seed, the skill set (what
each means, in a sentence), the score line, and a link that reproduces the pitch (app/web/pitch_link.py)."""

from __future__ import annotations

from typing import Callable

import viser

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.number_field import FieldError, NumberField
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.web.ui.projector import THINKING_LABEL, TOGGLE_LABEL
from soccer_lab.ga.config import SEED_BOUND
from soccer_lab.soccer.config import SKILL_SET_NAMES
from soccer_lab.soccer.outcome import skill_set_sentence


class PlayControls:
    def __init__(
        self,
        gui: viser.GuiApi,
        *,
        on_play: Callable[[bool], None],
        on_step: Callable[[], None],
        on_new_start: Callable[[int], None],
        on_reset_view: Callable[[], None],
        on_skills: Callable[[str], None],
        on_projector: Callable[[], None],
        on_thinking: Callable[[int], None],
        skills: str,
        make_link: Callable[[], str] | None = None,
        notice: str | None = None,
    ):
        if notice:  # e.g. why the link this tab was opened with was not played: one line, as text
            gui.add_html(f'<div class="link-notice" style="{style.FONT}; color:{style.ERROR}">{escape(notice)}</div>')
        self.status = gui.add_html("")
        # in a match: whose rules, inputs and decision the Inference panel and the policy map show
        self.thinking = gui.add_button_group(THINKING_LABEL, ("A", "B"), visible=False,
                                             hint="Whose rules, membership degrees and decision the panels show")
        self.thinking.on_click(lambda event: on_thinking(("A", "B").index(event.target.value)))
        buttons = gui.add_button_group("Game", ("Play", "Pause", "Step one tick"))
        self.speed = gui.add_slider(
            "Speed (× real time)", min=style.SPEED_RANGE[0], max=style.SPEED_RANGE[1], step=0.25,
            initial_value=style.DEFAULT_SPEED,
        )
        self.seed = NumberField(gui, "Seed", style.DEFAULT_SEED, minimum=0, maximum=SEED_BOUND - 1, integer=True,
                                hint="The start of the game: the same seed, the same start")
        starts = gui.add_button_group("Start", ("New random start", "Restart this seed"))
        self.skills = gui.add_dropdown("Skills", SKILL_SET_NAMES, initial_value=skills,
                                       hint="What the player's actions do in the world (soccer/skills.py)")
        self.skills_note = gui.add_html("")
        self.show_skills(skills)
        projector = gui.add_button(TOGGLE_LABEL, hint="The pitch fills the window; score, tick, action and what "
                                                      "the player did in large type; the panels fold away")
        projector.on_click(lambda _: on_projector())
        reset_view = gui.add_button("Fit pitch to view", color="gray")
        if make_link is not None:
            share = gui.add_button("Link to this pitch", color="gray",
                                   hint="A link that opens this pitch as it is now (rules, seed, tick) for anyone "
                                        "on this server")
            self.link = gui.add_text("Link (select, copy)", initial_value="")

            @share.on_click
            def _(_: viser.GuiEvent) -> None:
                self.link.value = make_link()

        @self.skills.on_update
        def _(event: viser.GuiEvent) -> None:
            if event.client is not None:  # the user's choice, not show_skills
                on_skills(self.skills.value)

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
            try:
                seed = int(self.seed.value)
            except FieldError:  # the field says what it needs
                return
            if event.target.value == "New random start":
                seed = (seed + 1) % SEED_BOUND
                self.seed.value = seed
            on_new_start(seed)

        @reset_view.on_click
        def _(_: viser.GuiEvent) -> None:
            on_reset_view()

    def show_skills(self, skills: str) -> None:
        """The game's skill set and its meaning (a run's player plays in its run's)."""
        self.skills.value = skills
        self.skills_note.content = (
            f'<div class="skills-note" data-skills="{escape(skills)}" style="{style.FONT}; '
            f'font-size:{style.SMALL_FONT_SIZE + 1}px; color:{style.INK}; margin:-4px 0 6px">'
            f"<b>{escape(skills)}</b>: {escape(skill_set_sentence(skills))}.</div>")

    def show_match(self, match: bool) -> None:
        """The thinking switch shows while a match is on the pitch."""
        if self.thinking.visible != match:
            self.thinking.visible = match

    def show_status(self, html: str) -> None:
        if self.status.content != html:
            self.status.content = html
