"""A small s-expression reader for rcssserver messages.

rcssserver's messages are s-expressions with bare atoms (`f`, `r`, `-0`, `goal_l_1`), numbers and
double-quoted strings (team names), sent as one datagram ending in NUL (sometimes `\\n` NUL).
Atoms that read as numbers become int or float; quoted strings become `Quoted` (a str) so a team
called "12" stays a name; everything else stays a plain str.

Hand-written rather than the `sexpdata` library: one regular-expression pass over the tokens reads
rcssserver's messages 4-5 times faster than `sexpdata.loads` (about 45 against 200 microseconds per
message on the project's 2-core machine), and gives plain str/int/float without wrapping every atom in
a Symbol. (The messages of every cycle do not come here: soccer/rcss/messages.py reads them with
regular expressions of their own, faster still.)
"""

from __future__ import annotations

import re

from soccer_lab.soccer.rcss.errors import RcssParseError

# One token: a quoted string (its content), a parenthesis, or a bare atom; anything else is an error.
_TOKEN = re.compile(r'"((?:[^"\\]|\\.)*)"|([()])|([^\s()"]+)|(\S)')
_NUMBER_START = frozenset("+-.0123456789")


class Quoted(str):
    """A string that was double-quoted in the message."""


def _atom(text: str) -> int | float | str:
    if text[0] not in _NUMBER_START:
        return text
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
    """Parse one message into nested lists. Raises RcssParseError naming what is wrong."""
    text = clean(text)
    stack: list[list] = [[]]
    for quoted, parenthesis, bare, stray in _TOKEN.findall(text):
        if parenthesis == "(":
            stack.append([])
        elif parenthesis == ")":
            if len(stack) == 1:
                raise RcssParseError(f"unbalanced ')' in {text[:60]!r}")
            finished = stack.pop()
            stack[-1].append(finished)
        elif bare:
            stack[-1].append(_atom(bare))
        elif stray:
            raise RcssParseError(f"cannot read {stray!r} in {text[:60]!r}")
        else:
            stack[-1].append(Quoted(quoted))
    if len(stack) != 1:
        raise RcssParseError(f"unbalanced '(' in {text[:60]!r}")
    top = stack[0]
    if len(top) != 1 or not isinstance(top[0], list):
        raise RcssParseError(f"expected one parenthesised message, got {text[:60]!r}")
    return top[0]
