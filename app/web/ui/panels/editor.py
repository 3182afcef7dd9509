"""Rule editor: rule text with errors at line and column, apply, undo, simplify, save to the library, and
the chromosome in the chapter's compact notation, both ways."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import viser

from soccer_lab.app.words import plural
from soccer_lab.app.rule_inspection import MAX_GAMES, size
from soccer_lab.app.web.access import ScopedStore
from soccer_lab.app.runs.outputs import best_of_text
from soccer_lab.app.store import StoreError
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.number_field import NumberField
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.notation import NotationError, format_compact, parse_compact
from soccer_lab.soccer.examples import examples

if TYPE_CHECKING:
    from soccer_lab.soccer.simplify import CheckedSimplification

EDITED_NAME = "edited"
PICK_EXAMPLE = "— pick an example —"
SIMPLIFIED_NAME = "simplified"
UNDO_DEPTH = 50
# viser's text area grows to six lines at most; the rule text (the element after the heading) gets
# the panel's whole width and the height its rules need (editor_style), so a whole rulebase reads without
# scrolling and Apply stays in view. min-height wins over the height the text area sets itself; the font is
# the panel's, not viser's small input font, so the rules read on a projector.
def editor_style(text: str) -> str:
    lines = sum(max(1, math.ceil(len(line) / style.RULE_EDITOR_LINE_CHARACTERS)) for line in text.splitlines())
    height = max(lines + 1, style.RULE_EDITOR_MIN_LINES) * style.RULE_EDITOR_LINE_HEIGHT
    return (
        "<style>div:has(> .rules-on-pitch) + div .mantine-Flex-root > div:first-child { display: none }"
        f"div:has(> .rules-on-pitch) + div textarea {{ min-height: min({height:.2f}em, {style.RULE_EDITOR_MAX_HEIGHT})"
        f" !important; font-size: {style.FONT_SIZE - 1}px !important; line-height: {style.RULE_EDITOR_LINE_HEIGHT} }}"
        "</style>"
    )


class EditorPanel:
    """Shows `on_pitch` (rulebase, name) first. `on_apply(rulebase, name)` puts rules on the pitch;
    `on_example(rulebase, name)` puts a built-in example on the pitch from a new start; `on_saved()`
    follows a save to the library; `simplify(rulebase, games)` simplifies rules (exact steps, then
    checked on that many games; 0: exact only); `best_of(rulebase)`: the figures of the run's best these
    rules are (None: they are no run's best), saved beside them. The session calls `show_rulebase` whenever a rulebase
    goes on the pitch, from here or elsewhere."""

    def __init__(
        self,
        gui: viser.GuiApi,
        vocabulary: Vocabulary,
        store: ScopedStore,
        on_pitch: tuple[Rulebase, str],
        *,
        on_apply: Callable[[Rulebase, str], None],
        on_example: Callable[[Rulebase, str], None],
        on_saved: Callable[[], None],
        simplify: Callable[[Rulebase, int], "CheckedSimplification"],
        best_of: Callable[[Rulebase], dict | None] = lambda rulebase: None,
    ):
        self.vocabulary = vocabulary
        self.store = store
        self.best_of = best_of
        self.on_apply = on_apply
        self.on_saved = on_saved
        self.simplify_with = simplify
        self.history: list[tuple[Rulebase, str]] = []
        self.codec = ChromosomeCodec(self.vocabulary)
        self.examples = {example.title: example for example in examples()}
        self.example = gui.add_dropdown("Example", (PICK_EXAMPLE, *self.examples), initial_value=PICK_EXAMPLE,
                                        hint="Built-in players, each showing one idea; picking one plays it")
        self.example_note = gui.add_html("")
        self.name = gui.add_html("")
        self.text = gui.add_text("Rules", "", multiline=True)
        actions = gui.add_button_group("Rules", ("Apply", "Undo"))
        self.message = gui.add_html("")
        with gui.add_folder("Simplify"):
            self.check_games = NumberField(gui, "Check on games", style.USAGE_GAMES, minimum=0, maximum=MAX_GAMES,
                                           integer=True)
            simplify = gui.add_button("Simplify",
                                      hint="The same player in fewer words: exact steps, then rules that never won "
                                           "in these games (from the pitch's seed), if every game replays the same")
        with gui.add_folder("Save to library"):
            self.save_name = gui.add_text("Name", "")
            save = gui.add_button("Save")
        with gui.add_folder("Chromosome (compact notation)"):
            self.compact = gui.add_text("Genes", "", multiline=True)
            conversions = gui.add_button_group("Convert", ("Rules → genes", "Genes → rules"))

        @actions.on_click
        def _(event: viser.GuiEvent) -> None:
            self.apply() if event.target.value == "Apply" else self.undo()

        @self.example.on_update
        def _(_: viser.GuiEvent) -> None:
            chosen = self.examples.get(self.example.value)
            if chosen is None:
                return
            self.history = (self.history + [self.on_pitch])[-UNDO_DEPTH:]
            on_example(chosen.rulebase(self.vocabulary), chosen.title)
            self.example_note.content = (
                f'<div class="example-note" style="{style.FONT}; font-size:{style.FONT_SIZE}px; color:{style.INK}">'
                f"{escape(chosen.shows)}</div>")

        @save.on_click
        def _(_: viser.GuiEvent) -> None:
            self.save()

        @simplify.on_click
        def _(_: viser.GuiEvent) -> None:
            self.simplify()

        @conversions.on_click
        def _(event: viser.GuiEvent) -> None:
            self.rules_to_genes() if event.target.value == "Rules → genes" else self.genes_to_rules()

        self.show_rulebase(*on_pitch)

    # ---- showing ----------------------------------------------------------------------------
    def show_rulebase(self, rulebase: Rulebase, name: str) -> None:
        """Called when a rulebase is put on the pitch (from here, the library or an evolution): what was said
        about the previous rules is cleared."""
        self.on_pitch = (rulebase, name)
        self.message.content = ""
        if name not in self.examples:
            self.example.value = PICK_EXAMPLE
            self.example_note.content = ""
        self.text.value = format_rulebase(rulebase, self.vocabulary)
        self.compact.value = format_compact(self.codec.encode(rulebase), self.vocabulary)
        self.name.content = (
            f'<div class="rules-on-pitch" style="{style.FONT}; font-size:{style.FONT_SIZE}px">On the pitch: '
            f"<b>{escape(name)}</b> ({plural(len(rulebase), 'rule')})</div>{editor_style(self.text.value)}"
        )

    def _say(self, text: str, *, error: bool = False, lines: list[str] | None = None) -> None:
        colour = style.ERROR if error else style.FIRED
        items = "".join(f"<li>{escape(line)}</li>" for line in lines or [])
        self.message.content = (
            f'<div class="editor-message" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{colour}">{escape(text)}'
            f'{f"<ul style=margin:4px 0 0 18px;padding:0>{items}</ul>" if items else ""}</div>'
        )

    def show_error(self, text: str) -> None:
        self._say(text, error=True)

    # ---- actions ----------------------------------------------------------------------------
    def apply(self) -> None:
        try:
            rulebase = parse_rulebase(self.text.value, self.vocabulary)
        except RuleSyntaxError as exc:
            self._say(f"{plural(len(exc.errors), 'error')}; nothing applied:", error=True,
                      lines=[str(e) for e in exc.errors])
            return
        if not len(rulebase):
            self._say("No rules: write at least one rule (the player would only hunt).", error=True)
            return
        self.history = (self.history + [self.on_pitch])[-UNDO_DEPTH:]
        self.on_apply(rulebase, EDITED_NAME)
        self._say(f"Applied {len(rulebase)} rule{'' if len(rulebase) == 1 else 's'}; the player now plays them.")

    def undo(self) -> None:
        if not self.history:
            self._say("Nothing to undo.", error=True)
            return
        rulebase, name = self.history.pop()
        self.on_apply(rulebase, name)
        self._say(f"Back to {name}.")

    def simplify(self) -> None:
        rulebase, name = self.on_pitch
        try:
            result = self.simplify_with(rulebase, int(self.check_games.value))
        except ValueError as exc:  # no usable number in the field (FieldError), or over a limit (checked_cost)
            self._say(f"Not simplified: {exc}", error=True)
            return
        simplified = result.simplification.rulebase
        lines = _change_lines(result.simplification.steps)
        if simplified == rulebase:
            self._say("Nothing to simplify: every step left the rules as they are.", lines=lines)
            return
        if not len(simplified):
            self._say("None of these rules can ever fire: nothing would be left to play.", error=True)
            return
        self.history = (self.history + [(rulebase, name)])[-UNDO_DEPTH:]
        self.on_apply(simplified, SIMPLIFIED_NAME)
        before, after = size(rulebase), size(simplified)
        self._say(f"Simplified {plural(before['rules'], 'rule')} ({plural(before['premises'], 'premise')}) to "
                  f"{after['rules']} ({after['premises']}); the player now plays them. Undo goes back.", lines=lines)

    def save(self) -> None:
        name = self.save_name.value.strip()
        if not name:
            self._say("Give the rulebase a name to save it.", error=True)
            return
        text = format_rulebase(self.on_pitch[0], self.vocabulary)
        try:
            record = self.store.create_rulebase(name, text, best_of=self.best_of(self.on_pitch[0]))
        except StoreError as exc:
            self._say(f"Not saved: {exc}", error=True)
            return
        figures = best_of_text(record.best_of)
        self._say(f"Saved the rules on the pitch as “{record.name}” (#{record.id})" +
                  (f", with {figures}." if figures else "."))
        self.on_saved()

    def rules_to_genes(self) -> None:
        try:
            rulebase = parse_rulebase(self.text.value, self.vocabulary)
        except RuleSyntaxError as exc:
            self._say("Fix the rules first:", error=True, lines=[str(e) for e in exc.errors])
            return
        self.compact.value = format_compact(self.codec.encode(rulebase), self.vocabulary)
        self._say(f"Encoded {plural(len(rulebase), 'rule')} as genes.")

    def genes_to_rules(self) -> None:
        try:
            rulebase = self.codec.decode(parse_compact(self.compact.value, self.vocabulary))
        except (NotationError, ValueError) as exc:
            self._say(f"Cannot read the genes: {exc}", error=True)
            return
        self.text.value = format_rulebase(rulebase, self.vocabulary)
        self._say(f"Decoded {plural(len(rulebase), 'valid rule')}; press Apply to play them.")


MAX_CHANGE_LINES = 40  # a long list says how many more it left out


def _change_lines(steps) -> list[str]:
    """Which rules went or changed, and why, step by step (a step listed but not applied says so)."""
    lines = []
    for step in steps:
        how = f"checked on {plural(step.games, 'game')}" if step.kind == "checked" else "exact"
        note = "" if step.applied else " (listed, not applied)"
        for change in step.changes:
            what = "dropped" if change.after is None else f"now “{change.after}”"
            lines.append(f"Rule {change.rule} {what}: {change.reason} [{step.name}, {how}{note}]")
    if len(lines) > MAX_CHANGE_LINES:
        lines = lines[:MAX_CHANGE_LINES] + [f"… and {len(lines) - MAX_CHANGE_LINES} more changes"]
    return lines
