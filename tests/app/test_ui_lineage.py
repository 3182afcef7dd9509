"""The Lineage and Breeding tabs and the Evolve tab's diversity plot, driven in headless Chromium: a small
evolution from the Evolve tab, the family tree of its best so far, of any individual and of a player of the
population view, a player loaded from its tree onto the pitch, one breeding step by step from the run's
population and from the library (the same seed breeds the same children), parents and children playing
from the same start. Screenshots go to artifacts/screenshots/ (scripts/lineage_screenshots.py makes the
documentation's)."""

from __future__ import annotations

import re
from urllib.parse import urlparse

import numpy as np
import pytest

from soccer_lab.app.lineage.breeding import BreedingDescription, Parent, breed
from soccer_lab.app.lineage.family_tree import RunLineage
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.lineage import Place
from soccer_lab.soccer.engine import GameBatch
from tests.app.test_ui_browser import (CHROMIUM, CHROMIUM_ARGS, TIMEOUT_MS, VIEWPORT, choose,  # noqa: F401
                                       dismiss_notifications, field, free_port, pytestmark, shot, wait_until)

VOCABULARY = Vocabulary.default()
CODEC = ChromosomeCodec(VOCABULARY)
POPULATION, GENERATIONS, BEHAVIOUR_SEEDS = 16, 4, 2
ELSEWHERE: list[str] = []  # requests the page made to any host but the app's own
SAVED_TEXT = "if Ball is VeryNear then KickTowardGoal High\nif Ball is not VeryNear then GoToBall VeryHigh"


def session_of(ui):
    """The page's session, once built (on a loaded machine the page may have reconnected: the newest)."""
    def ready():
        with ui.lock:
            return next((s for s in reversed(list(ui.sessions.values())) if s.ready.is_set()), None)

    return wait_until(ready, timeout=TIMEOUT_MS / 1000)


@pytest.fixture(scope="module")
def ui(tmp_path_factory):
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui import start_ui

    data = tmp_path_factory.mktemp("ui-lineage")
    store = Store(data / "db.sqlite3")
    store.create_rulebase("kick when very near", SAVED_TEXT)
    runs = RunManager(store, data)
    handle = start_ui(store, runs, port=free_port())
    yield handle
    handle.stop()
    runs.shutdown(wait=10)
    store.close()


@pytest.fixture(scope="module")
def page(ui):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport=VIEWPORT)
        page.set_default_timeout(TIMEOUT_MS)
        own = urlparse(ui.url).hostname
        page.on("request", lambda request: urlparse(request.url).scheme in ("http", "https", "ws", "wss")
                and urlparse(request.url).hostname != own and ELSEWHERE.append(request.url))
        page.goto(ui.url)
        page.locator(".game-status").wait_for()
        dismiss_notifications(page)
        yield page
        browser.close()


def fill(page, label: str, value: object) -> None:
    field(page, label, "input").fill(str(value))
    field(page, label, "input").press("Tab")


def evolve_in_page(page, session, population: int, generations: int, behaviour_seeds: int) -> int:
    """Start an elitist run from the Evolve tab, as a teacher does, and wait for its end; its id."""
    page.get_by_role("tab", name="Evolve").click()
    page.get_by_text("GA parameters (chapter's Table 2)").click()
    for label, value in (("Population size", population), ("Generations (max)", generations),
                         ("Behaviour seeds (count distinct behaviours; 0: off)", behaviour_seeds)):
        fill(page, label, value)
    choose(page, "Selection", "elitist", exact=True)
    wait_until(lambda: session.evolve.config()["behaviour_seeds"] == behaviour_seeds
               and session.evolve.config()["population_size"] == population
               and session.evolve.config()["selection"] == "elitist")
    page.get_by_role("button", name="Start").click()
    status = page.locator(".evolve-status")
    wait_until(lambda: "finished" in status.inner_text(), timeout=300)
    return session.evolve.run_id


def show_tree(page, which: str, **numbers: int) -> None:
    page.get_by_role("tab", name="Lineage").click()
    choose(page, "Player", which, exact=True)
    for label, value in numbers.items():
        fill(page, label, value)
    page.get_by_role("button", name="Show").click()


def tree_shown(page, session, place: Place) -> None:
    lineage = page.locator(".lineage")
    wait_until(lambda: lineage.count() and (int(lineage.get_attribute("data-generation")),
                                            int(lineage.get_attribute("data-index"))) == tuple(place))


@pytest.fixture(scope="module")
def run_id(ui, page):
    session = session_of(ui)
    run = evolve_in_page(page, session, POPULATION, GENERATIONS, BEHAVIOUR_SEEDS)
    shot(page, "lineage-1-evolve-diversity")
    return run


def test_the_evolve_tab_plots_diversity_as_the_run_goes(ui, page, run_id):
    stats = ui.context.store.statistics(run_id)
    page.get_by_role("tab", name="Evolve").click()
    titles = page.locator(".u-title")
    wait_until(lambda: any("Diversity" in t for t in titles.all_inner_texts()))
    legend = page.locator(".u-legend").nth(1).inner_text()
    last = stats[-1]
    assert f"distinct chromosomes {last['distinct_chromosomes']}/{POPULATION}" in legend
    assert f"distinct behaviours {last['distinct_behaviours']}/{POPULATION} on {BEHAVIOUR_SEEDS} seeds" in legend
    assert f"rule-set distance {last['rule_set_distance']:.2f}" in legend
    assert f"{last['distinct_rules']} distinct rules" in titles.nth(1).inner_text()
    plot = session_of(ui).evolve.diversity
    np.testing.assert_allclose(plot.plot.data[1], [s["distinct_chromosomes"] / POPULATION for s in stats])


def test_the_best_so_far_shows_its_ancestors_and_where_each_rule_came_from(ui, page, run_id):
    session = session_of(ui)
    lineage = RunLineage.from_store(ui.context.store, run_id, VOCABULARY)
    expected = lineage.family_tree(lineage.place())
    show_tree(page, "Best so far")
    tree_shown(page, session, expected.chosen)
    shown = page.locator(".lineage")
    assert int(shown.get_attribute("data-ancestors")) == len(expected.tree.ancestors)
    assert page.locator(".lineage svg .ancestor").count() == min(len(expected.tree.ancestors), sum(
        min(len(row), 4 - (len(row) > 4)) for row in expected.rows()))
    letters = [rule.get_attribute("data-letter") for rule in page.locator(".lineage-rule").all()]
    assert letters == [rule.letter for rule in expected.rules]
    text = shown.inner_text()
    for rule in expected.rules:
        assert rule.text in text and rule.summary in text
    assert page.locator(".lineage-gene").count() == len(expected.tree.individual.chromosome)
    shot(page, "lineage-2-best-so-far")


def test_any_individual_has_a_tree_and_can_be_put_on_the_pitch(ui, page, run_id):
    session = session_of(ui)
    show_tree(page, "Any individual", **{"Generation": GENERATIONS - 1, "Individual #": 5,
                                         "Generations back (0: to generation 0)": 1})
    tree_shown(page, session, Place(GENERATIONS - 1, 5))
    assert "back to generation 2" in page.locator(".lineage").inner_text()
    assert {int(g.get_attribute("data-generation")) for g in page.locator(".lineage svg .ancestor").all()} <= {2, 3}
    page.get_by_role("button", name="Load onto the pitch").click()
    wait_until(lambda: session.game.name == f"run #{run_id} gen {GENERATIONS - 1} #5")
    individual = RunLineage.from_store(ui.context.store, run_id, VOCABULARY).lineage.individual(Place(GENERATIONS - 1, 5))
    assert session.game.rulebase == CODEC.decode(individual.chromosome)
    show_tree(page, "Any individual", **{"Generation": GENERATIONS + 5})
    note = page.locator(".lineage-note[data-error='true']")
    wait_until(lambda: note.count() and f"not {GENERATIONS + 5}" in note.inner_text())
    fill(page, "Generations back (0: to generation 0)", 0)


def test_a_player_of_the_population_view_has_its_tree(ui, page, run_id):
    session = session_of(ui)
    page.get_by_role("tab", name="Population").click()
    wait_until(lambda: session.population.shown_players() is not None)
    shown_run, generation, players = session.population.shown_players()
    assert (shown_run, generation) == (run_id, GENERATIONS - 1)
    show_tree(page, "Player in the population view", **{"Rank in the population view": 2})
    tree_shown(page, session, Place(generation, players[1].index))
    ranked = sorted(range(POPULATION), key=lambda i: RunLineage.from_store(
        ui.context.store, run_id, VOCABULARY).lineage.individual(Place(generation, i)).fitness)
    assert players[1].index in ranked[:len(players)]


def breeding_step(page) -> int:
    return int(page.locator(".breeding-step").get_attribute("data-step"))


def test_one_breeding_step_by_step_from_the_runs_population(ui, page, run_id):
    session = session_of(ui)
    page.get_by_role("tab", name="Breeding").click()
    generation = GENERATIONS - 1
    for label, value in (("Parents' generation", generation), ("Parent A: individual #", 0),
                         ("Parent B: individual #", 3), ("Seed (the same seed gives the same cuts)", 7)):
        fill(page, label, value)
    choose(page, "Crossover operator", "two-point", exact=True)  # not the Evolve tab's Crossover
    wait_until(lambda: session.breeding.crossover.value == "two-point" and int(session.breeding.seed.value) == 7
               and int(session.breeding.second.value) == 3)
    lineage = RunLineage.from_store(ui.context.store, run_id, VOCABULARY).lineage
    # under the parents' numbers, the chosen generation's best players: picked by fitness, not blindly
    population = lineage.population(generation)
    best_first = sorted(range(len(population)), key=lambda i: population[i].fitness)[:8]
    ranking = page.locator(".breeding-ranking", has_text=f"Generation {generation}'s best")
    ranking.wait_for()
    assert [int(n) for n in re.findall(r"#(\d+) ·", ranking.inner_text())] == best_first
    parents = [Parent(str(i), lineage.individual(Place(generation, i)).chromosome) for i in (0, 3)]
    expected = BreedingDescription(breed(*parents, "two-point", 7, VOCABULARY, mutation_rate=0.1), VOCABULARY)
    page.get_by_role("button", name="Breed").click()
    wait_until(lambda: page.locator(".breeding-step").count() and breeding_step(page) == 1)
    assert page.locator(".breeding .cut").count() == 0
    page.get_by_role("button", name="Next step").click()  # the cuts: two in each parent
    wait_until(lambda: breeding_step(page) == 2)
    assert page.locator(".breeding .cut").count() == len(set(expected.cuts(0))) + len(set(expected.cuts(1)))
    shot(page, "lineage-3-breeding-cuts")
    page.get_by_role("button", name="Next step").click()  # the children, gene by gene from their parents
    wait_until(lambda: breeding_step(page) == 3)
    genes = page.locator(".breeding .gene")
    parent_genes = sum(len(p.chromosome) for p in parents)
    children = [expected.child_genes(c, mutated=False) for c in (0, 1)]
    assert genes.count() == parent_genes + sum(len(c) for c in children)
    shown = [int(g) for g in genes.evaluate_all("cells => cells.map(c => c.dataset.parent)")][parent_genes:]
    assert shown == [cell.parent for child in children for cell in child]
    page.get_by_role("button", name="Next step").click()  # the mutation, gene by gene
    wait_until(lambda: breeding_step(page) == 4)
    changes = expected.changes(0) + expected.changes(1)
    assert page.locator(".breeding-mutation").all_inner_texts() == changes
    assert page.locator(".breeding .gene[data-mutated='true']").count() == len(changes)
    shot(page, "lineage-4-breeding-mutation")
    page.get_by_role("button", name="Next step").click()  # what they do: the four play from the same start
    wait_until(lambda: breeding_step(page) == 5)
    wait_until(lambda: page.locator(".breeding-games .mini-pitch").count() == 4)
    panel = session.breeding
    rulebases = [CODEC.decode(p.chromosome) for p in parents] + [
        CODEC.decode(c.chromosome) for c in expected.breeding.children]
    with panel._lock:
        ticks = int(panel.batch.state.ticks.max())
        observation = [np.array(column, copy=True) for column in panel.batch.observation]
    reference = GameBatch(rulebases, [session.game.seed] * 4, panel.game, VOCABULARY)
    for _ in range(ticks):
        reference.step()
    for seen, wanted in zip(observation, reference.observation):
        np.testing.assert_array_equal(seen, wanted)
    shot(page, "lineage-5-breeding-play")


def test_the_same_seed_breeds_the_same_children_from_the_library(ui, page, run_id):
    session = session_of(ui)
    page.get_by_role("tab", name="Breeding").click()
    choose(page, "Parents from", "The library", exact=True)
    choose(page, "Parent B", next(o for o in session.breeding.second_saved.options if "kick when very near" in o))
    wait_until(lambda: "kick when very near" in session.breeding.second_saved.value)

    def bred() -> list[str]:
        page.get_by_role("button", name="Breed").click()
        wait_until(lambda: breeding_step(page) == 1)
        page.get_by_role("button", name="All steps").click()
        wait_until(lambda: breeding_step(page) == int(page.locator(".breeding-step").get_attribute("data-steps")))
        return page.locator(".breeding").inner_text()

    first = bred()
    assert re.search(r"Parent A: demo \(built in\)", first) and "Parent B: kick when very near" in first
    assert bred() == first
    fill(page, "Seed (the same seed gives the same cuts)", 8)
    wait_until(lambda: int(session.breeding.seed.value) == 8)
    assert bred() != first


def test_nothing_the_tabs_show_is_fetched_from_elsewhere(ui, page, run_id):
    """After every view above (trees, breedings, games): the page asked the app's own address only."""
    for tab in ("Lineage", "Breeding", "Evolve", "Population"):
        page.get_by_role("tab", name=tab).click()
    page.wait_for_timeout(1000)
    assert ELSEWHERE == []
