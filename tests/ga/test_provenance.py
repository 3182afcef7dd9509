"""Provenance: every individual's birth is recorded as the GA breeds, and every child's chromosome is rebuilt
bit for bit from its parents' chromosomes and its recorded operations, read back from the JSON record a
run writes (both crossovers, all three selections, a resumed run, and an operator the GA does not have)."""

import json
import threading

import numpy as np
import pytest
from ga_synthetic import SyntheticEvaluator

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga import crossover as crossover_module
from soccer_lab.ga.algorithms import evolve, random_search, resume
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.lineage import generation_record, read_generation_record
from soccer_lab.ga.provenance import ELITE, RANDOM, Birth, Mutation, Splice, rebuild

VOCABULARY = Vocabulary.default()
CONFIG = GAConfig(population_size=30, max_generations=6, max_length=24, target_fitness=0.0, seed=21)


def recorded_run(config, run=evolve, **options):
    """The run's generations as their JSON records say them: [(generation, population)]."""
    records = []

    def keep(stats, population):
        records.append(read_generation_record(json.loads(json.dumps(generation_record(stats.generation, population)))))

    result = run(config, SyntheticEvaluator(), VOCABULARY, callbacks=[keep], **options)
    return records, result


def assert_every_child_rebuilds(records) -> set[str]:
    """Each child of generation g >= 1 rebuilt from generation g - 1; the kinds of birth seen."""
    kinds = set()
    assert all(individual.birth == Birth() for individual in records[0][1])  # generation 0: drawn at random
    for (_, parents), (generation, children) in zip(records, records[1:]):
        for child in children:
            birth = child.birth
            kinds.add(birth.kind)
            rebuilt = rebuild(birth, [parents[p].chromosome for p in birth.parents])
            assert rebuilt.dtype == child.chromosome.dtype
            assert np.array_equal(rebuilt, child.chromosome), (generation, birth)
            if birth.kind in (ELITE, "copy"):  # the parent itself, running mean and all, evaluated once more
                parent = parents[birth.parents[0]]
                assert child.evaluations == parent.evaluations + 1 and child.first_seed == parent.first_seed
            else:
                assert child.evaluations == 1
    return kinds


@pytest.mark.parametrize("crossover", ["one-point", "two-point"])
@pytest.mark.parametrize("selection", ["roulette", "tournament", "elitist"])
def test_every_child_of_a_run_is_rebuilt_from_its_parents_and_its_recorded_operations(crossover, selection):
    records, result = recorded_run(CONFIG.model_copy(update={"crossover": crossover, "selection": selection}))
    assert len(records) == CONFIG.max_generations
    kinds = assert_every_child_rebuilds(records)
    # Every way to be born happened: crossed, mutated, both, passed on unchanged (and elites under elitism).
    assert {"splice", "mutation", "splice+mutation", "copy"} <= kinds
    assert (ELITE in kinds) == (selection == "elitist")
    splices = [op for _, population in records[1:] for i in population for op in i.birth.operations
               if isinstance(op, Splice)]
    assert {s.operator for s in splices} == {crossover}
    cuts_each = 1 if crossover == "one-point" else 2
    assert all(len(s.cuts) == 2 and all(len(c) == cuts_each for c in s.cuts) for s in splices)
    # The last record is the run's final population, births included.
    assert [i.to_dict() for i in records[-1][1]] == [i.to_dict() for i in result.population]


def test_a_resumed_run_records_the_same_births_and_every_child_still_rebuilds(tmp_path):
    config = CONFIG.model_copy(update={"selection": "elitist", "crossover": "two-point"})
    uninterrupted, _ = recorded_run(config)
    checkpoint, stop, records = tmp_path / "checkpoint", threading.Event(), []

    def keep(stats, population):
        records.append(read_generation_record(json.loads(json.dumps(generation_record(stats.generation, population)))))

    evolve(config, SyntheticEvaluator(), VOCABULARY, checkpoint=checkpoint, stop=stop,
           callbacks=[keep, lambda stats, population: stats.generation == 2 and stop.set()])
    assert [g for g, _ in records] == [0, 1, 2]
    resume(checkpoint, SyntheticEvaluator(), callbacks=[keep])
    assert [g for g, _ in records] == list(range(config.max_generations))
    assert [[i.to_dict() for i in p] for _, p in records] == [[i.to_dict() for i in p] for _, p in uninterrupted]
    assert_every_child_rebuilds(records)


def test_a_crossover_the_ga_does_not_have_records_itself_and_rebuilds_unchanged(monkeypatch):
    def uniform(a, b, max_length, rng):
        """Gene by gene from either parent (over the shorter's length): a splice of one-gene stretches."""
        picks = rng.integers(0, 2, size=min(len(a), len(b)))
        children = []
        for own in (0, 1):
            segments = [(int(p) if own == 0 else 1 - int(p), i, i + 1) for i, p in enumerate(picks)]
            children.append(Splice.of("uniform", ((), ()), segments, max_length))
        return tuple(children)

    monkeypatch.setitem(crossover_module.CROSSOVERS, "one-point", uniform)
    records, _ = recorded_run(CONFIG)
    assert_every_child_rebuilds(records)
    operators = {op.operator for _, p in records[1:] for i in p for op in i.birth.operations if isinstance(op, Splice)}
    assert operators == {"uniform"}


def test_random_search_draws_everyone():
    records, _ = recorded_run(CONFIG.model_copy(update={"max_generations": 3}), run=random_search)
    assert {i.birth.kind for _, p in records for i in p} == {RANDOM}


def test_operations_and_births_round_trip_and_a_wrong_record_is_refused():
    birth = Birth((3, 9), (Splice("two-point", ((1, 4), (2, 2)), ((0, 0, 1), (1, 2, 2), (0, 4, 6))),
                           Mutation(((0, 3, 1, 5), (4, 1, 0, 1)))))
    assert Birth.from_dict(json.loads(json.dumps(birth.to_dict()))) == birth
    assert birth.kind == "splice+mutation" and Birth((2,), elite=True).kind == ELITE and Birth((2,)).kind == "copy"
    assert Birth.from_dict({}) == Birth() and Birth().to_dict() == {}
    parent = np.zeros((4, 5), dtype=np.int8)
    with pytest.raises(ValueError, match="gene 1 field 3 is 0, the mutation recorded 2"):
        Mutation(((1, 3, 2, 4),)).apply(parent, ())
    with pytest.raises(ValueError, match="random draw"):
        rebuild(Birth(), [])
    with pytest.raises(ValueError, match="names 2 parents, 1 chromosomes"):
        rebuild(Birth((0, 1)), [parent])
    with pytest.raises(ValueError, match="unknown operation 'graft'"):
        Birth.from_dict({"parents": [1], "operations": [{"kind": "graft"}]})


def test_a_splice_is_cut_at_the_maximum_length():
    splice = Splice.of("one-point", ((3,), (2,)), [(0, 0, 3), (1, 2, 9)], max_length=5)
    assert splice.segments == ((0, 0, 3), (1, 2, 4))
    a, b = np.arange(15).reshape(3, 5).astype(np.int8), np.arange(45).reshape(9, 5).astype(np.int8)
    assert np.array_equal(splice.apply(a, (a, b)), np.concatenate((a, b[2:4])))
