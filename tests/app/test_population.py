"""The population view's data path: the RunManager samples each finished generation's best playable
individuals into its event, and the population panel plays exactly those in one GameBatch."""

from __future__ import annotations

import re
import threading
import time
from types import SimpleNamespace

import numpy as np
import pytest

from soccer_lab.app.runs.manager import SAMPLED_PLAYERS, RunEvent, RunManager, SampledPlayer, sample_players
from soccer_lab.app.store import Store
from soccer_lab.app.web.ui import style
from soccer_lab.app.runs.true_quality import TRUE_QUALITY_STARTS, TrueQuality, simple_soccer_batch_replayer
from soccer_lab.app.web.ui.panels.population import PopulationPanel
from soccer_lab.app.web.ui.player_qualities import PlayerQualities
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.notation import parse_compact
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import GameBatch
from tests.app.api_client import SHORT_GAMES, TINY_GA

VOCABULARY = Vocabulary.default()

CODEC = ChromosomeCodec(VOCABULARY)
SCORER = "(B,vN,A)(KG,n,H)"  # if Ball is VeryNear then KickTowardGoal High
CHASER = "(B,nF,A)(GB,n,M)"  # if Ball is not Far then GoToBall MediumPower
INVALID = "(T,L,n)(B,N,A)"  # a consequent with no premise, then a premise with no consequent: no rule


def individual(compact: str, fitness: float) -> Individual:
    return Individual(parse_compact(compact, VOCABULARY)).evaluated(fitness, 0)


def test_sample_is_the_best_playable_individuals_best_first():
    population = [individual(CHASER, 0.7), individual(INVALID, 0.1), individual(SCORER, 0.4),
                  individual(CHASER, 0.4)]
    sampled = sample_players(population, CODEC, count=2)
    assert [p.fitness for p in sampled] == [0.4, 0.4]  # the invalid one (never played) is skipped
    # Equal fitness keeps population order: the scorer came before the second chaser.
    assert [format_rulebase(p.rulebase, VOCABULARY) for p in sampled] == [
        format_rulebase(CODEC.decode(parse_compact(text, VOCABULARY)), VOCABULARY) for text in (SCORER, CHASER)]
    assert len(sample_players(population, CODEC)) == 3
    assert sample_players([individual(INVALID, 1.0)], CODEC) == ()


def test_every_finished_generation_is_published_with_its_best_players(tmp_path):
    store = Store(tmp_path / "db.sqlite3")
    runs = RunManager(store, tmp_path)
    events: list[RunEvent] = []
    lock = threading.Lock()

    def listen(event: RunEvent) -> None:
        with lock:
            events.append(event)

    runs.add_listener(listen)
    try:
        record = runs.start("sampled", ga={**TINY_GA, "population_size": 16}, game=SHORT_GAMES)
        runs.wait(record.id, timeout=120)
    finally:
        runs.shutdown()
    generations = [e for e in events if e.stats is not None]
    assert [e.stats["generation"] for e in generations] == [0, 1]
    for event, best in zip(generations, store.best_individuals(record.id)):
        players = event.players
        assert 0 < len(players) <= SAMPLED_PLAYERS
        fitnesses = [p.fitness for p in players]
        assert fitnesses == sorted(fitnesses) and all(len(p.rulebase) for p in players)
        if best.fitness < 1.0:  # the best individual played, so it leads the sample
            assert fitnesses[0] == best.fitness and format_rulebase(players[0].rulebase, VOCABULARY) == best.rules
    store.close()


class FakeButton(SimpleNamespace):
    def on_click(self, callback) -> None:
        self.click = lambda: callback(None)


class FakeGui:
    """Only what the panel asks of viser: HTML elements whose content it sets, a button it labels and shows."""

    def add_html(self, content: str) -> SimpleNamespace:
        return SimpleNamespace(content=content)

    def add_button(self, label: str, **props) -> FakeButton:
        return FakeButton(label=label, **props)


GAME = GameConfig(max_ticks=200)
SEED = 5  # the main pitch's seed, where every small pitch starts


def population_panel(games: dict[int, GameConfig] | None = None, asked: list[int] | None = None) -> PopulationPanel:
    """A panel whose runs play in `games` (by run id; GAME for any other run), noting each run asked for."""
    def game_of_run(run_id: int) -> GameConfig:
        (asked if asked is not None else []).append(run_id)
        return (games or {}).get(run_id, GAME)

    return PopulationPanel(FakeGui(), GAME.world, VOCABULARY, start_seed=lambda: SEED, game_of_run=game_of_run)


def assert_plays(panel: PopulationPanel, rulebases, game: GameConfig, ticks: int) -> None:
    """The panel's batch is the very games the engine plays for `rulebases` in `game`, from the session's start."""
    reference = GameBatch(rulebases, [SEED] * len(rulebases), game, VOCABULARY)
    for _ in range(ticks):
        reference.step()
    for seen, expected in zip(panel.batch.observation, reference.observation):
        np.testing.assert_array_equal(seen, expected)
    np.testing.assert_array_equal(panel.batch.state.kicks, reference.state.kicks)


def test_panel_plays_the_published_players_in_one_batch_from_one_start(monkeypatch):
    monkeypatch.setattr(style, "POPULATION_REFRESH_SECONDS", 0.0)
    panel = population_panel()
    panel.advance(3)
    assert panel.batch is None and "Start an evolution" in panel.grid.content
    rulebases = [CODEC.decode(parse_compact(text, VOCABULARY)) for text in (SCORER, CHASER, SCORER)]
    players = tuple(SampledPlayer(r, f) for r, f in zip(rulebases, (0.25, 0.5, 0.75)))
    panel.generation_finished(9, 4, players)
    panel.advance(30)
    assert panel.batch.games == 3 and panel.labels == ["#1 · 0.25", "#2 · 0.50", "#3 · 0.75"]
    assert 'data-run="9" data-generation="4"' in panel.caption.content
    assert panel.grid.content.count('class="mini-pitch"') == 3
    assert_plays(panel, rulebases, GAME, ticks=30)


def test_panel_shows_at_most_the_grid_and_ignores_an_empty_generation():
    panel = population_panel()
    rulebase = CODEC.decode(parse_compact(CHASER, VOCABULARY))
    many = tuple(SampledPlayer(rulebase, 0.5) for _ in range(SAMPLED_PLAYERS + 4))
    panel.generation_finished(1, 0, many)
    panel.advance(1)
    assert panel.batch.games == min(len(many), style.POPULATION_GRID[0] * style.POPULATION_GRID[1])
    batch = panel.batch
    panel.generation_finished(1, 1, ())
    panel.advance(1)
    assert panel.batch is batch


def test_the_caption_says_when_the_run_has_ended():
    panel = population_panel()
    players = (SampledPlayer(CODEC.decode(parse_compact(CHASER, VOCABULARY)), 0.5),)
    panel.generation_finished(3, 7, players)
    panel.advance(1)
    assert 'data-generation="7"' in panel.caption.content and "while generation 8 is evaluated" in panel.caption.content
    panel.run_ended(3, "finished")
    panel.advance(1)
    assert 'data-ended="true"' in panel.caption.content and "evaluated" not in panel.caption.content
    assert "the run finished after this generation" in panel.caption.content


def test_each_run_plays_in_its_own_game():
    assisted = GameConfig(max_ticks=200, skills="assisted", count_touches=True)
    asked: list[int] = []
    panel = population_panel({4: assisted}, asked)
    rulebases = [CODEC.decode(parse_compact(text, VOCABULARY)) for text in (SCORER, CHASER)]
    players = tuple(SampledPlayer(r, 0.5) for r in rulebases)
    for run_id, game in ((4, assisted), (9, GAME)):
        for generation in range(2):
            panel.generation_finished(run_id, generation, players)
            panel.advance(40)
            assert_plays(panel, rulebases, game, ticks=40)
        words = "assisted skills · body pushes count as kicks" if game is assisted else f"({GAME.skills} skills)"
        assert words in panel.caption.content
    assert asked == [4, 9]  # once per run: its settings do not change while it runs
    # Which matters: far from the ball, KickTowardGoal fetches it with assisted skills only.
    fetcher = [CODEC.decode(parse_compact("(B,nF,A)(KG,n,H)", VOCABULARY))]
    moved = []
    for game in (GAME, assisted):
        batch = GameBatch(fetcher, [SEED], game, VOCABULARY)
        start = batch.observation.player_x.copy()
        for _ in range(40):
            batch.step()
        moved.append(not np.array_equal(batch.observation.player_x, start))
    assert moved == [False, True]


# ---- true quality under each small pitch (app/runs/true_quality.py) ---------------------------------
def wait_until(condition, seconds: float = 60.0) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


def test_population_view_shows_each_players_replayed_quality_beside_its_fitness(monkeypatch):
    monkeypatch.setattr(style, "POPULATION_REFRESH_SECONDS", 0.0)
    qualities = PlayerQualities(VOCABULARY, share=None)  # every shown player, whatever it costs
    panel = PopulationPanel(FakeGui(), GAME.world, VOCABULARY, start_seed=lambda: SEED, game_of_run=lambda _: GAME,
                            qualities=qualities)
    rulebases = [CODEC.decode(parse_compact(text, VOCABULARY)) for text in (SCORER, CHASER)]
    panel.generation_finished(2, 0, tuple(SampledPlayer(r, f) for r, f in zip(rulebases, (0.25, 0.5))))
    panel.advance(1)
    wait_until(lambda: (panel.advance(1), panel.player_qualities())[1] is not None)
    expected = simple_soccer_batch_replayer(GAME, VOCABULARY)(rulebases)
    assert panel.player_qualities() == expected  # the same common starts as every run's best
    assert [q.starts for q in expected] == [TRUE_QUALITY_STARTS] * 2
    panel.advance(1)
    lines = re.findall(r'data-replayed="([0-9.]+)"', panel.grid.content)
    assert [float(value) for value in lines] == pytest.approx([q.fitness for q in expected], abs=1e-6)
    assert f"re-played {expected[0].fitness:.2f} ± {expected[0].fitness_std:.2f}" in panel.grid.content
    assert f"re-played on the same {TRUE_QUALITY_STARTS} fresh starts" in panel.caption.content
    assert 'data-replaying="false"' in panel.caption.content and "(mean ± spread).</div>" in panel.caption.content
    assert not panel.replay_button.visible  # nothing left to re-play


def test_population_replays_stay_off_the_frame_loop_and_replay_an_elite_once(monkeypatch):
    """The re-play runs on its own thread: a frame never waits for it, and a player shown again (an elite
    in the next generation, or in another tab) is not re-played."""
    release, replayed = threading.Event(), []

    def slow_replayer(game, vocabulary, starts):
        replay = simple_soccer_batch_replayer(game, vocabulary, starts)

        def batch(rulebases):
            replayed.append(len(rulebases))
            release.wait(30)
            return replay(rulebases)
        return batch

    qualities = PlayerQualities(VOCABULARY, replayer_for=slow_replayer, share=None)
    panel = PopulationPanel(FakeGui(), GAME.world, VOCABULARY, start_seed=lambda: SEED, game_of_run=lambda _: GAME,
                            qualities=qualities)
    scorer, chaser = (CODEC.decode(parse_compact(text, VOCABULARY)) for text in (SCORER, CHASER))
    panel.generation_finished(2, 0, (SampledPlayer(scorer, 0.25),))
    started = time.perf_counter()
    for _ in range(5):
        panel.advance(2)  # frames go on while the re-play waits
    assert time.perf_counter() - started < 5 and panel.player_qualities() is None
    assert 'data-replaying="true"' in panel.caption.content and "re-playing the best" in panel.caption.content
    release.set()
    wait_until(lambda: (panel.advance(1), panel.player_qualities())[1] is not None)
    panel.generation_finished(2, 1, (SampledPlayer(scorer, 0.25), SampledPlayer(chaser, 0.5)))
    panel.advance(1)
    wait_until(lambda: (panel.advance(1), panel.player_qualities())[1] is not None)
    assert replayed == [1, 1]  # generation 1 re-played only the chaser: the scorer's figure was known
    assert len(panel.player_qualities()) == 2


def test_an_rcss_runs_players_get_no_simple_soccer_quality(monkeypatch):
    monkeypatch.setattr(style, "POPULATION_REFRESH_SECONDS", 0.0)
    panel = PopulationPanel(FakeGui(), GAME.world, VOCABULARY, start_seed=lambda: SEED, game_of_run=lambda _: GAME,
                            qualities=PlayerQualities(VOCABULARY), replayable=lambda run_id: False)
    panel.generation_finished(3, 0, (SampledPlayer(CODEC.decode(parse_compact(CHASER, VOCABULARY)), 0.5),))
    panel.advance(1)
    assert 'class="replayed"' not in panel.grid.content and "re-played on" not in panel.caption.content
    assert not panel.replay_button.visible


def test_population_replays_keep_to_their_share_of_the_time_best_ranked_first():
    """Re-playing 12 players on 20 starts each generation cost 80% of a Table 2 run: the re-plays now spend
    at most their share of the wall time, best-ranked first, and say which players they had no time for."""
    now, replayed = [0.0], []

    def costly_replayer(game, vocabulary, starts):
        def batch(rulebases):
            replayed.append(list(rulebases))
            now[0] += 0.1 * len(rulebases)  # 0.1 s a player
            return [TrueQuality(starts, 0.5, 0.1, 1.0, 0.5) for _ in rulebases]
        return batch

    qualities = PlayerQualities(VOCABULARY, replayer_for=costly_replayer, share=0.05, clock=lambda: now[0])
    players = [CODEC.decode(parse_compact(f"(B,vN,A)(KG,n,H)(B,nF,A)(GB,n,{level})", VOCABULARY))
               for level in ("vL", "L", "sL", "M", "sH", "H", "vH")]
    first = qualities._qualities(1, GAME, players)
    assert [q is not None for q in first] == [True] + [False] * 6  # the best first: it measures the cost
    now[0] += 10.0  # a generation later: 5% of 10 s pays for 0.5 s less the 0.1 s spent
    second = qualities._qualities(1, GAME, players)
    assert replayed[1] == players[1:5] and [q is not None for q in second] == [True] * 5 + [False] * 2
    assert qualities.spent <= 0.05 * now[0] + 0.1  # within the share, give or take the first measure
    now[0] += 3600.0  # an idle hour saves no burst: at most a minute's share
    qualities._qualities(1, GAME, players + [CODEC.decode(parse_compact(SCORER, VOCABULARY))])
    assert len(replayed[2]) == 3 and replayed[2] == players[5:] + [CODEC.decode(parse_compact(SCORER, VOCABULARY))]


def test_the_replay_button_replays_every_shown_player_beyond_the_share(monkeypatch):
    """Within 5% of the time the grid's players stayed "not re-played" (0 of 12 under every pitch): the
    caption says once how many are re-played, the empty pitches say nothing, and "Measure these N on 20
    fresh starts" re-plays the rest (their cost stated) without spending the background's share."""
    monkeypatch.setattr(style, "POPULATION_REFRESH_SECONDS", 0.0)
    now, replayed = [0.0], []

    def costly_replayer(game, vocabulary, starts):
        def batch(rulebases):
            replayed.append(len(rulebases))
            now[0] += 0.1 * len(rulebases)  # 0.1 s a player
            return [TrueQuality(starts, 0.5 + 0.01 * len(replayed), 0.1, 1.0, 0.5) for _ in rulebases]
        return batch

    qualities = PlayerQualities(VOCABULARY, replayer_for=costly_replayer, share=0.05, clock=lambda: now[0])
    panel = PopulationPanel(FakeGui(), GAME.world, VOCABULARY, start_seed=lambda: SEED, game_of_run=lambda _: GAME,
                            qualities=qualities)
    players = tuple(SampledPlayer(CODEC.decode(parse_compact(f"(B,vN,A)(KG,n,H)(B,nF,A)(GB,n,{level})", VOCABULARY)),
                                  0.1 * rank) for rank, level in enumerate(("vL", "L", "sL", "M"), start=1))
    panel.generation_finished(1, 0, players)
    panel.advance(1)
    wait_until(lambda: (panel.advance(1), panel.player_qualities())[1] is not None)
    panel.advance(1)
    assert replayed == [1]  # the best measured the cost; the share paid for no more
    assert "not re-played" not in panel.grid.content and panel.grid.content.count("re-played 0.") == 1
    assert "1 of 4 so far" in panel.caption.content and 'data-replayed="1"' in panel.caption.content
    assert "measures the rest (60 games, about 0.3 s)" in panel.caption.content  # the cost, before it is paid
    assert panel.replay_button.visible and not panel.replay_button.disabled
    assert panel.replay_button.label == f"Measure these 4 on {TRUE_QUALITY_STARTS} fresh starts"
    allowance = qualities._allowance
    panel.replay_button.click()  # on viser's thread: the next frame asks
    panel.advance(1)
    assert panel.replay_button.disabled and "re-playing all 4…" in panel.caption.content
    wait_until(lambda: (panel.advance(1), panel.player_qualities())[1].count(None) == 0)
    panel.advance(1)
    assert replayed == [1, 3] and qualities._allowance == allowance  # the rest, not charged to the share
    assert panel.grid.content.count("re-played 0.") == 4 and 'data-replayed="4"' in panel.caption.content
    assert not panel.replay_button.visible  # nothing left to re-play
