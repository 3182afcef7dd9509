"""Breeding tab: one breeding, step by step, for a class (app/lineage/breeding.py). Two parents, from a run's
population or the library; their chromosomes in the chapter's compact notation; the crossover's cut
points; the two children, each gene coloured by the parent it came from; optionally a mutation, gene by
gene; then the children's rules, and parents and children playing side by side from the same start on
small pitches (the population view's, one GameBatch). Seeded: Breed with the same seed repeats it."""

from __future__ import annotations

import threading
import time
from typing import Callable

import viser

from soccer_lab.app.lineage.breeding import DEFAULT_MUTATION_RATE, BreedingDescription, BreedingError, Parent, breed
from soccer_lab.app.lineage.family_tree import RunLineage
from soccer_lab.app.words import plural
from soccer_lab.app.web.access import ScopedStore
from soccer_lab.app.store import NotFound
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.lineage import NONE, refresh_runs, run_id_of
from soccer_lab.app.web.ui.panels.population import population_html
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.web.ui.pitch import PitchGeometry
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.crossover import CROSSOVERS
from soccer_lab.ga.lineage import LineageError, Place
from soccer_lab.soccer.config import GameConfig, WorldConfig
from soccer_lab.soccer.engine import GameBatch

SETTINGS = "Parents, crossover and seed"
RUN_POPULATION, LIBRARY = "A run's population", "The library"
PARENT_TINTS = ("#bbdefb", "#ffe0b2")  # parent A's genes light blue, parent B's light orange, wherever they go
PARENT_INKS = ("#0d47a1", "#e65100")
CUT_COLOUR = "#d50000"
PITCH_COLUMNS = 2  # parents above, children below
RANKED = 8  # the chosen generation's best players listed under the parents' numbers, to pick them by fitness
STEPS = ("the parents", "the cuts", "the children", "the mutation", "what they do")
INTRO = ("Pick two parents and press Breed, then Next step: the cuts, the children, a mutation, "
         "and the four of them playing from the same start.")


class BreedingPanel:
    """`start_seed()`: the main pitch's seed, where the small pitches start; `game_of_run(run_id)`: the game
    a run's players play in; `app_game`: the game of saved rulebases; `demo`: the built-in rulebase and its
    name, a parent the library always has; `current_run()`: this tab's evolution, if any."""

    def __init__(self, gui: viser.GuiApi, store: ScopedStore, vocabulary: Vocabulary, world: WorldConfig, *,
                 start_seed: Callable[[], int], game_of_run: Callable[[int], GameConfig], app_game: GameConfig,
                 demo: tuple[Rulebase, str], current_run: Callable[[], int | None]):
        self.store = store
        self.vocabulary = vocabulary
        self.codec = ChromosomeCodec(vocabulary)
        self.geometry = PitchGeometry.from_world(world)
        self.start_seed = start_seed
        self.game_of_run = game_of_run
        self.app_game = app_game
        self.demo = demo
        self.current_run = current_run
        # The settings fold away (click their title), leaving the panel to the steps.
        with gui.add_folder(SETTINGS):
            self.source = gui.add_dropdown("Parents from", (RUN_POPULATION, LIBRARY), initial_value=RUN_POPULATION)
            self.run = gui.add_dropdown("Run", (NONE,))
            self.generation = gui.add_number("Parents' generation", initial_value=0, min=0, step=1)
            self.first = gui.add_number("Parent A: individual #", initial_value=0, min=0, step=1)
            self.second = gui.add_number("Parent B: individual #", initial_value=1, min=0, step=1)
            self.ranking = gui.add_html("")
            self.first_saved = gui.add_dropdown("Parent A", (demo[1],))
            self.second_saved = gui.add_dropdown("Parent B", (demo[1],))
            self.crossover = gui.add_dropdown("Crossover operator", tuple(CROSSOVERS),
                                              initial_value=tuple(CROSSOVERS)[0])
            self.seed = gui.add_number("Seed (the same seed gives the same cuts)", initial_value=1, min=0, step=1)
            self.mutate = gui.add_checkbox("Mutate the children", initial_value=True)
            self.rate = gui.add_number("Mutation rate (per gene)", initial_value=DEFAULT_MUTATION_RATE, min=0.01,
                                       max=1.0, step=0.01)
        buttons = gui.add_button_group("Breeding", ("Breed", "Next step", "All steps"))
        self.caption = gui.add_html(_text(INTRO, muted=True))
        self.diagram = gui.add_html("")
        self.pitches = gui.add_html("")
        self.breeding: BreedingDescription | None = None
        self.names: tuple[str, str] = ("", "")
        self.game: GameConfig = app_game
        self.step = 0
        self.batch: GameBatch | None = None
        self.labels: list[str] = []
        self._lock = threading.Lock()  # the buttons' threads replace the games the session loop steps
        self._last_render = 0.0
        self._show_inputs()

        @self.source.on_update
        def _(_: viser.GuiEvent) -> None:
            self._show_inputs()

        @self.run.on_update
        @self.generation.on_update
        def _(_: viser.GuiEvent) -> None:
            self._show_ranking()

        @buttons.on_click
        def _(event: viser.GuiEvent) -> None:
            {"Breed": self.breed, "Next step": self.next_step, "All steps": self.all_steps}[event.target.value]()

        self.refresh()

    # ---- choosing the parents ---------------------------------------------------------------------
    def refresh(self) -> None:
        refresh_runs(self.run, self.store, prefer=self.current_run())
        self._show_ranking()  # a new run, or the chosen one's generation just recorded
        saved = (self.demo[1], *(f"#{r.id} {r.name}" for r in self.store.list_rulebases()))
        for dropdown in (self.first_saved, self.second_saved):
            if tuple(dropdown.options) != saved:
                current = dropdown.value
                dropdown.options = saved
                dropdown.value = current if current in saved else saved[0]

    def _show_ranking(self) -> None:
        """The chosen generation's best players (individual #, fitness, goals), so parents are picked knowingly."""
        run_id = run_id_of(self.run.value)
        text = ""
        if run_id is not None:
            try:
                generation = int(self.generation.value)
                lineage = RunLineage.from_store(self.store, run_id, self.vocabulary).lineage
                if lineage.generations == 0:
                    raise LineageError("the run has finished no generation yet")
                population = lineage.population(generation)
            except (LineageError, NotFound, ValueError) as exc:
                text = f'<span style="color:{style.MUTED}">{escape(str(exc))}</span>'
            else:
                ranked = sorted(range(len(population)), key=lambda i: population[i].fitness)[:RANKED]
                text = (f"Generation {generation}'s best (# · fitness · goals): " +
                        ", ".join(f"<b>#{i}</b> · {population[i].fitness:.3f} · {population[i].goals}" for i in ranked))
        content = (f'<div class="breeding-ranking" style="{style.FONT}; font-size:{style.SMALL_FONT_SIZE + 1}px; '
                   f'color:{style.INK}; margin:0 0 6px 8px">{text}</div>') if text else ""
        if self.ranking.content != content:
            self.ranking.content = content

    def _show_inputs(self) -> None:
        from_run = self.source.value == RUN_POPULATION
        self.ranking.visible = from_run
        for handle in (self.run, self.generation, self.first, self.second):
            handle.visible = from_run
        for handle in (self.first_saved, self.second_saved):
            handle.visible = not from_run

    def _parents(self) -> tuple[Parent, Parent, GameConfig]:
        if self.source.value == LIBRARY:
            return self._saved(self.first_saved.value), self._saved(self.second_saved.value), self.app_game
        run_id = run_id_of(self.run.value)
        if run_id is None:
            raise BreedingError("no run yet: start one in the Evolve tab, or take parents from the library")
        lineage = RunLineage.from_store(self.store, run_id, self.vocabulary).lineage
        generation = int(self.generation.value)
        parents = []
        for index in (int(self.first.value), int(self.second.value)):
            individual = lineage.individual(Place(generation, index))
            parents.append(Parent(f"run #{run_id} gen {generation} #{index} (fitness {individual.fitness:.3f}, "
                                  f"{plural(individual.goals, 'goal')})",
                                  individual.chromosome))
        return parents[0], parents[1], self.game_of_run(run_id)

    def _saved(self, label: str) -> Parent:
        if label == self.demo[1]:
            return Parent(label, self.codec.encode(self.demo[0]))
        record = self.store.get_rulebase(int(label[1:].split(" ", 1)[0]))
        return Parent(record.name, self.codec.encode(parse_rulebase(record.text, self.vocabulary)))

    # ---- the steps -----------------------------------------------------------------------------
    def breed(self) -> None:
        """Breed the chosen parents afresh and show step 1."""
        try:
            first, second, game = self._parents()
            rate = float(self.rate.value) if self.mutate.value else None
            breeding = breed(first, second, self.crossover.value, int(self.seed.value), self.vocabulary,
                             mutation_rate=rate)
        except (BreedingError, LineageError, NotFound, RuleSyntaxError, ValueError) as exc:
            self.caption.content = _text(str(exc), error=True)
            return
        with self._lock:
            self.breeding = BreedingDescription(breeding, self.vocabulary)
            self.game = game
            self.batch = None
        self.step = 1
        self._show()

    def next_step(self) -> None:
        if self.breeding is None:
            self.breed()
            return
        self.step = min(self.step + 1, len(self._steps()))
        self._show()

    def all_steps(self) -> None:
        if self.breeding is None:
            self.breed()
        if self.breeding is not None:
            self.step = len(self._steps())
            self._show()

    def _steps(self) -> list[str]:
        mutated = self.breeding is not None and self.breeding.breeding.children[0].mutation is not None
        return [step for step in STEPS if mutated or step != "the mutation"]

    def _show(self) -> None:
        steps = self._steps()
        current = steps[self.step - 1]
        self.caption.content = _caption(self.breeding, self.step, steps)
        self.diagram.content = _diagram(self.breeding, {steps[i] for i in range(self.step)})
        if current == "what they do":
            self._play()
        else:
            with self._lock:
                self.batch = None
            self.pitches.content = ""

    # ---- playing -------------------------------------------------------------------------------
    def _play(self) -> None:
        """Parents and children from the same start, one batch (an empty rule set hunts, as the engine does)."""
        breeding = self.breeding.breeding
        chromosomes = [p.chromosome for p in breeding.parents] + [c.chromosome for c in breeding.children]
        rulebases = [self.codec.decode(c) for c in chromosomes]
        seed = self.start_seed()
        with self._lock:
            self.batch = GameBatch(rulebases, [seed] * len(rulebases), self.game, self.vocabulary)
            self.labels = [f"{who}{'' if len(r) else ' (no valid rule)'}"
                           for who, r in zip(("Parent A", "Parent B", "Child 1", "Child 2"), rulebases)]
            self._seed = seed
            self._last_render = 0.0
        self._render(force=True)

    def advance(self, ticks: int) -> None:
        """Called by the session loop with the ticks the main pitch advanced."""
        with self._lock:
            if self.batch is None:
                return
            for _ in range(ticks):
                self.batch.step()
        self._render()

    def _render(self, *, force: bool = False) -> None:
        now = time.perf_counter()
        with self._lock:
            if self.batch is None or (not force and now - self._last_render < style.POPULATION_REFRESH_SECONDS):
                return
            self._last_render = now
            batch = self.batch
            grid = population_html(self.geometry, batch.observation, batch.state, self.labels, columns=PITCH_COLUMNS)
        content = (f'<div class="breeding-games" data-games="{len(self.labels)}" style="{style.FONT}; '
                   f'{style.SCROLLBAR_ROOM}; '
                   f'font-size:{style.FONT_SIZE}px">Parents (top) and children (below), all from the start of seed '
                   f"{self._seed}, as the main pitch.{grid}</div>")
        if content != self.pitches.content:  # finished games: nothing more to send
            self.pitches.content = content


def _text(text: str, *, error: bool = False, muted: bool = False) -> str:
    colour = style.ERROR if error else style.MUTED if muted else style.INK
    return (f'<div class="breeding-note" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{colour}">{escape(text)}</div>')


def _caption(described: BreedingDescription, step: int, steps: list[str]) -> str:
    breeding = described.breeding
    cuts = [described.cuts(slot) for slot in (0, 1)]
    after = [" and ".join(str(c) for c in cut) for cut in cuts]
    explain = {
        "the parents": "Each chromosome is a list of genes in the chapter's compact notation: a premise "
                       "(object, term, connector), a consequent (action, direction, power); the premises up to "
                       "a consequent make one rule.",
        "the cuts": f"{breeding.crossover} crossover cuts each parent at its own place (messy chromosomes differ "
                    f"in length): parent A after gene {after[0]}, parent B after gene {after[1]} "
                    f"(seed {breeding.seed}: the same seed cuts the same places).",
        "the children": "Each child takes stretches of both parents, genes unchanged and in order (coloured by the "
                        "parent they came from); a child longer than the maximum length is cut short.",
        "the mutation": "Each gene of a child is hit with the mutation rate's chance (at least one); a hit changes "
                        "one field of the gene to another value (outlined red).",
        "what they do": "The children's rules, decoded; below, parents and children play from the same start.",
    }[steps[step - 1]]
    return (f'<div class="breeding-step" data-step="{step}" data-steps="{len(steps)}" style="{style.FONT}; '
            f'{style.SCROLLBAR_ROOM}; '
            f'font-size:{style.FONT_SIZE}px; color:{style.INK}"><div style="font-weight:700; font-size:'
            f'{style.FONT_SIZE + 2}px">Step {step} of {len(steps)}: {escape(steps[step - 1])}</div>'
            f"<div>{escape(explain)}</div></div>")


def _chip(compact: str, parent: int, mutated: str | None = None) -> str:
    outline = f"; outline:2px solid {CUT_COLOUR}" if mutated else ""
    title = f' title="{escape(mutated)}"' if mutated else ""
    return (f'<code class="gene" data-parent="{parent}" data-mutated="{str(bool(mutated)).lower()}"{title} '
            f'style="background:{PARENT_TINTS[parent]}; color:{style.INK}; border-radius:3px; padding:1px 3px; '
            f'white-space:nowrap{outline}">{escape(compact)}</code>')


CUT = (f'<span class="cut" style="display:inline-block; width:4px; height:1.3em; background:{CUT_COLOUR}; '
       'vertical-align:middle; margin:0 3px"></span>')


def _row(title: str, cells: str, colour: str = style.INK) -> str:
    return (f'<div style="margin:6px 0"><div style="font-weight:700; color:{colour}">{escape(title)}</div>'
            f'<div style="line-height:1.9">{cells}</div></div>')


def _diagram(described: BreedingDescription, shown: set[str]) -> str:
    breeding = described.breeding
    parts = []
    for slot, parent in enumerate(breeding.parents):
        genes = described.parent_genes(slot)
        cuts = set(described.cuts(slot)) if "the cuts" in shown else set()
        cells = " ".join((CUT if g in cuts else "") + _chip(gene, slot) for g, gene in enumerate(genes))
        rules = ""
        if "the children" not in shown:
            rules = "".join(f'<div style="font-size:{style.SMALL_FONT_SIZE + 1}px; color:{style.MUTED}">'
                            f"{escape(rule)}</div>" for rule in described.rules(parent.chromosome))
        parts.append(_row(f"Parent {'AB'[slot]}: {parent.name}", cells + rules, PARENT_INKS[slot]))
    if "the children" in shown:
        mutated = "the mutation" in shown
        for c, child in enumerate(breeding.children):
            stretches = ", then ".join(f"{'AB'[s]}'s genes {a}-{b}" for s, a, b in described.segments(c))
            cells = " ".join(_chip(g.compact, g.parent, g.mutated) for g in described.child_genes(c, mutated=mutated))
            changes = ""
            if mutated:
                changes = "".join(f'<div class="breeding-mutation" style="color:{CUT_COLOUR}; font-size:'
                                  f'{style.SMALL_FONT_SIZE + 1}px">{escape(change)}</div>'
                                  for change in described.changes(c))
            rules = ""
            if "what they do" in shown:
                decoded = described.rules(child.chromosome)
                rules = "".join(f'<div style="font-size:{style.SMALL_FONT_SIZE + 1}px">{escape(rule)}</div>'
                                for rule in decoded) or (f'<div style="color:{style.MUTED}">no valid rule: the GA '
                                                         f"scores it 1.0 without playing it</div>")
            parts.append(_row(f"Child {c + 1}: {stretches}", cells + changes + rules))
    return (f'<div class="breeding" data-shown="{len(shown)}" style="{style.FONT}; {style.SCROLLBAR_ROOM}; '
            f'font-size:{style.FONT_SIZE}px; '
            f'color:{style.INK}">{"".join(parts)}</div>')
