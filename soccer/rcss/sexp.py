"""A small s-expression reader for rcssserver messages.

rcssserver's messages are s-expressions with bare atoms (`f`, `r`, `-0`, `goal_l_1`), numbers and
double-quoted strings (team names), sent as one datagram ending in NUL (sometimes `\\n` NUL).
Atoms that read as numbers become int or float; quoted strings become `Quoted` (a str) so a team
called "12" stays a name; everything else stays a plain str.
"""

from __future__ import annotations

import re

from soccer.rcss.errors import RcssParseError

Atom = "int | float | str"
_TOKEN = re.compile(r'\s*(?:(\()|(\))|"((?:[^"\\]|\\.)*)"|([^\s()"]+))')


class Quoted(str):
    """A string that was double-quoted in the message."""


def _atom(text: str) -> int | float | str:
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def clean(datagram: bytes | str) -> str:
    """The message text: decoded, without the trailing NUL and whitespace the server appends."""
    if isinstance(datagram, bytes):
        datagram = datagram.decode("ascii", errors="replace")
    return datagram.rstrip("\x00").strip()


def parse(text: bytes | str) -> list:
    """Parse one message into nested lists. Raises RcssParseError with the offending position."""
    text = clean(text)
    stack: list[list] = [[]]
    position = 0
    length = len(text)
    while position < length:
        match = _TOKEN.match(text, position)
        if match is None:
            if text[position:].strip() == "":
                break
            raise RcssParseError(f"cannot read message at column {position + 1}: {text[position:position + 30]!r}")
        position = match.end()
        opening, closing, quoted, bare = match.groups()
        if opening:
            stack.append([])
        elif closing:
            if len(stack) == 1:
                raise RcssParseError(f"unbalanced ')' at column {position} in {text[:60]!r}")
            finished = stack.pop()
            stack[-1].append(finished)
        elif quoted is not None:
            stack[-1].append(Quoted(quoted))
        elif bare is not None:
            stack[-1].append(_atom(bare))
    if len(stack) != 1:
        raise RcssParseError(f"unbalanced '(' in {text[:60]!r}")
    top = stack[0]
    if len(top) != 1 or not isinstance(top[0], list):
        raise RcssParseError(f"expected one parenthesised message, got {text[:60]!r}")
    return top[0]
