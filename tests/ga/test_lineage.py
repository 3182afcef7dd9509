"""Family trees: a hand-made lineage whose every answer is known, and a real run whose genes, followed back
through the records, are what their ancestors held."""

import numpy as np
import pytest
from ga_synthetic import SyntheticEvaluator

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import evolve
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.genes import TERM
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.lineage import (CUT, DRAWN, EARLIER, MUTATED, Lineage, LineageError, Place, best_place,
                                   parent_position)
from soccer_lab.ga.notation import parse_compact
from soccer_lab.ga.provenance import Birth, Mutation, Splice

VOCABULARY = Vocabulary.default()
CODEC = ChromosomeCodec(VOCABULARY)


def member(text, birth, fitness=0.5):
    return Individual(parse_compact(text, VOCABULARY), birth=birth).evaluated(fitness, 1)


def applied(birth, parents):
    from soccer_lab.ga.provenance import rebuild

    return rebuild(birth, [parents[p].chromosome for p in birth.parents])


A = "(B,N,O) (KG,n,H) (G,F,A) (RB,n,L)"  # rules: genes 1-2, 3-4
B = "(B,F,A) (T,L,n) (G,vN,O) (B,A,A) (D,R,H)"  # rules: genes 1-2, 3-5


@pytest.fixture
def lineage():
    generation_0 = [member(A, Birth()), member(B, Birth())]
    crossed = Birth((0, 1), (Splice.of("one-point", ((2,), (2,)), [(0, 0, 2), (1, 2, 5)], 64),
                             Mutation(((3, TERM, 0, 2),))))  # (B,A,A) -> (B,N,A)
    cut_in_a_rule = Birth((0, 1), (Splice.of("one-point", ((3,), (1,)), [(0, 0, 3), (1, 1, 5)], 64),))
    generation_1 = [Individual(generation_0[0].chromosome, birth=Birth((0,), elite=True)).evaluated(0.5, 1),
                    Individual(applied(crossed, generation_0), birth=crossed).evaluated(0.25, 2),
                    Individual(applied(cut_in_a_rule, generation_0), birth=cut_in_a_rule).evaluated(0.3, 1)]
    back = Birth((1, 0), (Splice.of("one-point", ((2,), (2,)), [(0, 0, 2), (1, 2, 4)], 64),))
    generation_2 = [Individual(generation_1[2].chromosome, birth=Birth((2,))).evaluated(0.2, 3),
                    Individual(applied(back, generation_1), birth=back).evaluated(0.5, 1)]
    populations = [generation_0, generation_1, generation_2]
    return Lineage(lambda g: populations[g], 3)


def test_a_tree_holds_the_ancestors_whose_genes_the_player_carries(lineage):
    tree = lineage.family_tree(Place(2, 0))  # a copy of gen 1 #2 = A's genes 1-3 + B's genes 2-5
    assert set(tree.ancestors) == {Place(2, 0), Place(1, 2), Place(0, 0), Place(0, 1)}
    assert tree.ancestors[Place(2, 0)].parents == (Place(1, 2),)
    assert tree.ancestors[Place(1, 2)].parents == (Place(0, 0), Place(0, 1))
    assert tree.ancestors[Place(0, 0)].genes == (0, 1, 2) and tree.ancestors[Place(0, 1)].genes == (3, 4, 5, 6)
    assert [[a.place for a in row] for row in tree.generations()] == [
        [Place(2, 0)], [Place(1, 2)], [Place(0, 0), Place(0, 1)]]
    origins = [(r.first, r.last, r.origin, r.how, r.via) for r in tree.rules]
    assert origins == [(0, 1, Place(0, 0), DRAWN, Place(1, 2)),  # A's first rule, whole since generation 0
                       (2, 3, Place(1, 2), CUT, Place(1, 2)),  # A's premise with B's consequent: made by the cut
                       (4, 6, Place(0, 1), DRAWN, Place(1, 2))]  # B's second rule, whole
    assert tree.rules[1].operator == "one-point" and tree.rules[0].path == (Place(2, 0), Place(1, 2), Place(0, 0))
    assert tree.origins() == [Place(0, 0), Place(1, 2), Place(0, 1)]


def test_a_mutation_inside_a_rule_makes_it_new_and_is_reported(lineage):
    tree = lineage.family_tree(Place(1, 1))
    assert tree.ancestors[Place(1, 1)].mutations == ((3, TERM, 0, 2),)
    first, second = tree.rules
    assert (first.origin, first.how, first.via) == (Place(0, 0), DRAWN, Place(0, 0))
    assert (second.origin, second.how, second.via, second.mutations) == (Place(1, 1), MUTATED, None, ((3, TERM, 0, 2),))


def test_genes_flow_through_different_parents_from_one_ancestor(lineage):
    tree = lineage.family_tree(Place(2, 1))  # head of gen 1 #1, tail of the elite gen 1 #0: both from A
    assert tree.ancestors[Place(1, 1)].genes == (0, 1) and tree.ancestors[Place(1, 0)].genes == (2, 3)
    assert tree.ancestors[Place(0, 0)].genes == (0, 1, 2, 3) and Place(0, 1) not in tree.ancestors
    assert [(r.via, r.origin, r.how) for r in tree.rules] == [(Place(1, 1), Place(0, 0), DRAWN),
                                                             (Place(1, 0), Place(0, 0), DRAWN)]


def test_a_shorter_tree_stops_at_its_oldest_generation(lineage):
    tree = lineage.family_tree(Place(2, 0), generations=1)
    assert set(tree.ancestors) == {Place(2, 0), Place(1, 2)} and tree.oldest == 1
    assert [(r.origin, r.how) for r in tree.rules] == [(Place(1, 2), EARLIER)] * 3  # not followed further
    assert set(lineage.family_tree(Place(2, 0), generations=0).ancestors) == {Place(2, 0)}


def test_places_outside_the_records_are_refused(lineage):
    with pytest.raises(LineageError, match="generations 0 to 2, not 3"):
        lineage.family_tree(Place(3, 0))
    with pytest.raises(LineageError, match="individuals 0 to 1, not 2"):
        lineage.family_tree(Place(2, 2))
    missing = Lineage(lambda g: (_ for _ in ()).throw(LookupError(g)), 2)
    with pytest.raises(LineageError, match="no lineage record"):
        missing.individual(Place(1, 0))


def test_the_best_so_far_is_the_gas(lineage):
    assert best_place([(0, 0.5), (1, 0.25), (2, 0.2)], lineage.population) == Place(2, 0)
    assert best_place([(0, 0.5), (1, 0.2), (2, 0.2)], lineage.population) == Place(1, 1)  # earliest of equals


def test_every_gene_of_a_real_runs_best_is_what_its_ancestors_held():
    config = GAConfig(population_size=40, max_generations=8, max_length=32, target_fitness=0.0, seed=9,
                      mutation_probability=0.6)
    populations = []
    evolve(config, SyntheticEvaluator(), VOCABULARY, callbacks=[lambda stats, p: populations.append(p)])
    lineage = Lineage(lambda g: populations[g], len(populations))
    checked_mutations = 0
    for index in range(0, 40, 7):
        chosen = Place(7, index)
        chromosome = lineage.individual(chosen).chromosome
        for gene in range(len(chromosome)):  # follow each gene back, undoing what mutations changed
            value, place, position = chromosome[gene].copy(), chosen, gene
            while (birth := lineage.individual(place).birth).parents:
                slot, position, changes = parent_position(birth, position)
                for column, old, new in reversed(changes):
                    assert value[column] == new
                    value[column] = old
                    checked_mutations += 1
                place = Place(place.generation - 1, birth.parents[slot])
                assert np.array_equal(lineage.individual(place).chromosome[position], value)
            assert place.generation == 0
        tree = lineage.family_tree(chosen)
        assert sorted(g for a in tree.ancestors.values() if a.place.generation == 0 for g in a.genes) == list(
            range(len(chromosome)))  # every gene goes back to one individual of generation 0
        for rule in tree.rules:  # along its path, every holder has the rule whole
            rulebase = CODEC.decode(chromosome[rule.first:rule.last + 1])
            for holder in rule.path[1:]:
                assert rulebase.rules[0] in CODEC.decode(lineage.individual(holder).chromosome).rules
    assert checked_mutations > 0
