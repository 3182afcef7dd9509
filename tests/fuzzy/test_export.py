"""Export: lossless JSON, and the shape of the FLL, FCL and .fis text (tests/fuzzy/test_export_readers.py
loads them in the real readers)."""

import json
import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from soccer_lab.fuzzy.export import (RulebaseFormatError, export_rulebase, rulebase_from_json, to_fcl, to_fis, to_fll,
                                     to_json)
from soccer_lab.fuzzy.export.layout import FisLayout
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from tests.fuzzy.iec_fcl import FclError, parse_fcl

fl = pytest.importorskip("fuzzylite", reason="pyfuzzylite is not installed: "
                                              "pip install --no-deps pyfuzzylite==8.0.6 (scripts/test does)")

VOCABULARY = Vocabulary.default()
EXAMPLE = parse_rulebase(
    "if (Ball is Near or Ball is not Far) and Goal is Near then RunTowardBall Low\n"
    "if Ball is At then Kick SlightlyRight High\n"
    "if Ball is Left then Turn Left [power High]\n"
    "if Goal is not VeryFar then DoNothing\n", VOCABULARY
)


@given(st.integers(0, 2**32 - 1))
def test_json_round_trip_is_lossless(seed):
    rulebase = random_rulebase(np.random.default_rng(seed), VOCABULARY, rules=int(seed % 12))
    loaded, vocabulary = rulebase_from_json(to_json(rulebase, VOCABULARY))
    assert loaded == rulebase
    assert vocabulary == VOCABULARY


def mutated(change):
    data = json.loads(to_json(EXAMPLE, VOCABULARY))
    change(data)
    return json.dumps(data)


@pytest.mark.parametrize("text, message", [
    ("{", "not valid JSON"),
    ("[]", "top level: expected an object"),
    (mutated(lambda d: d.update(format="other")), "format: expected 'soccer-lab-rulebase', found \"other\""),
    (mutated(lambda d: d.update(version=2)), "version: expected 1"),
    (mutated(lambda d: d["rules"][1]["premises"][0].update(term="NEARR")), "rules[1].premises[0].term: expected one of"),
    (mutated(lambda d: d["rules"][0]["premises"][0].update(object="BALLS")), "rules[0].premises[0].object"),
    (mutated(lambda d: d["rules"][0]["premises"][0].update(negated="yes")), "negated: expected true or false"),
    (mutated(lambda d: d["rules"][0].update(connectors=["OR"])), "rules[0].connectors: expected a list of 2"),
    (mutated(lambda d: d["rules"][0].update(connectors=["OR", "XOR"])), "rules[0].connectors[1]: expected AND or OR"),
    (mutated(lambda d: d["rules"][2]["consequent"].update(action="JUMP")), "rules[2].consequent.action"),
    (mutated(lambda d: d["rules"][2]["consequent"].update(power="LEFT")), "rules[2].consequent.power: expected null"),
    (mutated(lambda d: d["rules"][2].update(premises=[])), "rules[2].premises: expected a non-empty list"),
    (mutated(lambda d: d["rules"][3].update(extra=1)), "rules[3]: expected only the keys"),
    (mutated(lambda d: d["rules"][3]["consequent"].pop("power")), "missing power"),
    (mutated(lambda d: d["vocabulary"].pop("actions")), "vocabulary: malformed vocabulary"),
])
def test_json_loader_names_what_is_wrong(text, message):
    with pytest.raises(RulebaseFormatError) as caught:
        rulebase_from_json(text)
    assert message in str(caught.value)


def test_fll_loads_in_pyfuzzylite_with_explicit_grouping():
    engine = fl.FllImporter().from_string(to_fll(EXAMPLE, VOCABULARY))
    assert engine.input_variable("ball_visible") is not None
    first = engine.rule_blocks[0].rules[0].antecedent.text
    assert first == ("((ball_visible is YES and ball_distance is NEAR) or (ball_visible is YES and ball_distance "
                     "is not FAR)) and (goal_visible is YES and goal_distance is NEAR)")
    names = [v.name for v in engine.output_variables]
    assert names == ["runtowardball_support", "runtowardball_power", "kick_support", "kick_direction", "kick_power",
                     "turn_support", "turn_direction", "donothing_support"]  # actions by their first rule


def test_fcl_follows_the_standards_production_rules():
    block = parse_fcl(to_fcl(EXAMPLE, VOCABULARY))
    assert block.operators == {"AND": "MIN", "ACT": "MIN", "ACCU": "MAX"}
    assert set(block.inputs) == {"ball_distance", "ball_direction", "goal_distance", "goal_direction",
                                 "ball_visible", "goal_visible"}
    assert set(block.methods.values()) == {"MM"}
    # one conclusion per rule: the support, then each non-Null parameter the action uses
    assert [c for _, c in block.rules] == [
        [("runtowardball_support", "FIRED")], [("runtowardball_power", "LOW")],
        [("kick_support", "FIRED")], [("kick_direction", "SLIGHTLYRIGHT")], [("kick_power", "HIGH")],
        [("turn_support", "FIRED")], [("turn_direction", "LEFT")],
        [("donothing_support", "FIRED")],
    ]
    assert block.rules[0][0] == block.rules[1][0]
    assert "is not FAR" in block.rules[0][0]
    assert "turn_power" not in block.outputs  # Turn's unused power is not exported


@given(st.integers(0, 2**32 - 1))
def test_fcl_of_any_rulebase_follows_the_standard(seed):
    rulebase = random_rulebase(np.random.default_rng(seed), VOCABULARY, rules=1 + int(seed % 12))
    block = parse_fcl(to_fcl(rulebase, VOCABULARY))
    layout = FisLayout(rulebase, VOCABULARY)
    assert len(block.rules) == sum(len(layout.conclusions(rule)) for rule in rulebase)


@pytest.mark.parametrize("old, new, message", [
    ("(*\n    ACCU : MAX; // fuzzylite reads ACCU here, the standard in RULEBLOCK *)", "\n    ACCU : MAX;",
     "expected TERM, found ACCU"),
    ("RULE 1 :", "// a comment fuzzylite reads\n    RULE 1 :", "character '/'"),
    ("ACT : MIN; ACCU : MAX; (*", "ACT : MIN; (*", "expected ACCU"),
])
def test_the_standard_reader_is_strict(old, new, message):
    """What only fuzzylite reads, taken out of its standard comment, breaks the standard's view."""
    text = to_fcl(EXAMPLE, VOCABULARY)
    assert old in text
    with pytest.raises(FclError, match=message):
        parse_fcl(text.replace(old, new, 1))


def test_fcl_shoulders_are_flat_beyond_their_end_points():
    text = to_fcl(EXAMPLE, VOCABULARY)
    distance = text.split("FUZZIFY ball_distance")[1].split("END_FUZZIFY")[0]
    assert "TERM AT := (0, 1) (1, 1) (2, 0);" in distance
    assert "TERM VERYFAR := (40, 0) (60, 1) (130, 1);" in distance
    assert "TERM LEFT180 := (-180, 1) (-90, 0);" in text.split("FUZZIFY ball_direction")[1]


def test_fis_expands_or_into_rules_and_reads_repeated_inputs_from_copies():
    text = to_fis(parse_rulebase("if (Ball is Near or Ball is not Far) and Ball is not VeryNear then Kick High\n",
                                 VOCABULARY), VOCABULARY)
    names = re.findall(r"^Name='(\w+)'", text, flags=re.M)
    assert names[1:8] == ["ball_distance", "ball_direction", "goal_distance", "goal_direction", "ball_visible",
                          "goal_visible", "ball_distance_2"]
    assert names[8:] == ["kick_support", "kick_direction", "kick_power"]
    rules = text.split("[Rules]\n")[1].splitlines()
    # (Near and not VeryNear) or (not Far and not VeryNear); the second test of ball_distance reads the copy
    assert rules == ["3 0 0 0 1 0 -2, 1 0 6 (1) : 1", "-7 0 0 0 1 0 -2, 1 0 6 (1) : 1"]
    assert "NumRules=2" in text and "NumInputs=7" in text and "DefuzzMethod='mom'" in text


def test_fis_ranges_have_our_defaults_in_their_middle():
    """MATLAB gives an output no rule fired for the middle of its range: that must be our default."""
    text = to_fis(EXAMPLE, VOCABULARY)
    ranges = dict(re.findall(r"^Name='(\w+)'\nRange=\[([^]]+)\]", text, flags=re.M))
    assert ranges["kick_power"] == "0 110"  # default 55
    assert ranges["kick_direction"] == "-180 180"  # default 0
    assert ranges["kick_support"] == "-1 1"  # 0 when no rule of the action fired
    assert "MF7='VERYHIGH':'trapmf',[85 100 100 100]" in text  # terms keep their own feet


def test_unknown_export_format():
    with pytest.raises(ValueError, match="unknown export format 'xml'; expected one of json, fcl, fll, fis"):
        export_rulebase(EXAMPLE, "xml", VOCABULARY)
