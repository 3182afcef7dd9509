"""The reference pages read on GitHub as on the site: their generated blocks are committed, and current."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def load_script():
    spec = importlib.util.spec_from_file_location("reference_pages", ROOT / "scripts" / "reference_pages.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_reference_pages_hold_their_generated_text_as_committed():
    script = load_script()
    for page in script.PAGES:
        assert script.refreshed(page) == page.read_text(encoding="utf-8"), (
            f"{page.relative_to(ROOT)} is behind the code: run python scripts/reference_pages.py")


def test_vocabulary_page_shows_its_term_tables_without_a_site_build():
    text = (ROOT / "docs" / "reference" / "vocabulary.md").read_text(encoding="utf-8")
    assert "| SlightlyNear | 4 | 8 | 8 | 15 |" in text
    assert "| Straight | -15 | 0 | 0 | 15 |" in text


def github_anchors(text: str) -> set[str]:
    """The ids GitHub gives a page: its `<a id>` anchors and each heading's slug (lower case, punctuation
    dropped but for hyphens and underscores, spaces as hyphens)."""
    ids = set(re.findall(r'<a id="([^"]+)"></a>', text))
    for heading in re.findall(r"^#+ (.+)$", text, re.MULTILINE):
        ids.add(re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-"))
    return ids


@pytest.mark.parametrize("page", ["api.md", "cli.md", "vocabulary.md", "limits.md", "rules.md"])
def test_reference_page_holds_no_site_only_syntax_and_its_links_land_on_github(page):
    """attr_list's `{#id}` after a heading showed on GitHub as text, and the API page's 61 links to its schemas
    went nowhere there: GitHub gives the heading an id of its own."""
    text = (ROOT / "docs" / "reference" / page).read_text(encoding="utf-8")
    assert not re.search(r"\{[:#.]", text.replace("{{", "")), "attr_list syntax GitHub shows as text"
    missing = sorted(set(re.findall(r"\]\(#([^)]+)\)", text)) - github_anchors(text))
    assert not missing, missing
