import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from soccer_lab.fuzzy.rule import Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.genes import GeneSpace
from soccer_lab.ga.initialisation import random_chromosome
from soccer_lab.ga.notation import parse_compact

VOCABULARY = Vocabulary.default()

FIG_6 = "(B,L,A) (B,A,O) (G,nF,O) (Dr,n,L)"
FIG_7 = "(B,N,O) (B,nF,A) (G,N,A) (RB,n,L) (B,A,A) (G,vN,O) (KG,n,M) (B,L,A) (T,L,n)"
codec = ChromosomeCodec(VOCABULARY)


def decode(notation: str) -> Rulebase:
    return codec.decode(parse_compact(notation, VOCABULARY))


def test_fig_6_fragment_decodes_to_the_chapter_rule():
    # if (Ball is Left and Ball is At) or Goal is not Far then Dribble Low; the last OR is ignored
    assert decode(FIG_6).rules == (
        Rule(
            premises=(Premise("BALL", "LEFT"), Premise("BALL", "AT"), Premise("GOAL", "FAR", negated=True)),
            connectors=("AND", "OR"),
            consequent=Consequent("DRIBBLE", None, "LOW"),
        ),
    )


def test_fig_7_chromosome_decodes_to_its_three_rules():
    assert decode(FIG_7).rules == (
        Rule((Premise("BALL", "NEAR"), Premise("BALL", "FAR", True), Premise("GOAL", "NEAR")), ("OR", "AND"),
             Consequent("RUNTOWARDBALL", None, "LOW")),
        Rule((Premise("BALL", "AT"), Premise("GOAL", "VERYNEAR")), ("AND",),
             Consequent("KICKTOWARDGOAL", None, "MEDIUMPOWER")),
        Rule((Premise("BALL", "LEFT"),), (), Consequent("TURN", "LEFT", None)),
    )


def test_rules_without_premises_and_trailing_premises_are_skipped():
    rulebase = decode("(T,L,n) (B,N,A) (K,S,H) (D,n,H) (G,F,O)")
    assert rulebase.rules == (Rule((Premise("BALL", "NEAR"),), (), Consequent("KICK", "STRAIGHT", "HIGH")),)


def test_a_chromosome_without_a_valid_rule_decodes_to_an_empty_rulebase():
    assert len(decode("(T,L,n) (DN,n,n) (B,N,A) (G,vF,O)")) == 0


def test_encode_writes_the_shortest_chromosome_for_a_rulebase():
    rulebase = decode(FIG_7)
    encoded = codec.encode(rulebase)
    assert len(encoded) == 9
    assert codec.decode(encoded) == rulebase


@given(st.integers(0, 2**32 - 1))
def test_decode_encode_decode_gives_back_the_rulebase(seed):
    chromosome = random_chromosome(GeneSpace.from_vocabulary(VOCABULARY), 64, 0.25, np.random.default_rng(seed))
    rulebase = codec.decode(chromosome)
    assert codec.decode(codec.encode(rulebase)) == rulebase
