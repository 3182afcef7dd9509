"""Rewrite the generated blocks of the reference pages (docs/reference/cli.md, api.md, vocabulary.md) from the
code, so that they read on GitHub as on the site. tests/docs/test_reference_pages.py fails when one is behind.

    python scripts/reference_pages.py          # rewrite the pages
    python scripts/reference_pages.py --check  # exit 1, naming the pages that are behind
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"
sys.path.insert(0, str(DOCS / "hooks"))

import api_reference  # noqa: E402  (docs/hooks/, put on the path above)
import cli_reference  # noqa: E402
import vocabulary_reference  # noqa: E402
from generated_block import with_block  # noqa: E402

PAGES = {
    DOCS / "reference" / "cli.md": (cli_reference.NAME, cli_reference.cli_reference),
    DOCS / "reference" / "api.md": (api_reference.NAME, api_reference.api_reference),
    DOCS / "reference" / "vocabulary.md": (vocabulary_reference.NAME, vocabulary_reference.vocabulary_reference),
}


def refreshed(page: Path) -> str:
    """The page's text with its generated block made afresh."""
    name, generate = PAGES[page]
    return with_block(page.read_text(encoding="utf-8"), name, generate())


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true", help="only say which pages are behind (exit 1 if any)")
    args = parser.parse_args()
    behind = [page for page in PAGES if refreshed(page) != page.read_text(encoding="utf-8")]
    if args.check:
        for page in behind:
            print(f"{page.relative_to(DOCS.parent)} is behind: run python scripts/reference_pages.py")
        return 1 if behind else 0
    for page in behind:
        page.write_text(refreshed(page), encoding="utf-8")
        print(f"rewrote {page.relative_to(DOCS.parent)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
