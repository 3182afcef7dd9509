import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from ga_synthetic import SyntheticEvaluator

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import evolve, random_search, resume
from soccer_lab.ga.checkpoint import CheckpointError, load_checkpoint
from soccer_lab.ga.config import GAConfig

VOCABULARY = Vocabulary.default()

CONFIG = GAConfig(population_size=24, max_generations=10, max_length=20, selection="elitist",
                  target_fitness=0.0, seed=11)
HELPERS = Path(__file__).parent

RUN_IN_SUBPROCESS = """
import sys
sys.path.insert(0, sys.argv[2])
from ga_synthetic import SyntheticEvaluator
from soccer_lab.ga.algorithms import evolve
from soccer_lab.ga.config import GAConfig
from soccer_lab.fuzzy.vocabulary import Vocabulary
evolve(GAConfig.model_validate_json(sys.argv[3]), SyntheticEvaluator(delay=0.15), Vocabulary.default(),
       checkpoint=sys.argv[1])
"""


def comparable(result):
    history = [{k: v for k, v in s.to_dict().items() if k != "wall_time"} for s in result.history]
    return history, result.best.to_dict(), [i.to_dict() for i in result.population], result.stop_reason


def generation_in(path: Path) -> int:
    return len(json.loads(path.read_text())["history"]) - 1 if path.exists() else -1


def test_a_killed_run_resumes_and_finishes_exactly_like_the_uninterrupted_run(tmp_path):
    checkpoint = tmp_path / "run.json"
    process = subprocess.Popen([sys.executable, "-c", RUN_IN_SUBPROCESS, str(checkpoint), str(HELPERS),
                                CONFIG.model_dump_json()])
    deadline = time.monotonic() + 120
    while generation_in(checkpoint) < 2:
        assert process.poll() is None, "the run ended before it could be killed"
        assert time.monotonic() < deadline, "no checkpoint of generation 2"
        time.sleep(0.005)
    os.kill(process.pid, signal.SIGKILL)
    assert process.wait() == -signal.SIGKILL
    killed_at = generation_in(checkpoint)
    assert 2 <= killed_at < CONFIG.max_generations - 1  # really mid-run

    resumed = resume(checkpoint, SyntheticEvaluator())
    uninterrupted = evolve(CONFIG, SyntheticEvaluator(), VOCABULARY)
    assert comparable(resumed) == comparable(uninterrupted)
    assert resumed.history[killed_at].wall_time <= resumed.history[-1].wall_time  # wall time carries on
    assert generation_in(checkpoint) == CONFIG.max_generations - 1  # resume keeps checkpointing


def test_resume_may_use_another_number_of_workers(tmp_path):
    checkpoint = tmp_path / "run.json"
    config = CONFIG.model_copy(update={"max_generations": 4})
    stop = threading.Event()
    evolve(config, SyntheticEvaluator(), VOCABULARY, checkpoint=checkpoint, stop=stop,
           callbacks=[lambda stats, population: stats.generation == 1 and stop.set()])
    resumed = resume(checkpoint, SyntheticEvaluator(), workers=2)
    assert resumed.config.workers == 2
    assert comparable(resumed)[:2] == comparable(evolve(config, SyntheticEvaluator(), VOCABULARY))[:2]


def test_resuming_a_finished_random_search_returns_its_result(tmp_path):
    checkpoint = tmp_path / "random.json"
    config = CONFIG.model_copy(update={"max_generations": 3})
    complete = random_search(config, SyntheticEvaluator(), VOCABULARY, checkpoint=checkpoint)
    state = load_checkpoint(checkpoint)
    assert state.algorithm == "random-search" and len(state.history) == 3
    assert comparable(resume(checkpoint, SyntheticEvaluator())) == comparable(complete)  # already finished


def test_a_checkpoint_holds_the_full_state(tmp_path):
    checkpoint = tmp_path / "run.json"
    result = evolve(CONFIG.model_copy(update={"max_generations": 2}), SyntheticEvaluator(), VOCABULARY,
                    checkpoint=checkpoint)
    state = load_checkpoint(checkpoint)
    assert state.config == result.config and state.history == result.history
    assert [i.to_dict() for i in state.population] == [i.to_dict() for i in result.population]
    assert state.best.to_dict() == result.best.to_dict()
    assert state.vocabulary == result.vocabulary
    assert not list(tmp_path.glob(".*tmp"))  # no temporary file left behind


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "cannot read checkpoint"),
        ("{not json", "cannot read checkpoint"),
        ('{"format": "something-else"}', "is not a GA checkpoint"),
        ('{"format": "soccer-lab-ga-checkpoint", "version": 99}', "unsupported checkpoint version 99"),
        ('{"format": "soccer-lab-ga-checkpoint", "version": 1, "algorithm": "ga"}', "malformed checkpoint"),
    ],
)
def test_unreadable_checkpoints_give_clear_errors(tmp_path, content, message):
    path = tmp_path / "bad.json"
    if content is not None:
        path.write_text(content)
    with pytest.raises(CheckpointError, match=message):
        resume(path, SyntheticEvaluator())
