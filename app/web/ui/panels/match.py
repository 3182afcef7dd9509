"""Match (in the Play tab): pick two players, each an example, the player on the pitch, a library rulebase, a
run's best (the GA's) or a class entry (classroom mode), and watch their match on the pitch. Every name is
shown as text; a player that cannot be read (a run without a best yet) says so in one line."""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

import viser

from soccer_lab.app.store import NotFound, StoreError
from soccer_lab.app.web.access import ScopedStore
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.examples import examples

if TYPE_CHECKING:
    from soccer_lab.app.web.classroom.tournament import Tournament

ON_PITCH = "The player on the pitch"
EXAMPLE, LIBRARY, RUN, ENTRY = "Example: ", "Library #", "Best of run #", "Class entry #"
DEFAULT_PLAYERS = ("Two-rule striker", "The demo")  # the examples a first match plays


class MatchPanel:
    """`current()`: the rules on the pitch and their name; `on_watch(a, b, names)` plays their match on the
    pitch. `tournament` (classroom mode): its entries can be picked too."""

    def __init__(self, gui: viser.GuiApi, store: ScopedStore, vocabulary: Vocabulary, *,
                 current: Callable[[], tuple[Rulebase, str]],
                 on_watch: Callable[[Rulebase, Rulebase, tuple[str, str]], None],
                 tournament: Tournament | None = None):
        self.store, self.vocabulary, self.tournament = store, vocabulary, tournament
        self.current = current
        self.examples = {f"{EXAMPLE}{e.title}": e for e in examples()}
        gui.add_html(f'<div style="{style.FONT}; font-size:{style.FONT_SIZE}px; color:{style.INK}">Two players on one '
                     "pitch: two halves from one start, the sides swapped at half time.</div>")
        self.players = tuple(
            gui.add_dropdown(f"Player {letter}", (ON_PITCH,),
                             hint="An example, the player on the pitch, a saved rulebase, a run's best or a class entry")
            for letter in ("A", "B"))
        watch = gui.add_button("Watch the match", hint="The two players' match from the Seed above, on the pitch")
        self.message = gui.add_html("")
        self.refresh()
        for dropdown, title in zip(self.players, DEFAULT_PLAYERS):
            dropdown.value = f"{EXAMPLE}{title}"

        @watch.on_click
        def _(_: viser.GuiEvent) -> None:
            self.watch(on_watch)

        self._remove_listener = tournament.add_listener(
            lambda event: self.refresh() if event.kind == "entries" else None) if tournament else (lambda: None)

    def close(self) -> None:
        self._remove_listener()

    def refresh(self) -> None:
        """The players to pick from as they are now (a run finished, a rulebase saved, an entry made)."""
        labels = [ON_PITCH, *self.examples]
        labels += [f"{LIBRARY}{r.id} {r.name}" for r in self.store.list_rulebases()]
        labels += [f"{RUN}{r.id} {r.name}" for r in self.store.list_runs()]
        if self.tournament is not None:
            labels += [f"{ENTRY}{e.id} {e.name}" for e in self.tournament.entries()]
        options = tuple(labels)
        for dropdown in self.players:
            if tuple(dropdown.options) != options:
                chosen = dropdown.value
                dropdown.options = options
                dropdown.value = chosen if chosen in options else ON_PITCH

    def watch(self, on_watch: Callable[[Rulebase, Rulebase, tuple[str, str]], None]) -> None:
        picked = []
        for letter, dropdown in zip(("A", "B"), self.players):
            try:
                picked.append(self.player(dropdown.value))
            except (NotFound, StoreError, RuleSyntaxError, ValueError) as exc:
                self._say(f"Player {letter} cannot play: {exc}", error=True)
                return
        (a, a_name), (b, b_name) = picked
        on_watch(a, b, (a_name, b_name))
        self._say(f"Watching A {a_name} against B {b_name}.")

    def player(self, label: str) -> tuple[Rulebase, str]:
        """The rules and name a label stands for (NotFound: gone since the list was made; ValueError: no player's
        label)."""
        if label == ON_PITCH:
            return self.current()
        if label in self.examples:
            chosen = self.examples[label]
            return chosen.rulebase(self.vocabulary), chosen.title
        for prefix, read in ((LIBRARY, self._saved), (RUN, self._run_best), (ENTRY, self._entry)):
            if label.startswith(prefix):
                number = label[len(prefix):].split(" ", 1)[0]
                if not number.isdigit():
                    break
                return read(int(number))
        raise ValueError(f"no player “{label}”: pick another")

    def _saved(self, record_id: int) -> tuple[Rulebase, str]:
        record = self.store.get_rulebase(record_id)
        return parse_rulebase(record.text, self.vocabulary), record.name

    def _run_best(self, run_id: int) -> tuple[Rulebase, str]:
        best = self.store.best_individual(run_id)  # NotFound: no generation finished yet
        return parse_rulebase(best.rules, self.vocabulary), f"run #{run_id} best (gen {best.generation})"

    def _entry(self, entry_id: int) -> tuple[Rulebase, str]:
        entry = next((e for e in self.tournament.entries() if e.id == entry_id), None) if self.tournament else None
        if entry is None:
            raise NotFound("class entry", entry_id, f"class entry #{entry_id} has left the tournament")
        return parse_rulebase(entry.text, self.vocabulary), entry.name

    def _say(self, text: str, *, error: bool = False) -> None:
        self.message.content = (
            f'<div class="match-message" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{style.ERROR if error else style.FIRED}">{escape(text)}</div>')
