"""Property tests: no operator yields an out-of-range gene, a chromosome longer than the maximum,
or a gene of the other kind."""

import itertools

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.crossover import one_point, rule_segments, two_point, uniform
from soccer_lab.ga.genes import CONSEQUENT, GENE_WIDTH, KIND, MIN_LENGTH, GeneSpace
from soccer_lab.ga.initialisation import random_chromosome, random_population
from soccer_lab.ga.mutation import mutate

VOCABULARY = Vocabulary.default()

SPACE = GeneSpace.from_vocabulary(VOCABULARY)
seeds = st.integers(0, 2**32 - 1)
max_lengths = st.integers(MIN_LENGTH, 100)


@st.composite
def chromosomes(draw, kind=None):
    """Any in-range chromosome; `kind` forces every gene to be a premise (0) or a consequent (1)."""
    length = draw(st.integers(MIN_LENGTH, 80))
    kinds = np.full(length, kind) if kind is not None else np.array(draw(st.lists(
        st.integers(0, 1), min_size=length, max_size=length)))
    fields = np.random.default_rng(draw(seeds)).integers(0, SPACE.field_sizes[kinds])
    fields[:, KIND] = kinds
    return fields.astype(np.int8)


def cross(crossover, a, b, max_length, rng):
    """The two children's chromosomes: each child's recorded splice applied to its parents."""
    return [splice.apply(a, (a, b)) for splice in crossover(a, b, max_length, rng)]


def mutated(chromosome, rate, rng):
    return mutate(chromosome, rate, SPACE, rng).apply(chromosome, ())


def gene_multiset(*parts):
    return sorted(map(tuple, np.concatenate(parts).tolist()))


@given(seeds, max_lengths, st.floats(0.01, 0.99))
def test_initial_chromosomes_are_in_range_and_within_length(seed, max_length, consequent_probability):
    chromosome = random_chromosome(SPACE, max_length, consequent_probability, np.random.default_rng(seed))
    SPACE.check(chromosome)
    assert MIN_LENGTH <= len(chromosome) <= max_length


def test_initialisation_matches_the_configured_proportions():
    population = random_population(SPACE, 400, 64, 0.25, np.random.default_rng(1))
    lengths = np.array([len(c) for c in population])
    kinds = np.concatenate([c[:, KIND] for c in population])
    assert lengths.min() == MIN_LENGTH and lengths.max() == 64
    assert abs(lengths.mean() - 33) < 1.5  # uniform on [2, 64]
    assert abs(kinds.mean() - 0.25) < 0.01
    nulls = np.concatenate([c[c[:, KIND] == 1, 2] for c in population]) == SPACE.null_direction
    assert abs(nulls.mean() - 1 / 10) < 0.02  # 9 directions + Null, uniform


@given(chromosomes(), chromosomes(), seeds)
def test_one_point_crossover_conserves_genes_without_truncation(a, b, seed):
    c1, c2 = cross(one_point, a, b, 10_000, np.random.default_rng(seed))
    assert len(c1) + len(c2) == len(a) + len(b)
    assert gene_multiset(c1, c2) == gene_multiset(a, b)
    assert len(c1) >= MIN_LENGTH and len(c2) >= MIN_LENGTH


@given(chromosomes(kind=0), chromosomes(kind=1), seeds)
def test_one_point_children_are_head_of_one_parent_and_tail_of_the_other(a, b, seed):
    # a is all premises and b all consequents, so a child's kinds show where its cut fell.
    c1, c2 = cross(one_point, a, b, 10_000, np.random.default_rng(seed))
    i, j = int((c1[:, KIND] == 0).sum()), int((c2[:, KIND] == 1).sum())
    assert 0 < i < len(a) and 0 < j < len(b)  # independent interior cuts
    assert np.array_equal(c1, np.concatenate((a[:i], b[j:])))
    assert np.array_equal(c2, np.concatenate((b[:j], a[i:])))


@given(chromosomes(), chromosomes(), seeds)
def test_two_point_crossover_conserves_genes_without_truncation(a, b, seed):
    c1, c2 = cross(two_point, a, b, 10_000, np.random.default_rng(seed))
    assert gene_multiset(c1, c2) == gene_multiset(a, b)
    assert np.array_equal(c1[0], a[0]) and np.array_equal(c1[-1], a[-1])  # heads and tails stay


@st.composite
def distinct_genes(draw, kind):
    """A chromosome of `kind` genes, all different, so every gene's origin is known."""
    every_gene = np.array([[kind, *fields] for fields in itertools.product(
        *(range(SPACE.field_sizes[kind, c]) for c in range(1, GENE_WIDTH)))], dtype=np.int8)
    length = draw(st.integers(MIN_LENGTH, 60))
    return np.random.default_rng(draw(seeds)).permutation(every_gene)[:length]


def origins(genes, parent):
    where = {tuple(g): k for k, g in enumerate(parent.tolist())}
    return np.array([where[tuple(g)] for g in genes.tolist()], dtype=int)


@given(distinct_genes(0), distinct_genes(1), seeds)
def test_two_point_swaps_one_middle_segment_of_each_parent(a, b, seed):
    c1, c2 = cross(two_point, a, b, 10_000, np.random.default_rng(seed))
    for child, own, other, own_kind in ((c1, a, b, 0), (c2, b, a, 1)):
        kinds = child[:, KIND]
        assert kinds[0] == own_kind and kinds[-1] == own_kind  # own head and tail are never empty
        assert np.count_nonzero(np.diff(kinds)) <= 2  # head, swapped middle, tail
        kept = origins(child[kinds == own_kind], own)
        assert np.all(np.diff(kept) > 0)  # own genes in order, one segment missing
        received = origins(child[kinds != own_kind], other)
        assert np.all(np.diff(received) == 1)  # the other's middle, contiguous
    given_away = origins(c2[c2[:, KIND] == 0], a)
    assert sorted([*origins(c1[c1[:, KIND] == 0], a), *given_away]) == list(range(len(a)))


@given(chromosomes(), chromosomes(), seeds, max_lengths, st.sampled_from([one_point, two_point, uniform]))
def test_crossover_children_are_in_range_and_truncated(a, b, seed, max_length, crossover):
    a, b = a[:max_length], b[:max_length]  # parents are never longer than the maximum (initialisation, crossover)
    for child in cross(crossover, a, b, max_length, np.random.default_rng(seed)):
        SPACE.check(child)
        assert MIN_LENGTH <= min(len(a), len(b), len(child)) and len(child) <= max_length


def rules(*chromosomes):
    """The rules (runs of premises closed by a consequent) of the chromosomes, as a sorted multiset."""
    return sorted(s.tobytes() for c in chromosomes for s in rule_segments(c) if s[-1, KIND] == CONSEQUENT)


def trailing(chromosome):
    """The premises after the last consequent: they form no rule."""
    return chromosome[len(chromosome) - np.argmax(chromosome[::-1, KIND] == CONSEQUENT):] \
        if np.any(chromosome[:, KIND] == CONSEQUENT) else chromosome


@given(chromosomes(), chromosomes(), seeds, max_lengths)
def test_uniform_children_hold_only_whole_rules_of_their_parents_within_the_maximum(a, b, seed, max_length):
    a, b = a[:max_length], b[:max_length]
    for child in cross(uniform, a, b, max_length, np.random.default_rng(seed)):
        assert len(child) <= max_length
        # every rule of a child is a rule of a parent, whole: none is cut, none joined to another's premises
        assert all(rule in rules(a, b) for rule in rules(child))
        assert gene_multiset(child) == [g for g in gene_multiset(child) if g in gene_multiset(a, b)]
        assert all(gene in gene_multiset(trailing(a), trailing(b)) for gene in gene_multiset(trailing(child)))


@given(chromosomes(), chromosomes(), seeds)
def test_uniform_shares_out_every_rule_without_truncation(a, b, seed):
    s1, s2 = uniform(a, b, 10_000, np.random.default_rng(seed))
    if s1.segments == ((0, 0, len(a)),) or s2.segments == ((1, 0, len(b)),):  # a lone-consequent child: its parent
        return
    c1, c2 = s1.apply(a, (a, b)), s2.apply(b, (a, b))
    assert rules(c1, c2) == rules(a, b)
    assert gene_multiset(c1, c2) == gene_multiset(a, b)


def test_uniform_takes_each_rule_from_either_parent_by_a_fair_coin():
    rule = lambda premise, action: np.array([[0, premise, 0, 0, 0], [CONSEQUENT, action, 0, 0, 0]], dtype=np.int8)
    a = np.concatenate([rule(0, i % 2) for i in range(20)])  # 20 rules of a: premise object 0
    b = np.concatenate([rule(1, i % 2) for i in range(20)])  # 20 rules of b: premise object 1
    rng = np.random.default_rng(5)
    from_a = [np.mean([s[0, 1] == 0 for s in rule_segments(cross(uniform, a, b, 10_000, rng)[0])]) for _ in range(300)]
    assert abs(np.mean(from_a) - 0.5) < 0.02
    assert 0 < min(from_a) and max(from_a) < 1  # mixed, rule by rule, not whole parents


def test_uniform_is_reproducible_from_the_generator():
    rng = np.random.default_rng(0)
    a, b = random_chromosome(SPACE, 64, 0.25, rng), random_chromosome(SPACE, 64, 0.25, rng)
    first = cross(uniform, a, b, 64, np.random.default_rng(9))
    again = cross(uniform, a, b, 64, np.random.default_rng(9))
    assert all(np.array_equal(x, y) for x, y in zip(first, again))


@given(chromosomes(), seeds, st.floats(0, 1))
def test_mutation_changes_single_alleles_in_range_and_never_a_kind(chromosome, seed, rate):
    mutant = mutated(chromosome, rate, np.random.default_rng(seed))
    SPACE.check(mutant)
    assert mutant.shape == chromosome.shape
    assert np.array_equal(mutant[:, KIND], chromosome[:, KIND])
    changed_fields = (mutant != chromosome).sum(axis=1)
    assert changed_fields.max() == 1  # at least one gene hit, each hit changes exactly one field


def test_mutation_rate_sets_the_share_of_genes_hit():
    chromosome = random_chromosome(SPACE, 64, 0.25, np.random.default_rng(0))
    rng = np.random.default_rng(2)
    hit = [np.mean((mutated(chromosome, 0.3, rng) != chromosome).any(axis=1)) for _ in range(500)]
    assert abs(np.mean(hit) - 0.3) < 0.02


def test_mutation_leaves_its_input_untouched():
    chromosome = random_chromosome(SPACE, 64, 0.25, np.random.default_rng(0))
    before = chromosome.copy()
    mutated(chromosome, 1.0, np.random.default_rng(0))
    assert np.array_equal(chromosome, before)
