"""The reference pages read on GitHub as on the site: their generated blocks are committed, and current."""

from __future__ import annotations

import importlib.util
from pathlib import Path

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
