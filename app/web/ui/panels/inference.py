"""The inference view, in the order inference happens: fuzzify the inputs, fire the rules, clip and
aggregate the output sets, defuzzify. The decision sits on top because it is what people look at first."""

from __future__ import annotations

from html import escape
from typing import TYPE_CHECKING, Callable, Mapping, Sequence

import viser

from soccer_lab.app.rule_inspection import MAX_GAMES
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.number_field import FieldError, NumberField
from soccer_lab.app.web.ui.panels.membership import input_html, input_names, kick_reach, terms_html
from soccer_lab.app.web.ui.panels.outputs import outputs_html
from soccer_lab.app.web.ui.panels.rules import decision_html, rules_html
from soccer_lab.app.words import plural
from soccer_lab.fuzzy.engine import Inference
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import WorldConfig

if TYPE_CHECKING:
    from soccer_lab.soccer.usage import Usage


class InferencePanel:
    """`on_usage(games)` measures the rules' usage over that many games; `show_usage` shows it beside
    the rules (None clears it, when another rulebase goes on the pitch)."""

    def __init__(self, gui: viser.GuiApi, vocabulary: Vocabulary, on_change: Callable[[], None],
                 on_usage: Callable[[int], None], world: WorldConfig = WorldConfig()):
        self.vocabulary = vocabulary
        self.reaches = kick_reach(vocabulary, world)
        self.usage: Usage | None = None
        self.whose = gui.add_html("")  # in a match: whose thinking this is
        self.decision = gui.add_html("")
        with gui.add_folder("Rules and their strengths"):
            self.only_fired = gui.add_checkbox("Only rules that fired", False)
            self.only_fired.on_update(lambda _: on_change())  # redraw now, also while paused
            self.usage_games = NumberField(gui, "Usage games", style.USAGE_GAMES, minimum=1, maximum=MAX_GAMES,
                                           integer=True)
            measure = gui.add_button("Measure rule usage",
                                     hint="Play these games from the pitch's seed and show how often each rule won")
            measure.on_click(lambda _: self._measure(on_usage))
            self.usage_note = gui.add_html("")  # under the button pressed: measuring, or why no usage is shown
            self.rules = gui.add_html("")
        with gui.add_folder("Output sets (clipped, max, mean of maximum)"):
            self.outputs = gui.add_html("")
        with gui.add_folder("Inputs: membership degrees"):
            gui.add_html(terms_html(vocabulary))
            self.membership = {name: gui.add_html("") for name in input_names(vocabulary)}
        self._shown: dict[str, str] = {}

    def show(self, inputs: Mapping[str, float | None], rule_texts: Sequence[str], inference: Inference,
             outcome: str | None = None, refused: bool = False, tick: int | None = None,
             whose: str = "") -> None:
        """`outcome`: what the player then did (a sentence, None before its first decision); `refused`: the
        skill could not do what the action asks; `whose`: in a match, a line of HTML naming the player shown."""
        self._set(self.whose, "whose", whose)
        self._set(self.decision, "decision", decision_html(self.vocabulary, inference, outcome, refused, tick))
        self._set(self.rules, "rules", rules_html(rule_texts, inference, self.only_fired.value, self.usage))
        self._set(self.outputs, "outputs", outputs_html(self.vocabulary, inference))
        for name, handle in self.membership.items():
            self._set(handle, name, input_html(self.vocabulary, name, inputs.get(name), self.reaches.get(name)))

    def _measure(self, on_usage: Callable[[int], None]) -> None:
        try:
            games = int(self.usage_games.value)
        except FieldError:  # the field says what it needs
            return
        self.say_usage(f"Measuring rule usage on {plural(games, 'game')} ...")
        on_usage(games)

    def show_usage(self, usage: "Usage | None") -> None:
        self.usage = usage
        self.say_usage("")  # the caption above the rules says what was measured

    def say_usage(self, text: str, *, error: bool = False) -> None:
        """A line under Measure rule usage: what it is doing, or why no usage is shown."""
        colour = style.ERROR if error else style.INK
        self.usage_note.content = text and (
            f'<div class="usage-note" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{colour}">{escape(text)}</div>')

    def _set(self, handle: viser.GuiHtmlHandle, key: str, content: str) -> None:
        # Only changed content goes over the websocket; at 30 fps most panels are unchanged most frames.
        if self._shown.get(key) != content:
            self._shown[key] = content
            handle.content = content
