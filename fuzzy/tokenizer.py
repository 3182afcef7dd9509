"""A hand-written tokenizer for rule text (docs/reference/rules.md): words, parentheses, brackets, commas.

Each token keeps its 1-based line and column so the parser can say exactly where it stopped.
`#` starts a comment that runs to the end of the line; every line ends with an END token.
"""

from __future__ import annotations

from dataclasses import dataclass

WORD, LPAREN, RPAREN, LBRACKET, RBRACKET, COMMA, END, UNKNOWN = (
    "word", "(", ")", "[", "]", ",", "end of line", "unknown",
)
COMMENT = "#"
PUNCTUATION = {"(": LPAREN, ")": RPAREN, "[": LBRACKET, "]": RBRACKET, ",": COMMA}


@dataclass(frozen=True)
class Token:
    kind: str
    text: str
    line: int
    column: int

    def describe(self) -> str:
        """How an error message names this token: 'Nearr', '(' or 'end of line'."""
        return END if self.kind == END else f"'{self.text}'"


def _is_word_char(char: str) -> bool:
    return char.isalnum() or char == "_"


def tokenize_line(text: str, line: int) -> list[Token]:
    """The tokens of one line, ending with an END token (which sits where the comment or line ends)."""
    tokens: list[Token] = []
    i = 0
    while i < len(text):
        char = text[i]
        if char == COMMENT:
            break
        if char.isspace():
            i += 1
        elif char in PUNCTUATION:
            tokens.append(Token(PUNCTUATION[char], char, line, i + 1))
            i += 1
        elif _is_word_char(char):
            start = i
            while i < len(text) and _is_word_char(text[i]):
                i += 1
            tokens.append(Token(WORD, text[start:i], line, start + 1))
        else:
            tokens.append(Token(UNKNOWN, char, line, i + 1))
            i += 1
    tokens.append(Token(END, "", line, i + 1))
    return tokens


def tokenize(text: str) -> list[list[Token]]:
    """One token list per line of `text` (blank and comment-only lines give just an END token)."""
    return [tokenize_line(line, number) for number, line in enumerate(text.splitlines(), start=1)]
