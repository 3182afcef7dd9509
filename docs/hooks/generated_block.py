"""What the reference hooks share: a page's generated block, kept in the page itself.

A block runs from `<!-- generated: NAME -->` to `<!-- end of generated: NAME -->`. Its text is committed, so
the page reads on GitHub as on the site; the hook writes the block afresh when the site is built, and
`scripts/reference_pages` rewrites the committed text (tests/docs/test_reference_pages.py fails when it is
behind). Not a hook itself; mkdocs puts a hook's folder on sys.path while loading it."""

from __future__ import annotations

import re


def start(name: str) -> str:
    return f"<!-- generated: {name} -->"


def end(name: str) -> str:
    return f"<!-- end of generated: {name} -->"


def has_block(markdown: str, name: str) -> bool:
    return start(name) in markdown


def with_block(markdown: str, name: str, content: str) -> str:
    """`markdown` with its block NAME holding `content` (a page holding only the start marker gets the end too)."""
    block = f"{start(name)}\n\n{content.strip()}\n\n{end(name)}"
    pattern = re.compile(re.escape(start(name)) + r"(?:.*?" + re.escape(end(name)) + r")?", re.S)
    return pattern.sub(lambda _: block, markdown, count=1)
