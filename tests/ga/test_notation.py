import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.genes import GeneSpace
from soccer_lab.ga.initialisation import random_chromosome
from soccer_lab.ga.notation import NotationError, format_compact, parse_compact

VOCABULARY = Vocabulary.default()

FIG_7 = "(B,N,O) (B,nF,A) (G,N,A) (RB,n,L) (B,A,A) (G,vN,O) (KG,n,M) (B,L,A) (T,L,n)"


def test_fig_7_notation_round_trips():
    assert format_compact(parse_compact(FIG_7, VOCABULARY), VOCABULARY) == FIG_7


def test_position_disambiguates_m_and_n():
    space = GeneSpace.from_vocabulary(VOCABULARY)
    premise, consequent = parse_compact("(G,nM,O) (K,n,M)", VOCABULARY)
    assert space.terms[premise[3]] == "MEDIUMDISTANT" and premise[2] == 1  # n prefix = not
    assert space.powers[consequent[3]] == "MEDIUMPOWER"
    assert consequent[2] == space.null_direction  # n alone = Null


def test_whitespace_between_and_inside_genes_is_accepted():
    chromosome = parse_compact(" (B, N ,O)\n\t(RB,n,L)(T,L,n) ", VOCABULARY)
    assert format_compact(chromosome, VOCABULARY) == "(B,N,O) (RB,n,L) (T,L,n)"


def test_every_vocabulary_name_has_an_abbreviation():
    space = GeneSpace.from_vocabulary(VOCABULARY)
    names = {*space.objects, *space.terms, *space.connectors, *space.actions, *space.directions, *space.powers}
    assert names <= set(VOCABULARY.abbreviations)


@given(st.integers(0, 2**32 - 1))
def test_parse_format_round_trips_random_chromosomes(seed):
    chromosome = random_chromosome(GeneSpace.from_vocabulary(VOCABULARY), 64, 0.25, np.random.default_rng(seed))
    text = format_compact(chromosome, VOCABULARY)
    assert np.array_equal(parse_compact(text, VOCABULARY), chromosome)
    assert format_compact(parse_compact(text, VOCABULARY), VOCABULARY) == text


@pytest.mark.parametrize(
    ("notation", "message"),
    [
        ("", "empty chromosome"),
        ("   ", "empty chromosome"),
        ("(B,N)", "gene 1 (B,N) at column 1: a gene has 3 comma-separated fields, found 2"),
        ("(B,N,O) (X,N,O)", "gene 2 (X,N,O) at column 9: unknown object or action 'X'"),
        ("(B,N,O) junk", "column 9: expected a gene like (B,N,O) or (RB,n,L), found 'junk'"),
        ("(B,N,O", "column 1: expected a gene"),
        ("(B,n,O)", "unknown term 'n'"),
        ("(B,nn,O)", "unknown term 'nn'"),
        ("(B,N,X)", "unknown connector 'X' (expected one of A, O)"),
        ("(RB,N,L)", "unknown direction 'N'"),
        ("(T,L,Q)", "unknown power 'Q'"),
        ("(b,N,O)", "unknown object or action 'b'"),
    ],
)
def test_malformed_notation_says_what_and_where(notation, message):
    with pytest.raises(NotationError) as error:
        parse_compact(notation, VOCABULARY)
    assert message in str(error.value)
