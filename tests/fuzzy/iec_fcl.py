"""A reader of IEC 61131-7 FCL that follows the standard's production rules to the letter.

No standard-following FCL reader installs here (jFuzzyLogic ships only on Maven), so the standard's
view of our FCL is checked by this parser: `(* *)` comments and nothing else, keywords in any case,
blocks and statements in the order the grammar gives (RULEBLOCK: operator definition, [ACT], ACCU,
rules; DEFUZZIFY: terms, METHOD, DEFAULT, [RANGE]), every name declared before use. MM (mean of
maximum) is accepted as METHOD beside the standard's five, as jFuzzyLogic and fuzzylite accept it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

TOKEN = re.compile(r"\s+|\(\*.*?\*\)"  # blanks and comments, then the tokens:
                   r"|(?P<t>:=|\.\.|[:;,()]|-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?|[A-Za-z_][A-Za-z0-9_]*)", re.S)
METHODS = {"COG", "COGS", "COA", "LM", "RM", "MM"}


class FclError(ValueError):
    pass


@dataclass
class FunctionBlock:
    inputs: dict[str, set[str]] = field(default_factory=dict)  # variable -> its terms
    outputs: dict[str, set[str]] = field(default_factory=dict)
    methods: dict[str, str] = field(default_factory=dict)
    operators: dict[str, str] = field(default_factory=dict)  # AND/OR, ACT, ACCU -> method
    rules: list[tuple[str, list[tuple[str, str]]]] = field(default_factory=list)  # (condition text, conclusions)


def tokens(text: str) -> list[str]:
    found, position = [], 0
    while position < len(text):
        match = TOKEN.match(text, position)
        if match is None:
            raise FclError(f"character {text[position]!r} at offset {position} is not FCL")
        if match.group("t"):
            found.append(match.group("t"))
        position = match.end()
    return found


class Parser:
    def __init__(self, text: str):
        self.tokens = tokens(text)
        self.at = 0
        self.block = FunctionBlock()

    def peek(self, *words: str) -> bool:
        return self.at < len(self.tokens) and self.tokens[self.at].upper() in words

    def take(self, *words: str) -> str:
        if not self.peek(*words):
            found = self.tokens[self.at] if self.at < len(self.tokens) else "the end"
            raise FclError(f"expected {' or '.join(words)}, found {found} (token {self.at})")
        self.at += 1
        return self.tokens[self.at - 1].upper()

    def name(self) -> str:
        token = self.tokens[self.at] if self.at < len(self.tokens) else ""
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", token):
            raise FclError(f"expected a name, found {token or 'the end'}")
        self.at += 1
        return token

    def number(self) -> float:
        token = self.tokens[self.at] if self.at < len(self.tokens) else ""
        try:
            value = float(token)
        except ValueError:
            raise FclError(f"expected a number, found {token or 'the end'}") from None
        self.at += 1
        return value

    def function_block(self) -> FunctionBlock:
        self.take("FUNCTION_BLOCK")
        self.name()
        while self.peek("VAR_INPUT", "VAR_OUTPUT"):
            kind = self.block.inputs if self.take("VAR_INPUT", "VAR_OUTPUT") == "VAR_INPUT" else self.block.outputs
            while not self.peek("END_VAR"):
                variable = self.name()
                self.take(":"), self.take("REAL"), self.take(";")
                kind[variable] = set()
            self.take("END_VAR")
        while self.peek("FUZZIFY"):
            self.take("FUZZIFY")
            self.terms(self.declared(self.block.inputs), "END_FUZZIFY")
            self.take("END_FUZZIFY")
        while self.peek("DEFUZZIFY"):
            self.take("DEFUZZIFY")
            variable = self.declared(self.block.outputs)
            self.terms(variable, "METHOD")
            self.take("METHOD"), self.take(":")
            self.block.methods[variable] = self.take(*METHODS)
            self.take(";"), self.take("DEFAULT"), self.take(":=")
            self.take("NC") if self.peek("NC") else self.number()
            self.take(";")
            if self.peek("RANGE"):
                self.take("RANGE"), self.take(":="), self.take("(")
                self.number(), self.take(".."), self.number()
                self.take(")"), self.take(";")
            self.take("END_DEFUZZIFY")
        while self.peek("RULEBLOCK"):
            self.rule_block()
        self.take("END_FUNCTION_BLOCK")
        if self.at != len(self.tokens):
            raise FclError(f"text after END_FUNCTION_BLOCK: {self.tokens[self.at]}")
        return self.block

    def declared(self, variables: dict[str, set[str]]) -> str:
        variable = self.name()
        if variable not in variables:
            raise FclError(f"{variable} is not declared in the VAR block it needs")
        return variable

    def terms(self, variable: str, closing: str) -> None:
        terms = {**self.block.inputs, **self.block.outputs}[variable]
        while not self.peek(closing):
            self.take("TERM")
            terms.add(self.name())
            self.take(":=")
            self.take("(")
            while True:
                self.number(), self.take(","), self.number(), self.take(")")
                if not self.peek("("):
                    break
                self.take("(")
            self.take(";")

    def rule_block(self) -> None:
        self.take("RULEBLOCK")
        self.name()
        operator = self.take("AND", "OR")
        self.take(":")
        methods = ("MIN", "PROD", "BDIF") if operator == "AND" else ("MAX", "ASUM", "BSUM")
        self.block.operators[operator] = self.take(*methods)
        self.take(";")
        if self.peek("ACT"):
            self.take("ACT"), self.take(":")
            self.block.operators["ACT"] = self.take("MIN", "PROD")
            self.take(";")
        self.take("ACCU"), self.take(":")
        self.block.operators["ACCU"] = self.take("MAX", "BSUM", "NSUM")
        self.take(";")
        while self.peek("RULE"):
            self.take("RULE")
            if not re.fullmatch(r"\d+", self.tokens[self.at]):
                raise FclError(f"expected a rule number, found {self.tokens[self.at]}")
            self.at += 1
            self.take(":"), self.take("IF")
            start = self.at
            self.condition()
            condition = " ".join(self.tokens[start:self.at])
            self.take("THEN")
            conclusions = [self.conclusion()]
            while self.peek(","):
                self.take(",")
                conclusions.append(self.conclusion())
            self.take(";")
            self.block.rules.append((condition, conclusions))
        self.take("END_RULEBLOCK")

    def condition(self) -> None:
        self.subcondition()
        while self.peek("AND", "OR"):
            self.take("AND", "OR")
            self.subcondition()

    def subcondition(self) -> None:
        if self.peek("NOT"):
            self.take("NOT")
        if self.peek("("):
            self.take("(")
            self.condition()
            self.take(")")
            return
        variable = self.declared(self.block.inputs)
        self.take("IS")
        if self.peek("NOT"):
            self.take("NOT")
        self.known_term(variable)

    def conclusion(self) -> tuple[str, str]:
        variable = self.declared(self.block.outputs)
        self.take("IS")
        return variable, self.known_term(variable)

    def known_term(self, variable: str) -> str:
        term = self.name()
        if term not in {**self.block.inputs, **self.block.outputs}[variable]:
            raise FclError(f"{variable} has no term {term}")
        return term


def parse_fcl(text: str) -> FunctionBlock:
    return Parser(text).function_block()
