"""Lineage tab: a player's family tree, for the run's best so far, any generation's best, a player of the
population view (by its rank there) or any individual: the ancestors whose genes it carries, in rows
from the oldest generation down to the player (fitness, goals, how each was made), then each of its rules
with the ancestor it came from (a letter and a colour) and what a mutation changed, and its chromosome in
the chapter's compact notation coloured the same way (app/lineage/family_tree.py, app/lineage/drawing.py)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Sequence

import viser

from soccer_lab.app.lineage.family_tree import MUTATED_COLOUR, FamilyTreeView, RunLineage
from soccer_lab.app.lineage.drawing import tree_svg
from soccer_lab.app.web.access import ScopedStore
from soccer_lab.app.store import NotFound
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.lineage import LineageError, Place

if TYPE_CHECKING:
    from soccer_lab.app.runs.manager import SampledPlayer

NONE = "(no run yet)"
BEST_SO_FAR, GENERATION_BEST, POPULATION_VIEW, INDIVIDUAL = (
    "Best so far", "Best of a generation", "Player in the population view", "Any individual")
TREE_COLUMNS = 4  # ancestors side by side in the panel's width; more in one generation are counted
INTRO = ("Pick a run and a player, then Show: its ancestors back to generation 0, each with fitness and goals "
         "and how it was made, and where each of its rules came from.")

PopulationShown = Callable[[], "tuple[int, int, Sequence[SampledPlayer]] | None"]


def run_label(run_id: int, name: str) -> str:
    return f"#{run_id} {name}"


def run_id_of(label: str) -> int | None:
    return int(label[1:].split(" ", 1)[0]) if label.startswith("#") else None


def refresh_runs(dropdown: viser.GuiDropdownHandle, store: ScopedStore, prefer: int | None = None) -> None:
    """The store's runs, newest first; keeps the selection, else selects run `prefer` or the newest."""
    labels = tuple(run_label(r.id, r.name) for r in store.list_runs()) or (NONE,)
    current = run_id_of(dropdown.value)
    if tuple(dropdown.options) != labels:
        dropdown.options = labels
    wanted = current if any(run_id_of(label) == current for label in labels) else prefer
    dropdown.value = next((label for label in labels if run_id_of(label) == wanted), labels[0])


class LineagePanel:
    """`population_shown()`: the run, generation and players the population view shows (None before its
    first generation); `current_run()`: this tab's evolution, if any; `on_load(rulebase, name, run_id)`
    puts a player on the pitch."""

    def __init__(self, gui: viser.GuiApi, store: ScopedStore, vocabulary: Vocabulary, *, population_shown: PopulationShown,
                 current_run: Callable[[], int | None], on_load: Callable[[Rulebase, str, int], None]):
        self.store = store
        self.vocabulary = vocabulary
        self.codec = ChromosomeCodec(vocabulary)
        self.population_shown = population_shown
        self.current_run = current_run
        self.on_load = on_load
        self.run = gui.add_dropdown("Run", (NONE,))
        self.which = gui.add_dropdown("Player", (BEST_SO_FAR, GENERATION_BEST, POPULATION_VIEW, INDIVIDUAL),
                                      initial_value=BEST_SO_FAR)
        self.generation = gui.add_number("Generation", initial_value=0, min=0, step=1)
        self.index = gui.add_number("Individual #", initial_value=0, min=0, step=1)
        self.rank = gui.add_number("Rank in the population view", initial_value=1, min=1, max=12, step=1)
        self.back = gui.add_number("Generations back (0: to generation 0)", initial_value=0, min=0, step=1)
        buttons = gui.add_button_group("Family tree", ("Show", "Load onto the pitch"))
        self.view = gui.add_html(_note(INTRO))
        self.shown: tuple[int, Place] | None = None  # the run and player whose tree is shown
        self._show_inputs()

        @self.which.on_update
        def _(_: viser.GuiEvent) -> None:
            self._show_inputs()

        @buttons.on_click
        def _(event: viser.GuiEvent) -> None:
            self.show() if event.target.value == "Show" else self.load()

        self.refresh()

    def refresh(self) -> None:
        refresh_runs(self.run, self.store, prefer=self.current_run())

    def _show_inputs(self) -> None:
        which = self.which.value
        self.generation.visible = which in (GENERATION_BEST, INDIVIDUAL)
        self.index.visible = which == INDIVIDUAL
        self.rank.visible = which == POPULATION_VIEW

    def show(self) -> None:
        try:
            run_id, lineage, place = self._chosen()
            view = lineage.family_tree(place, int(self.back.value) or None)
        except (LineageError, NotFound, ValueError) as exc:
            self.view.content = _note(str(exc), error=True)
            return
        self.shown = (run_id, place)
        self.view.content = lineage_html(view, run_id)

    def load(self) -> None:
        if self.shown is None:
            self.show()
        if self.shown is None:
            return
        run_id, place = self.shown
        lineage = RunLineage.from_store(self.store, run_id, self.vocabulary)
        rulebase = self.codec.decode(lineage.lineage.individual(place).chromosome)
        self.on_load(rulebase, f"run #{run_id} {place}", run_id)

    def _chosen(self) -> tuple[int, RunLineage, Place]:
        which = self.which.value
        if which == POPULATION_VIEW:
            shown = self.population_shown()
            if shown is None:
                raise LineageError("the population view shows no generation yet: start an evolution")
            run_id, generation, players = shown
            rank = int(self.rank.value)
            if not 1 <= rank <= len(players):
                raise LineageError(f"the population view shows ranks 1 to {len(players)}, not {rank}")
            self.refresh()
            self.run.value = next(label for label in self.run.options if run_id_of(label) == run_id)
            return run_id, RunLineage.from_store(self.store, run_id, self.vocabulary), Place(
                generation, players[rank - 1].index)
        run_id = run_id_of(self.run.value)
        if run_id is None:
            raise LineageError("no run yet: start one in the Evolve tab")
        lineage = RunLineage.from_store(self.store, run_id, self.vocabulary)
        generation = int(self.generation.value)
        if which == BEST_SO_FAR:
            return run_id, lineage, lineage.place()
        if which == GENERATION_BEST:
            return run_id, lineage, lineage.place(generation)
        return run_id, lineage, lineage.place(generation, int(self.index.value))


def _note(text: str, *, error: bool = False) -> str:
    colour = style.ERROR if error else style.MUTED
    return (f'<div class="lineage-note" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{colour}">{escape(text)}</div>')


def _chip(letter: str, colour: str) -> str:
    return (f'<span style="display:inline-block; min-width:1.4em; text-align:center; border-radius:0.7em; '
            f'background:{colour}; color:white; font-weight:700; margin-right:6px">{escape(letter)}</span>')


def lineage_html(view: FamilyTreeView, run_id: int) -> str:
    """The tree (SVG), the rules with their origins and the chromosome, as the Lineage tab shows them."""
    chosen = view.chosen
    rules = "".join(
        f'<li class="lineage-rule" data-letter="{escape(rule.letter)}" style="margin:0 0 8px 0">'
        f"{_chip(rule.letter, rule.colour)}{escape(rule.text)}"
        f'<div style="color:{style.MUTED}; font-size:{style.SMALL_FONT_SIZE + 1}px; margin-left:2em">'
        f"<code>{escape(rule.genes)}</code><br>{escape(rule.summary)}</div>"
        + "".join(f'<div class="lineage-mutation" style="color:{MUTATED_COLOUR}; font-size:{style.SMALL_FONT_SIZE + 1}px; '
                  f'margin-left:2em">mutated here: {escape(change)}</div>' for change in rule.mutated)
        + "</li>"
        for rule in view.rules)
    colours = {letter: view.colour(place) for place, letter in view.letters.items()}
    genes = " ".join(
        f'<code class="lineage-gene" title="{escape(gene.mutated or "")}" style="color:{colours.get(gene.origin, style.MUTED)}; '
        f'white-space:nowrap{f"; text-decoration:underline 2px {MUTATED_COLOUR}" if gene.mutated else ""}">'
        f"{escape(gene.compact)}</code>" for gene in view.genes())
    legend = " · ".join(f"{_chip(letter, colours[letter])}{escape(place)}" for place, letter in view.letters.items())
    heading = "font-weight:700; margin:10px 0 4px 0"
    return (
        f'<div class="lineage" data-run="{run_id}" data-generation="{chosen.generation}" data-index="{chosen.index}" '
        f'data-ancestors="{len(view.tree.ancestors)}" data-rules="{len(view.rules)}" '
        f'style="{style.FONT}; {style.SCROLLBAR_ROOM}; font-size:{style.FONT_SIZE}px; color:{style.INK}">'
        f'<div style="font-weight:700">Run #{run_id}: {escape(view.title())}</div>'
        f'<div style="color:{style.MUTED}">Born: {escape(view.birth_text(view.tree.ancestors[chosen]))}</div>'
        f'<div style="{heading}">Its ancestors (those whose genes it carries), back to generation '
        f"{view.tree.oldest}</div>{tree_svg(view, max_row_nodes=TREE_COLUMNS)}{_opponents_html(view, heading)}"
        f'<div style="{heading}">Its rules, each marked with the ancestor it came from</div>'
        f'<ol style="padding-left:0; list-style:none; margin:0">{rules}</ol>'
        f'<div style="{heading}">Its chromosome in compact notation (Figs. 6, 7), coloured by origin; '
        f'underlined red: mutated at its birth</div><div style="line-height:1.7">{genes}</div>'
        f'<div style="margin-top:6px; font-size:{style.SMALL_FONT_SIZE + 1}px">{legend}</div></div>'
    )


def _opponents_html(view: FamilyTreeView, heading: str) -> str:
    """Co-evolution: whom each generation of the tree was scored against (the hall of fame members it drew)."""
    if not view.opponents:
        return ""
    lines = "".join(f'<div class="lineage-opponents" data-generation="{g}">gen {g}: {escape(", ".join(labels))}</div>'
                    for g, labels in sorted(view.opponents.items(), reverse=True))
    return f'<div style="{heading}">Scored against (co-evolution: the hall of fame members each generation played)</div>{lines}'
