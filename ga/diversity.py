"""How varied a generation is (issue 24; docs/teaching/lineage.md says what each measure means).

Genotypic, from the chromosomes alone (cheap: every generation of every run):
- distinct chromosomes: how many different gene sequences the population holds;
- distinct rules: how many different rules its rule sets contain between them (a rule as the codec
  decodes it: its premises, their connectors, its consequent; the connector after a rule's last premise,
  which decoding ignores, is ignored here too);
- rule-set distance: the mean, over every pair of individuals, of the Jaccard distance between their
  sets of rules (1 - shared rules / rules of either): 0 when every player has the same rules, 1 when no
  two share one. Exact up to population 2,000 (in bounded memory); above, its pairs are too many to
  visit every generation (50 million at 10,000), and it is the mean over a sample of 200,000 pairs drawn
  uniformly at random, with a standard error of at most 0.0011 (so within 0.0034 of the exact mean in all
  but 3 generations in 1,000). The sample is drawn from the population itself (seeded by its rule sets),
  so the same population always gives the same figure.

Behavioural, from play (costs games, so an option: GAConfig.behaviour_seeds = K): every distinct chromosome
also plays the run's K common seeds, and the population's distinct outcome tuples are counted (an outcome:
the (fitness, goals) of each of the K games). Two players count as one behaviour when their K games end
with the same score and the same fitness, which measures how close the ball came to goal to the last bit:
in practice, when they played the same games.
"""

from __future__ import annotations

import hashlib
from typing import Sequence

import numpy as np
from scipy import sparse

from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import SEED_BOUND, GAConfig
from soccer_lab.ga.evaluation import Evaluation
from soccer_lab.ga.genes import CONNECTOR, CONSEQUENT, KIND, PREMISE
from soccer_lab.ga.individual import Individual

GENE_CODE_RADIX = 1 << 8  # gene fields are int8: a gene is one integer, its fields its base-256 digits
BEHAVIOUR_STREAM = 1  # the behaviour seeds' own random stream, apart from the GA's (which they never touch)
DISTANCE_STREAM = 2  # the rule-set distance's sample of pairs: a stream of its own too
# The rule-set distance is exact up to this many pairs (population 2,000), in blocks of at most BLOCK_ENTRIES
# shared-rule counts (about 100 MB at worst, when every pair shares a rule); above, it is the mean over
# SAMPLED_PAIRS pairs drawn at random (SAMPLE_BLOCK at a time): a standard error of at most
# 0.5 / sqrt(SAMPLED_PAIRS) = 0.0011, since each pair's distance lies in [0, 1]
EXACT_PAIRS = 2_000 * 1_999 // 2
BLOCK_ENTRIES = 4_000_000
SAMPLED_PAIRS = 200_000
SAMPLE_BLOCK = 20_000


def gene_codes(pool: np.ndarray) -> np.ndarray:
    """One integer per gene (rows of `pool`), equal exactly when the genes are."""
    return pool.astype(np.int64) @ GENE_CODE_RADIX ** np.arange(pool.shape[1], dtype=np.int64)


def rule_spans(kinds: np.ndarray, starts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first gene, consequent) of every rule the codec decodes, over genes of the kinds `kinds` from
    chromosomes beginning at `starts`: a consequent right after a premise closes a rule that takes every
    premise back to the previous consequent or the chromosome's start."""
    positions = np.arange(len(kinds))
    first = np.zeros(len(kinds), dtype=bool)
    first[starts] = True
    after_consequent = np.ones(len(kinds), dtype=bool)
    after_consequent[1:] = kinds[:-1] == CONSEQUENT
    run_starts = np.maximum.accumulate(np.where((kinds == PREMISE) & (first | after_consequent), positions, 0))
    closing = (kinds == CONSEQUENT) & ~first & ~after_consequent
    ends = positions[closing]
    return run_starts[ends - 1], ends


def genotypic_diversity(chromosomes: Sequence[np.ndarray]) -> tuple[int, int, float]:
    """(distinct chromosomes, distinct rules, mean pairwise rule-set distance) of a population."""
    distinct_chromosomes = len({chromosome.tobytes() for chromosome in chromosomes})
    lengths = np.array([len(chromosome) for chromosome in chromosomes])
    pool = np.concatenate(chromosomes)
    starts = np.cumsum(lengths) - lengths
    first, last = rule_spans(pool[:, KIND], starts)
    if len(last) == 0:
        return distinct_chromosomes, 0, 0.0
    codes = gene_codes(pool)
    codes[last - 1] -= pool[last - 1, CONNECTOR].astype(np.int64) * GENE_CODE_RADIX ** CONNECTOR  # ignored
    sizes = last - first + 1
    rows = np.repeat(np.arange(len(last)), sizes)
    offsets = np.arange(sizes.sum()) - np.repeat(np.cumsum(sizes) - sizes, sizes)
    padded = np.full((len(last), sizes.max()), -1, dtype=np.int64)
    padded[rows, offsets] = codes[np.repeat(first, sizes) + offsets]
    ids: dict[bytes, int] = {}  # each distinct rule's number, in order of appearance
    rule_ids = np.array([ids.setdefault(rule, len(ids)) for rule in padded.view(f"V{padded.itemsize * padded.shape[1]}").ravel().tolist()])
    owners = np.searchsorted(starts, last, side="right") - 1
    return distinct_chromosomes, len(ids), _mean_jaccard_distance(owners, rule_ids, len(chromosomes))


def _mean_jaccard_distance(owners: np.ndarray, rules: np.ndarray, individuals: int) -> float:
    """Mean over pairs of individuals of 1 - |shared rules| / |rules of either| (0 for two empty sets):
    exact up to EXACT_PAIRS pairs, else estimated from SAMPLED_PAIRS pairs (module docstring)."""
    if individuals < 2:
        return 0.0
    has = sparse.csr_matrix((np.ones(len(owners)), (owners, rules)), shape=(individuals, rules.max() + 1))
    has.data[:] = 1.0  # a rule held twice is one rule of the set
    own = np.asarray(has.sum(axis=1)).ravel()
    if individuals * (individuals - 1) // 2 <= EXACT_PAIRS:
        return _exact_mean_distance(has, own)
    return _sampled_mean_distance(has, own, _pair_sampler(owners, rules))


def _exact_mean_distance(has: sparse.csr_matrix, own: np.ndarray) -> float:
    """Every pair, in blocks of rows whose shared-rule counts hold at most BLOCK_ENTRIES entries: only pairs
    sharing a rule add a similarity, and pairs of two empty sets add 1 (the same rules)."""
    individuals = has.shape[0]
    rows = max(1, BLOCK_ENTRIES // individuals)
    similarity = 0.0
    for lo in range(0, individuals, rows):
        shared = (has[lo:lo + rows] @ has.T).tocoo()
        pair = shared.row + lo < shared.col  # each unordered pair once
        i, j, both = shared.row[pair] + lo, shared.col[pair], shared.data[pair]
        similarity += float(np.sum(both / (own[i] + own[j] - both)))
    empty = int(np.count_nonzero(own == 0))
    pairs = individuals * (individuals - 1) // 2
    return float((pairs - similarity - empty * (empty - 1) // 2) / pairs)


def _sampled_mean_distance(has: sparse.csr_matrix, own: np.ndarray, rng: np.random.Generator) -> float:
    """The mean distance of SAMPLED_PAIRS pairs of distinct individuals drawn uniformly (with replacement)."""
    individuals = has.shape[0]
    first = rng.integers(0, individuals, size=SAMPLED_PAIRS)
    second = rng.integers(0, individuals - 1, size=SAMPLED_PAIRS)
    second += second >= first  # another individual, every one equally likely
    total = 0.0
    for lo in range(0, SAMPLED_PAIRS, SAMPLE_BLOCK):
        i, j = first[lo:lo + SAMPLE_BLOCK], second[lo:lo + SAMPLE_BLOCK]
        both = np.asarray(has[i].multiply(has[j]).sum(axis=1)).ravel()
        either = own[i] + own[j] - both
        total += float(np.sum(1.0 - np.divide(both, either, out=np.ones_like(both), where=either > 0)))
    return total / SAMPLED_PAIRS


def _pair_sampler(owners: np.ndarray, rules: np.ndarray) -> np.random.Generator:
    """The sample's generator, seeded by the population's rule sets: the same population gives the same
    figure (a run, its resume and its replay agree bit for bit) and the GA's own stream is never touched."""
    digest = hashlib.blake2b(np.ascontiguousarray(owners, dtype=np.int64).tobytes(), digest_size=16)
    digest.update(np.ascontiguousarray(rules, dtype=np.int64).tobytes())
    return np.random.default_rng(np.random.SeedSequence(int.from_bytes(digest.digest(), "little"),
                                                        spawn_key=(DISTANCE_STREAM,)))


def behaviour_seeds(config: GAConfig) -> list[int]:
    """The run's K common game seeds for behavioural diversity: the same every generation (so the curve
    follows the population, not the starts), drawn from the run's seed in a stream of their own."""
    rng = np.random.default_rng(np.random.SeedSequence(config.seed, spawn_key=(BEHAVIOUR_STREAM,)))
    return rng.integers(0, SEED_BOUND, size=config.behaviour_seeds).tolist()


class BehaviourProbe:
    """Counts a generation's distinct behaviours: each distinct chromosome plays the common seeds once and
    its outcome is kept while it lives (an elite's is not played again), so a resumed run, which starts
    with none kept, counts the same."""

    def __init__(self, seeds: Sequence[int], codec: ChromosomeCodec):
        self.seeds = list(seeds)
        self.codec = codec
        self.outcomes: dict[bytes, tuple] = {}

    def __call__(self, population: Sequence[Individual], evaluation: Evaluation) -> int:
        keys = [individual.chromosome.tobytes() for individual in population]
        new = {key: individual for key, individual in zip(keys, population) if key not in self.outcomes}
        rulebases = [self.codec.decode(individual.chromosome) for individual in new.values()]
        scores = evaluation([rulebase for rulebase in rulebases for _ in self.seeds], self.seeds * len(rulebases),
                            report=False)  # the progress shown is the generation's evaluation
        k = len(self.seeds)
        played = {key: tuple(scores[i * k:(i + 1) * k]) for i, key in enumerate(new)}
        self.outcomes = {key: self.outcomes.get(key) or played[key] for key in keys}
        return len(set(self.outcomes.values()))
