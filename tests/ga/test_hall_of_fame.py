"""Co-evolution against a hall of fame (ga/hall_of_fame.py): the hall is the GA's state, drawn from with the run's
Generator, checkpointed with it, so one seed fixes a co-evolution run bit for bit, resumed or not."""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np
import pytest
from ga_synthetic import SyntheticResult, play

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import evolve, resume
from soccer_lab.ga.checkpoint import load_checkpoint
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.hall_of_fame import HallOfFame, founded_hall

VOCABULARY = Vocabulary.default()
CODEC = ChromosomeCodec(VOCABULARY)
CONFIG = GAConfig(population_size=16, max_generations=8, max_length=20, selection="elitist", target_fitness=0.0,
                  seed=5)


@dataclass(frozen=True)
class OpponentsEvaluator:
    """A synthetic game whose result depends on the opponents: the player's "goals" minus the opponents' mean."""

    opponents: tuple[Rulebase, ...] = ()

    def against(self, opponents):
        return OpponentsEvaluator(tuple(opponents))

    def __call__(self, rulebases, seeds):
        assert self.opponents, "scored before the generation's opponents were set"
        strength = np.mean([play(opponent, 0).goals for opponent in self.opponents])
        results = []
        for rulebase, seed in zip(rulebases, seeds):
            margin = play(rulebase, seed).goals - strength
            results.append(SyntheticResult(1 / (2 * margin) if margin > 0 else 1.0 - 0.01 * margin, max(0, int(margin))))
        return results


def founder() -> HallOfFame:
    rng = np.random.default_rng(1)
    from soccer_lab.ga.initialisation import random_population

    return founded_hall(random_population(CODEC.space, 1, 20, 0.5, rng)[0], "the founder", 3, 2)


class Heard:
    def __init__(self):
        self.opponents = {}

    def on_opponents(self, generation, members):
        self.opponents[generation] = [member.label for member in members]

    def on_generation(self, stats, population):
        assert stats.generation in self.opponents  # heard before the generation was scored


def comparable(result, hall):
    return ([{k: v for k, v in s.to_dict().items() if k != "wall_time"} for s in result.history],
            [i.to_dict() for i in result.population], hall.to_dict())


def test_generation_0_plays_the_founder_then_the_hall_grows_with_distinct_bests_to_its_size(tmp_path):
    heard = Heard()
    checkpoint = tmp_path / "run.json"
    evolve(CONFIG, OpponentsEvaluator(), VOCABULARY, hall=founder(), callbacks=[heard], checkpoint=checkpoint)
    hall = load_checkpoint(checkpoint).hall
    assert heard.opponents[0] == ["the founder"]
    assert all(len(labels) == 2 for g, labels in heard.opponents.items() if g > 0)  # the sample, once there is a choice
    assert hall.founder.label == "the founder" and len(hall.bests) == hall.size  # bounded; the founder stays
    labels = [m.label for m in hall.bests]
    assert labels == sorted(labels, key=lambda label: int(label.rsplit(" ", 1)[1]))  # oldest first, the last kept
    chromosomes = [m.chromosome.tobytes() for m in hall.members]
    assert len(set(chromosomes)) == len(chromosomes)  # distinct players
    assert [m.label for m in hall.drawn] == heard.opponents[CONFIG.max_generations - 1]


def test_one_seed_fixes_a_coevolution_run_and_a_resumed_run_finishes_the_same(tmp_path):
    whole, stopped = tmp_path / "whole.json", tmp_path / "stopped.json"
    uninterrupted = evolve(CONFIG, OpponentsEvaluator(), VOCABULARY, hall=founder(), checkpoint=whole)
    again = evolve(CONFIG, OpponentsEvaluator(), VOCABULARY, hall=founder())
    assert comparable(again, load_checkpoint(whole).hall)[:2] == comparable(uninterrupted, load_checkpoint(whole).hall)[:2]

    stop = threading.Event()

    def stop_after_third(stats, population):
        if stats.generation == 2:
            stop.set()

    part = evolve(CONFIG, OpponentsEvaluator(), VOCABULARY, hall=founder(), checkpoint=stopped, stop=stop,
                  callbacks=[stop_after_third])
    assert len(part.history) == 3
    resumed = resume(stopped, OpponentsEvaluator())
    assert comparable(resumed, load_checkpoint(stopped).hall) == comparable(uninterrupted, load_checkpoint(whole).hall)
    other_seed = evolve(CONFIG.model_copy(update={"seed": 6}), OpponentsEvaluator(), VOCABULARY, hall=founder())
    assert comparable(other_seed, load_checkpoint(whole).hall)[0] != comparable(uninterrupted, load_checkpoint(whole).hall)[0]


def test_a_run_without_a_hall_draws_nothing_more_than_before():
    """The plain GA's draws are untouched by co-evolution's code (its runs' results stay as recorded)."""
    from ga_synthetic import SyntheticEvaluator

    first = evolve(CONFIG, SyntheticEvaluator(), VOCABULARY)
    second = evolve(CONFIG, SyntheticEvaluator(), VOCABULARY, hall=None)
    assert [s.best for s in first.history] == [s.best for s in second.history]


def test_coevolution_needs_an_evaluator_that_plays_opponents_and_a_bounded_hall():
    from ga_synthetic import SyntheticEvaluator

    with pytest.raises(ValueError, match="against"):
        evolve(CONFIG, SyntheticEvaluator(), VOCABULARY, hall=founder())
    for size, sample in ((0, 1), (1, 0), (10_000, 1), (1, 10_000)):
        with pytest.raises(ValueError, match="hall"):
            HallOfFame(size, sample, founder().founder)


def test_the_hall_round_trips_through_its_dict():
    hall = founder().with_best(founder().founder.chromosome[:3], 0)
    again = HallOfFame.from_dict(hall.to_dict())
    assert again.to_dict() == hall.to_dict()
    assert again.with_best(hall.bests[0].chromosome, 1) is again  # a player already in it does not join twice
