"""The evolve panel starts a run on rcssservers the run starts itself (the app's rcssserver), on a real
viser server (no browser) and real servers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from soccer_lab.app.runs.outputs import RECORDING
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import RunStatus, Store
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.soccer.config import SOCCER_VOCABULARY
from soccer_lab.soccer.rcss.trial import start_position
from tests.app.api_client import wait_for
from tests.app.test_cli_evolve import generation_bests, read_recording
from tests.app.test_ui_wiring import gui  # noqa: F401  (fixture)
from tests.rcss.real_server import rcssserver_children


@pytest.fixture
def runs(tmp_path, rcssserver):
    store = Store(tmp_path / "db.sqlite3")
    manager = RunManager(store, tmp_path, rcssserver=rcssserver)
    yield manager, store
    manager.shutdown()
    store.close()


def test_a_run_on_two_rcssservers_from_the_evolve_panel(gui, runs):  # noqa: F811
    from soccer_lab.app.web.ui.panels.evolve import RCSSSERVER, EvolvePanel

    manager, store = runs
    before = rcssserver_children()
    panel = EvolvePanel(gui, manager, store, on_load=lambda *_: None, on_generation=lambda *_: None,
                        on_run_ended=lambda *_: None, on_runs_changed=lambda: None)
    panel.where.value, panel.servers.value = RCSSSERVER, 2
    for name, value in {"population_size": 4, "max_generations": 2, "max_length": 16, "seed": 3}.items():
        panel.inputs[name].value = value
    panel.start()
    record = store.get_run(panel.run_id)
    assert (record.config["env"], record.config["start_servers"], record.config["ga"]["workers"]) == ("rcss", 2, 1)
    done = wait_for(lambda: (r := store.get_run(panel.run_id)).status != RunStatus.RUNNING and r, timeout=180,
                    what="the run to end")
    assert done.status == RunStatus.FINISHED, done.error
    assert len(store.statistics(panel.run_id)) == 2
    assert rcssserver_children() == before  # the run's servers went with it
    # The recording replays each generation's best player's first trial (where it has a rule to play),
    # as the server played it: from where the trainer put the player for that trial's seed, the ball on
    # the centre spot.
    folder = Path(done.folder)
    entities = read_recording(folder / RECORDING)
    codec = ChromosomeCodec(SOCCER_VOCABULARY)
    playable = [(g, best) for g, best in generation_bests(folder) if len(codec.decode(best.chromosome))]
    assert playable
    for generation, best in playable:
        player = entities[f"/replay/generation_{generation}/player"]["columns"]["Points2D:positions"]
        ball = entities[f"/replay/generation_{generation}/ball"]["columns"]["Points2D:positions"]
        assert player[0][0] == pytest.approx(start_position(np.random.default_rng(best.first_seed)), abs=0.01)
        assert ball[0][0] == pytest.approx((0.0, 0.0), abs=0.01)
