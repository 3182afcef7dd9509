"""Rule text -> Rulebase, by recursive descent over the tokens of fuzzy/tokenizer.py.

One rule a line; keywords, objects, terms and actions in any case; `#` comments; blank lines.

    rule        := 'if' antecedent 'then' consequent
    antecedent  := '('* premise ( ')'* connector premise )* ')'*
    premise     := OBJECT 'is' ['not'] TERM
    connector   := 'and' | 'or'
    consequent  := ACTION used_term* [ '[' unused_field (',' unused_field)* ']' ]
    unused_field:= OUTPUT TERM          e.g.  [power High]

Premises combine strictly left to right, so a '(' is accepted only at the start of the
antecedent (it groups a leading run of premises) and every '(' must be closed before 'then'.
After the action come the terms of the parameters it uses, in the vocabulary's output order
(direction before power); a Null parameter is simply left out. A parameter the action does not
use is kept as genetic material and written in brackets: `then Turn Left [power High]`.
"""

from __future__ import annotations

from soccer_lab.fuzzy.rule import AND, OR, Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.tokenizer import COMMA, END, LBRACKET, LPAREN, RBRACKET, RPAREN, WORD, Token, tokenize
from soccer_lab.fuzzy.vocabulary import Vocabulary

IF, THEN, IS, NOT = "if", "then", "is", "not"
CONNECTOR_WORDS = {"and": AND, "or": OR}


class RuleSyntaxError(ValueError):
    """A syntax error at a line and column. `errors` holds every error of the text parsed (this one first)."""

    def __init__(self, line: int, column: int, expected: str, found: str, hint: str = ""):
        self.line = line
        self.column = column
        self.expected = expected
        self.found = found
        self.hint = hint
        self.errors: list[RuleSyntaxError] = [self]
        super().__init__(self.message)

    @property
    def message(self) -> str:
        """'expected X, found Y' (plus a hint), without the position."""
        text = f"expected {self.expected}, found {self.found}"
        return f"{text} ({self.hint})" if self.hint else text

    def __str__(self) -> str:
        return f"line {self.line}, column {self.column}: {self.message}"


def parse_rulebase(text: str, vocabulary: Vocabulary) -> Rulebase:
    """Parse every line of `text`; raise RuleSyntaxError (with all errors in `.errors`) if any line is wrong."""
    rules: list[Rule] = []
    errors: list[RuleSyntaxError] = []
    for tokens in tokenize(text):
        if tokens[0].kind == END:
            continue
        try:
            rules.append(_LineParser(tokens, vocabulary).rule())
        except RuleSyntaxError as error:
            errors.append(error)
    if errors:
        errors[0].errors = errors
        raise errors[0]
    return Rulebase(tuple(rules))


def parse_rule(text: str, vocabulary: Vocabulary) -> Rule:
    """Parse exactly one rule (one line)."""
    rulebase = parse_rulebase(text, vocabulary)
    if len(rulebase) != 1:
        raise RuleSyntaxError(1, 1, "exactly one rule", f"{len(rulebase)} rules")
    return rulebase.rules[0]


def _alternatives(options: list[str]) -> str:
    """'a', 'a or b', 'a, b or c'."""
    return options[0] if len(options) == 1 else ", ".join(options[:-1]) + " or " + options[-1]


def _one_of(words: list[str]) -> str:
    return _alternatives([f"'{w}'" for w in words])


class _LineParser:
    def __init__(self, tokens: list[Token], vocabulary: Vocabulary):
        self.tokens = tokens
        self.position = 0
        self.vocabulary = vocabulary

    # ---- token helpers -----------------------------------------------------------------------
    @property
    def token(self) -> Token:
        return self.tokens[self.position]

    def advance(self) -> Token:
        token = self.token
        if token.kind != END:
            self.position += 1
        return token

    def is_word(self, word: str) -> bool:
        return self.token.kind == WORD and self.token.text.lower() == word

    def error(self, expected: str, hint: str = "") -> RuleSyntaxError:
        return RuleSyntaxError(self.token.line, self.token.column, expected, self.token.describe(), hint)

    def expect_word(self, word: str) -> None:
        if not self.is_word(word):
            raise self.error(f"'{word}'")
        self.advance()

    def names(self, keys) -> str:
        return ", ".join(self.vocabulary.display(k) for k in keys)

    # ---- grammar -----------------------------------------------------------------------------
    def rule(self) -> Rule:
        self.expect_word(IF)
        premises, connectors = self.antecedent()
        consequent = self.consequent()
        return Rule(tuple(premises), tuple(connectors), consequent)

    def antecedent(self) -> tuple[list[Premise], list[str]]:
        open_groups = 0
        while self.token.kind == LPAREN:
            open_groups += 1
            self.advance()
        premises = [self.premise()]
        connectors: list[str] = []
        while True:
            while self.token.kind == RPAREN:
                if open_groups == 0:
                    raise self.error(f"{_one_of(['and', 'or', 'then'])}", "this ')' closes no '('")
                open_groups -= 1
                self.advance()
            if self.is_word(THEN):
                if open_groups:
                    raise self.error("')'", f"{open_groups} '(' still open before 'then'")
                self.advance()
                return premises, connectors
            if self.token.kind == WORD and self.token.text.lower() in CONNECTOR_WORDS:
                connectors.append(CONNECTOR_WORDS[self.advance().text.lower()])
            else:
                expected = ["and", "or", "then"] if open_groups == 0 else ["and", "or", ")"]
                raise self.error(_one_of(expected))
            if self.token.kind == LPAREN:
                raise self.error(
                    f"an object ({self.names(self.vocabulary.object_names)})",
                    "premises combine strictly left to right, so '(' may only open at the start of the rule",
                )
            premises.append(self.premise())

    def premise(self) -> Premise:
        objects = self.vocabulary.object_names
        if self.token.kind != WORD or self.vocabulary.canonical(self.token.text) not in objects:
            raise self.error(f"an object ({self.names(objects)})")
        obj = self.vocabulary.canonical(self.advance().text)
        self.expect_word(IS)
        negated = self.is_word(NOT)
        if negated:
            self.advance()
        terms = self.vocabulary.premise_terms
        if self.token.kind != WORD or self.vocabulary.canonical(self.token.text) not in terms:
            expected = "a term" if negated else f"'{NOT}' or a term"
            raise self.error(f"{expected} ({self.names(terms)})")
        return Premise(obj, self.vocabulary.canonical(self.advance().text), negated)

    def consequent(self) -> Consequent:
        actions = self.vocabulary.action_names
        if self.token.kind != WORD or self.vocabulary.canonical(self.token.text) not in actions:
            raise self.error(f"an action ({self.names(actions)})")
        action = self.vocabulary.canonical(self.advance().text)
        fields: dict[str, str | None] = {output: None for output in self.vocabulary.output_names}
        self.used_terms(action, fields)
        if self.token.kind == LBRACKET:
            self.advance()
            self.unused_fields(action, fields)
        if self.token.kind != END:
            raise self.error("end of line")
        return Consequent(action, **fields)

    def used_terms(self, action: str, fields: dict[str, str | None]) -> None:
        """The bare terms after the action, each filling the next used parameter it belongs to."""
        remaining = list(self.vocabulary.actions[action])
        while self.token.kind == WORD:
            word = self.vocabulary.canonical(self.token.text)
            for index, output in enumerate(remaining):
                if word in self.vocabulary.output_variable(output).term_names:
                    fields[output] = word
                    del remaining[: index + 1]
                    self.advance()
                    break
            else:
                raise self.error(self.expected_after_action(action, remaining), self.unused_hint(action, word))

    def expected_after_action(self, action: str, remaining: list[str]) -> str:
        options = [
            f"a {output} term ({self.names(self.vocabulary.output_variable(output).term_names)})" for output in remaining
        ]
        unused = [o for o in self.vocabulary.output_names if o not in self.vocabulary.actions[action]]
        if unused:
            options.append("'['")
        options.append("end of line")
        return _alternatives(options)

    def unused_hint(self, action: str, word: str) -> str:
        for output in self.vocabulary.output_names:
            if word in self.vocabulary.output_variable(output).term_names:
                if output not in self.vocabulary.actions[action]:
                    shown = self.vocabulary.display(word)
                    return (
                        f"{self.vocabulary.display(action)} does not use {output}; "
                        f"write [{output} {shown}] to keep it unused"
                    )
                order = ", then ".join(self.vocabulary.actions[action])
                return f"{self.vocabulary.display(action)} takes at most one term each for {order}"
        return ""

    def unused_fields(self, action: str, fields: dict[str, str | None]) -> None:
        unused = [o for o in self.vocabulary.output_names if o not in self.vocabulary.actions[action]]
        while True:
            by_name = {o.lower(): o for o in unused}
            if self.token.kind != WORD or self.token.text.lower() not in by_name:
                expected = f"a parameter {self.vocabulary.display(action)} does not use ({', '.join(unused)})"
                raise self.error(expected if unused else "']'")
            if fields[by_name[self.token.text.lower()]] is not None:
                raise self.error("a parameter not given yet in these brackets")
            output = by_name[self.advance().text.lower()]
            terms = self.vocabulary.output_variable(output).term_names
            if self.token.kind != WORD or self.vocabulary.canonical(self.token.text) not in terms:
                raise self.error(f"a {output} term ({self.names(terms)})")
            fields[output] = self.vocabulary.canonical(self.advance().text)
            if self.token.kind == RBRACKET:
                self.advance()
                return
            if self.token.kind != COMMA:
                raise self.error(_one_of([",", "]"]))
            self.advance()
