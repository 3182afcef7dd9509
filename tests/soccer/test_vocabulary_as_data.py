"""The vocabulary is data: its order is nobody's constant. A vocabulary listing the same actions,
objects, inputs, outputs and terms in other orders plays exactly the same games; one the skills or
perception cannot serve is refused with a message that says why."""

import numpy as np
import pytest

from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary, VocabularyError
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.notation import format_compact, parse_compact
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import GameBatch, play_game, play_games

VOCABULARY = Vocabulary.default()
# Assisted skills: random rulebases then reach the ball often, so kicks and goals are part of what is compared.
SHORT = GameConfig(max_ticks=300, skills="assisted")


def reversed_dict(mapping):
    return dict(reversed(list(mapping.items())))


def reordered(data):
    """Every ordered part of a vocabulary document reversed: actions, objects (and each object's
    inputs), inputs, outputs and each variable's terms."""
    data = dict(data)
    data["actions"] = reversed_dict(data["actions"])
    data["objects"] = {obj: reversed_dict(kinds) for obj, kinds in reversed_dict(data["objects"]).items()}
    data["inputs"] = reversed_dict(data["inputs"])
    data["outputs"] = reversed_dict(data["outputs"])
    data["variables"] = {name: {**spec, "terms": reversed_dict(spec["terms"])}
                         for name, spec in reversed_dict(data["variables"]).items()}
    return data


REORDERED = Vocabulary.from_dict(reordered(VOCABULARY.to_dict()))


def test_the_reordered_vocabulary_really_orders_everything_differently():
    assert REORDERED == Vocabulary.from_dict(reordered(VOCABULARY.to_dict()))
    assert REORDERED.action_names == VOCABULARY.action_names[::-1]
    assert REORDERED.object_names == VOCABULARY.object_names[::-1]
    assert REORDERED.input_names == VOCABULARY.input_names[::-1]
    assert REORDERED.output_names == VOCABULARY.output_names[::-1]
    assert REORDERED.premise_terms != VOCABULARY.premise_terms
    assert sorted(REORDERED.premise_terms) == sorted(VOCABULARY.premise_terms)


def test_a_reordered_vocabulary_plays_exactly_the_same_games():
    rng = np.random.default_rng(12)
    rulebases = [demo_rulebase()] + [random_rulebase(rng, VOCABULARY, rules=10) for _ in range(23)]
    seeds = list(range(500, 524))
    results = play_games(rulebases, seeds, SHORT, VOCABULARY)
    assert sum(r.kicks > 0 for r in results) >= 3 and sum(r.goals for r in results) > 0  # real play
    assert play_games(rulebases, seeds, SHORT, REORDERED) == results


@pytest.mark.parametrize("game", [0, 3, 7])
def test_a_reordered_vocabulary_gives_the_same_trace_tick_for_tick(game):
    rng = np.random.default_rng(12)
    rulebases = [demo_rulebase()] + [random_rulebase(rng, VOCABULARY, rules=10) for _ in range(7)]
    expected, expected_trace = play_game(rulebases[game], 500 + game, SHORT, vocabulary=VOCABULARY)
    result, trace = play_game(rulebases[game], 500 + game, SHORT, vocabulary=REORDERED)
    assert result == expected and trace.vocabulary is REORDERED
    for name in ("player_x", "player_y", "facing", "ball_x", "ball_y", "strengths", "direction", "power", "goals"):
        np.testing.assert_array_equal(getattr(trace, name), getattr(expected_trace, name), err_msg=name)

    def named(trace, what, names):
        return {name: getattr(trace, what)[:, names.index(name)] for name in names}

    for name, column in named(expected_trace, "inputs", VOCABULARY.input_names).items():
        np.testing.assert_array_equal(named(trace, "inputs", REORDERED.input_names)[name], column, err_msg=name)
    for name, column in named(expected_trace, "visible", VOCABULARY.object_names).items():
        np.testing.assert_array_equal(named(trace, "visible", REORDERED.object_names)[name], column, err_msg=name)

    def action_names(trace):
        return ["hunt" if a < 0 else trace.vocabulary.action_names[a] for a in trace.action]

    assert action_names(trace) == action_names(expected_trace)
    assert len(set(action_names(trace))) >= 2


def test_chromosomes_mean_the_same_rules_in_the_reordered_vocabulary():
    text = "(B,N,O) (B,nF,A) (G,N,A) (RB,n,L) (B,A,A) (G,vN,O) (KG,n,M) (B,L,A) (T,L,n)"
    rulebase = ChromosomeCodec(VOCABULARY).decode(parse_compact(text, VOCABULARY))
    chromosome = parse_compact(text, REORDERED)
    assert ChromosomeCodec(REORDERED).decode(chromosome) == rulebase
    assert format_compact(chromosome, REORDERED) == text


def changed(edit):
    data = VOCABULARY.to_dict()
    edit(data)
    return Vocabulary.from_dict(data)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["actions"].update(JUMP=["power"]), "no skill performs JUMP"),
        (lambda d: d["actions"].update(DASH=["direction", "power"]),
         "DASH uses direction, power but its skill reads power"),
        (lambda d: d["actions"].update(TURN=[]), "TURN uses no parameter but its skill reads direction"),
        (lambda d: (d["objects"].pop("GOAL"), d["abbreviations"].pop("GOAL")),
         "SimpleSoccer perceives BALL and GOAL"),
    ],
)
def test_a_vocabulary_the_skills_or_perception_cannot_serve_is_refused(edit, message):
    vocabulary = changed(edit)
    with pytest.raises(VocabularyError, match=message):
        GameBatch([demo_rulebase()], [1], SHORT, vocabulary)


def test_the_refusal_names_the_skills():
    with pytest.raises(VocabularyError, match="the skills are TURN, DASH, KICK, RUNTOWARDGOAL"):
        GameBatch([demo_rulebase()], [1], SHORT, changed(lambda d: d["actions"].update(JUMP=[])))


def test_a_subset_of_the_actions_is_served():
    vocabulary = changed(lambda d: [(d["actions"].pop(a), d["abbreviations"].pop(a))
                                    for a in ("TURN", "DASH", "DONOTHING")])
    assert play_games([demo_rulebase()], [3], SHORT, vocabulary) == play_games([demo_rulebase()], [3], SHORT)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["outputs"].update(angle={"variable": "direction", "default": 0.0}),
         "the outputs must be direction and power"),
        (lambda d: d["abbreviations"].update(JUMP="J"), "abbreviations of unknown names: JUMP"),
    ],
)
def test_a_vocabulary_file_is_checked_when_read(edit, message):
    with pytest.raises(VocabularyError, match=message):
        changed(edit)


def test_abbreviations_live_in_the_vocabulary_file_and_do_not_change_its_meaning():
    assert VOCABULARY.abbreviations["MEDIUMDISTANT"] == VOCABULARY.abbreviations["MEDIUMPOWER"] == "M"
    without = changed(lambda d: d.pop("abbreviations"))
    assert without == VOCABULARY and without.abbreviations == {}  # e.g. a rulebase file saved before them


def test_editing_a_vocabulary_document_leaves_the_vocabulary_alone():
    data = VOCABULARY.to_dict()
    data["objects"]["BALL"]["distance"] = "x"
    data["inputs"].clear()
    data["abbreviations"]["BALL"] = "Q"
    assert VOCABULARY.to_dict() != data and VOCABULARY.objects["BALL"]["distance"] == "ball_distance"
