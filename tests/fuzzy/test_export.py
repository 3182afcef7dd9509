"""Export (spec 2.4): lossless JSON, FLL that pyfuzzylite runs to the same outputs, well-formed FCL."""

import json
import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from fuzzy.defuzzifier import sampled_error_bound
from fuzzy.engine import Engine
from fuzzy.export import RulebaseFormatError, export_rulebase, rulebase_from_json, to_fcl, to_fll, to_json
from fuzzy.export.layout import RESOLUTION, parameter_output, support_output
from fuzzy.parser import parse_rulebase
from fuzzy.random_rulebase import random_rulebase
from fuzzy.vocabulary import Vocabulary

fl = pytest.importorskip("fuzzylite")

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


def load_fll(rulebase):
    return fl.FllImporter().from_string(to_fll(rulebase, VOCABULARY))


def test_fll_loads_in_pyfuzzylite_with_explicit_grouping():
    engine = load_fll(EXAMPLE)
    assert engine.input_variable("ball_visible") is not None
    first = engine.rule_blocks[0].rules[0].antecedent.text
    assert first == ("((ball_visible is YES and ball_distance is NEAR) or (ball_visible is YES and ball_distance "
                     "is not FAR)) and (goal_visible is YES and goal_distance is NEAR)")
    names = {v.name for v in engine.output_variables}
    assert names == {"runtowardball_support", "runtowardball_power", "kick_support", "kick_direction", "kick_power",
                     "turn_support", "turn_direction", "donothing_support"}


def test_fll_in_pyfuzzylite_matches_our_engine_to_its_sampling_error():
    rng = np.random.default_rng(2024)
    compared = 0
    for _ in range(8):
        rulebase = random_rulebase(rng, VOCABULARY, rules=10)
        engine = load_fll(rulebase)
        n = 150
        inputs = np.column_stack([rng.uniform(v.minimum - 10, v.maximum + 10, n)
                                  for v in (VOCABULARY.variables[k] for k in VOCABULARY.inputs.values())])
        visible = rng.random((n, 2)) < 0.8
        for j, name in enumerate(VOCABULARY.input_names):
            engine.input_variable(name).value = inputs[:, j]
        for j, obj in enumerate(VOCABULARY.object_names):
            engine.input_variable(f"{obj.lower()}_visible").value = visible[:, j].astype(float)
        engine.process()

        def fll_value(name, i):
            return np.broadcast_to(engine.output_variable(name).value, (n,))[i]

        ours = Engine(rulebase, VOCABULARY)
        for i in range(n):
            seen = dict(zip(VOCABULARY.object_names, visible[i]))
            crisp = {name: (inputs[i, j] if seen[obj] else None) for j, name in enumerate(VOCABULARY.input_names)
                     for obj in VOCABULARY.object_names if name in VOCABULARY.objects[obj].values()}
            inference = ours.infer(crisp)
            fired = {a.action: a for a in inference.fired}
            for action in {r.consequent.action for r in rulebase}:
                support = fired[action].support if action in fired else 0.0
                assert fll_value(support_output(action), i) == pytest.approx(support, abs=1.0 / RESOLUTION)
                if action not in fired:
                    continue
                for output, value in fired[action].parameters.items():
                    variable = VOCABULARY.output_variable(output)
                    step = (variable.maximum - variable.minimum) / RESOLUTION
                    sets = inference.clipped_sets[action][output]
                    tolerance = sampled_error_bound(ours.maximum_cuts(output, sets), step) if sets else 0.0
                    if tolerance is None:  # a maximum made of points: sampling cannot see it (spec 2.2)
                        continue
                    assert fll_value(parameter_output(action, output), i) == pytest.approx(value, abs=tolerance + 1e-9)
                    compared += 1
    assert compared > 1000


def fcl_blocks(text):
    body = re.sub(r"\(\*.*?\*\)", "", text, flags=re.S)
    return body, {kind: dict(re.findall(rf"^{kind} (\w+)\n(.*?)^END_{kind}", body, flags=re.S | re.M))
                  for kind in ("FUZZIFY", "DEFUZZIFY")}


def test_fcl_is_well_formed():
    text = to_fcl(EXAMPLE, VOCABULARY)
    body, blocks = fcl_blocks(text)
    lines = [line.strip() for line in body.splitlines() if line.strip()]
    assert lines[0] == "FUNCTION_BLOCK soccer_lab" and lines[-1] == "END_FUNCTION_BLOCK"
    for opener in ("VAR_INPUT", "VAR_OUTPUT", "FUZZIFY", "DEFUZZIFY", "RULEBLOCK"):
        opened = sum(line.split()[0] == opener for line in lines)
        closed = sum(line == {"VAR_INPUT": "END_VAR", "VAR_OUTPUT": "END_VAR"}.get(opener, f"END_{opener}")
                     for line in lines)
        assert opened >= 1 and (opener.startswith("VAR") or opened == closed)
    statements = [line for line in lines if not line.startswith(("FUNCTION_BLOCK", "END_", "VAR_", "FUZZIFY",
                                                                   "DEFUZZIFY", "RULEBLOCK"))]
    assert all(line.endswith(";") for line in statements)
    declared_inputs = set(re.findall(r"^\s+(\w+) : REAL;", body.split("VAR_OUTPUT")[0], flags=re.M))
    assert declared_inputs == set(blocks["FUZZIFY"])
    terms = {name: set(re.findall(r"TERM (\w+) :=", block)) for kind in blocks.values() for name, block in kind.items()}
    for block in blocks["DEFUZZIFY"].values():
        assert re.search(r"METHOD : (MM|LM);", block) and re.search(r"DEFAULT := [-\d.]+;", block)
    rules = re.findall(r"RULE (\d+) : IF (.*) THEN (.*);", body)
    assert [int(r[0]) for r in rules] == [1, 2, 3, 4]
    for _, antecedent, conclusion in rules:
        depth = 0
        for char in antecedent:
            depth += {"(": 1, ")": -1}.get(char, 0)
            assert depth >= 0
        assert depth == 0
        for variable, term in re.findall(r"(\w+) IS (?:NOT )?(\w+)", antecedent + ", " + conclusion):
            assert term in terms[variable]
    assert "IS NOT FAR" in rules[0][1] and "turn_direction IS LEFT" in rules[2][2]
    assert "turn_power" not in body  # Turn's unused power is not exported


def test_fcl_shoulders_are_flat_beyond_their_end_points():
    _, blocks = fcl_blocks(to_fcl(EXAMPLE, VOCABULARY))
    distance = blocks["FUZZIFY"]["ball_distance"]
    assert "TERM AT := (0, 1) (1, 1) (2, 0);" in distance
    assert "TERM VERYFAR := (40, 0) (60, 1) (130, 1);" in distance
    assert "TERM LEFT180 := (-180, 1) (-90, 0);" in blocks["FUZZIFY"]["ball_direction"]


def test_unknown_export_format():
    with pytest.raises(ValueError, match="unknown export format 'xml'; expected one of json, fcl, fll"):
        export_rulebase(EXAMPLE, "xml", VOCABULARY)
