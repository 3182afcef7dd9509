"""Rule text (docs/reference/rules.md): parsing, printing with explicit grouping, errors with line and column."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rule, parse_rulebase
from soccer_lab.fuzzy.printer import format_rule, format_rulebase
from soccer_lab.fuzzy.rule import AND, OR, Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.tokenizer import tokenize_line
from soccer_lab.fuzzy.vocabulary import Vocabulary

VOCABULARY = Vocabulary.default()


def test_chapter_examples_parse_to_the_model():
    assert parse_rule("if Ball is Near and Goal is not Far then KickTowardGoal Low", VOCABULARY) == Rule(
        (Premise("BALL", "NEAR"), Premise("GOAL", "FAR", negated=True)), (AND,),
        Consequent("KICKTOWARDGOAL", None, "LOW"))
    assert parse_rule("if Ball is Left then Turn Left", VOCABULARY) == Rule(
        (Premise("BALL", "LEFT"),), (), Consequent("TURN", "LEFT", None))
    assert parse_rule("if Ball is At then Kick SlightlyRight High", VOCABULARY).consequent == Consequent(
        "KICK", "SLIGHTLYRIGHT", "HIGH")
    assert parse_rule("if Ball is At then DoNothing", VOCABULARY).consequent == Consequent("DONOTHING")


def test_case_comments_blank_lines():
    text = "\n# a comment\n  IF BALL IS NOT near Or goal IS Left180 THEN runtowardball LOW   # trailing\n\n"
    assert parse_rulebase(text, VOCABULARY) == Rulebase((Rule(
        (Premise("BALL", "NEAR", True), Premise("GOAL", "LEFT180")), (OR,), Consequent("RUNTOWARDBALL", None, "LOW")),))
    assert parse_rulebase("# nothing here\n\n", VOCABULARY) == Rulebase(())


def test_printing_shows_left_to_right_grouping():
    rule = parse_rule("if Ball is Near or Ball is not Far and Goal is Near then RunTowardBall Low", VOCABULARY)
    assert (format_rule(rule, VOCABULARY)
            == "if (Ball is Near or Ball is not Far) and Goal is Near then RunTowardBall Low")
    rule = parse_rule("if Ball is Left or Goal is Near and Ball is Far or Goal is At then Dash", VOCABULARY)
    assert (format_rule(rule, VOCABULARY)
            == "if ((Ball is Left or Goal is Near) and Ball is Far) or Goal is At then Dash")
    rule = parse_rule("if Ball is Left and Goal is Near and Ball is Far then Dash", VOCABULARY)
    assert format_rule(rule, VOCABULARY) == "if Ball is Left and Goal is Near and Ball is Far then Dash"


def test_parentheses_that_match_the_grouping_are_accepted():
    plain = parse_rule("if Ball is Left or Goal is Near and Ball is Far then Dash", VOCABULARY)
    for text in ("if (Ball is Left or Goal is Near) and Ball is Far then Dash",
                 "if ((Ball is Left or Goal is Near) and Ball is Far) then Dash",
                 "if ((Ball is Left) or Goal is Near) and Ball is Far then Dash"):
        assert parse_rule(text, VOCABULARY) == plain


def test_unused_and_null_fields_round_trip():
    for consequent, text in [
        (Consequent("TURN", "LEFT", "HIGH"), "Turn Left [power High]"),
        (Consequent("TURN", None, "HIGH"), "Turn [power High]"),
        (Consequent("KICK", None, "HIGH"), "Kick High"),
        (Consequent("KICK", "LEFT", None), "Kick Left"),
        (Consequent("DASH", "RIGHT180", None), "Dash [direction Right180]"),
        (Consequent("DONOTHING", "LEFT", "LOW"), "DoNothing [direction Left, power Low]"),
    ]:
        rule = Rule((Premise("BALL", "AT"),), (), consequent)
        assert format_rule(rule, VOCABULARY) == f"if Ball is At then {text}"
        assert parse_rule(format_rule(rule, VOCABULARY), VOCABULARY) == rule


MALFORMED = [
    # (text, line, column, what the message must say)
    ("Ball is Near then Turn", 1, 1, "expected 'if', found 'Ball'"),
    ("if Bal is Near then Turn", 1, 4, "expected an object (Ball, Goal), found 'Bal'"),
    ("if Ball Near then Turn", 1, 9, "expected 'is', found 'Near'"),
    ("if Ball is Nearr then Turn", 1, 12, "expected 'not' or a term (At, VeryNear"),
    ("if Ball is not not Near then Turn", 1, 16, "expected a term (At,"),
    ("if Ball is Near Goal is Far then Turn", 1, 17, "expected 'and', 'or' or 'then', found 'Goal'"),
    ("if Ball is Near then", 1, 21, "expected an action (Turn, Dash, Kick"),
    ("if Ball is Near then Jump", 1, 22, "found 'Jump'"),
    ("if Ball is Near and (Goal is Far or Ball is At) then Turn", 1, 21,
     "found '(' (premises combine strictly left to right"),
    ("if (Ball is Near and Goal is Far then Turn", 1, 34, "expected ')', found 'then'"),
    ("if Ball is Near) then Turn", 1, 16, "found ')' (this ')' closes no '(')"),
    ("if (Ball is Near and Goal is Far Turn", 1, 34, "expected 'and', 'or' or ')', found 'Turn'"),
    ("if Ball is Near then Turn High", 1, 27, "Turn does not use power; write [power High]"),
    ("if Ball is Near then Kick High Left", 1, 32, "found 'Left' (Kick takes at most one term each"),
    ("if Ball is Near then Turn Left [power]", 1, 38, "expected a power term (VeryLow"),
    ("if Ball is Near then Turn Left [direction Left]", 1, 33, "expected a parameter Turn does not use (power)"),
    ("if Ball is Near then Turn [power High, power Low]", 1, 40, "a parameter not given yet"),
    ("if Ball is Near then Turn [power High", 1, 38, "expected ',' or ']', found end of line"),
    ("if Ball is Near then Kick Left High extra", 1, 37, "expected end of line, found 'extra'"),
    ("if Ball % Near then Turn", 1, 9, "expected 'is', found '%'"),
    ("if then Turn", 1, 4, "expected an object (Ball, Goal), found 'then'"),
    ("\n\n  if Ball is Near and then Turn", 3, 23, "expected an object (Ball, Goal), found 'then'"),
]


@pytest.mark.parametrize("text, line, column, message", MALFORMED, ids=[m[3][:40] for m in MALFORMED])
def test_malformed_text_names_line_column_and_what_was_expected(text, line, column, message):
    with pytest.raises(RuleSyntaxError) as caught:
        parse_rulebase(text, VOCABULARY)
    error = caught.value
    assert (error.line, error.column) == (line, column)
    assert str(error).startswith(f"line {line}, column {column}: expected ")
    assert message in str(error)


def test_every_error_of_a_text_is_collected():
    text = "if Ball is Near then Turn\nif Ball is Nearr then Turn\n# ok\nif Goal is Far then\nif Ball is At then Dash"
    with pytest.raises(RuleSyntaxError) as caught:
        parse_rulebase(text, VOCABULARY)
    assert [(e.line, e.column) for e in caught.value.errors] == [(2, 12), (4, 20)]
    assert caught.value.expected.startswith("'not' or a term")
    assert caught.value.found == "'Nearr'"


def test_tokenizer_positions():
    tokens = tokenize_line("if (Ball is Near) # c", 7)
    assert [(t.kind, t.text, t.column) for t in tokens] == [
        ("word", "if", 1), ("(", "(", 4), ("word", "Ball", 5), ("word", "is", 10), ("word", "Near", 13),
        (")", ")", 17), ("end of line", "", 19)]
    assert {t.line for t in tokens} == {7}


def fields(output):
    return st.one_of(st.none(), st.sampled_from(VOCABULARY.output_variable(output).term_names))


premises = st.builds(Premise, st.sampled_from(VOCABULARY.object_names), st.sampled_from(VOCABULARY.premise_terms),
                     st.booleans())
consequents = st.builds(Consequent, st.sampled_from(VOCABULARY.action_names), fields("direction"), fields("power"))
rules = st.lists(premises, min_size=1, max_size=6).flatmap(
    lambda ps: st.builds(Rule, st.just(tuple(ps)),
                         st.lists(st.sampled_from([AND, OR]), min_size=len(ps) - 1, max_size=len(ps) - 1).map(tuple),
                         consequents))
rulebases = st.lists(rules, max_size=8).map(lambda rs: Rulebase(tuple(rs)))


@given(rulebases)
def test_print_then_parse_is_the_identity(rulebase):
    text = format_rulebase(rulebase, VOCABULARY)
    assert parse_rulebase(text, VOCABULARY) == rulebase
    assert parse_rulebase(text.upper(), VOCABULARY) == rulebase
    assert format_rulebase(parse_rulebase(text, VOCABULARY), VOCABULARY) == text
