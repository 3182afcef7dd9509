"""Rulebase files: rule text (`.rules`, anything else) or our JSON (`.json`, or text starting with `{`).
Every player soccer-lab writes opens here: a run's best.rules/best.json, an experiment's
trials/*.best.json (the rulebase JSON with the trial's figures beside it; folders from before that
hold the rule text under "rules"), a library or UI export, a lineage ancestor.

Every problem becomes one `RulebaseFileError` whose message names the file and, for rule text, the
line and column, so the CLI prints it as one line.
"""

from __future__ import annotations

import json
from pathlib import Path

from soccer_lab.fuzzy.export import RulebaseFormatError, rulebase_from_json, to_json
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

JSON_SUFFIX = ".json"


class RulebaseFileError(ValueError):
    """A rulebase file that cannot be read or parsed; the message is one line."""


def load_rulebase(path: str | Path, vocabulary: Vocabulary = Vocabulary.default()) -> Rulebase:
    """The rulebase in `path`, which must hold at least one rule written in `vocabulary`
    (default: the soccer vocabulary, the one SimpleSoccer plays with)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise RulebaseFileError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise RulebaseFileError(f"{path}: is a folder, not a rulebase file") from None
    except UnicodeDecodeError:
        raise RulebaseFileError(f"{path}: not a text file (expected rule text or JSON)") from None
    except OSError as exc:
        raise RulebaseFileError(f"{path}: cannot read: {exc.strerror or exc}") from None

    if path.suffix.lower() == JSON_SUFFIX or text.lstrip().startswith("{"):
        try:
            legacy_text = legacy_trial_rules(text)
            if legacy_text is not None:
                return load_rulebase_text(path, legacy_text, vocabulary)
            rulebase, file_vocabulary = rulebase_from_json(text)
        except RulebaseFormatError as exc:
            raise RulebaseFileError(f"{path}: {exc}") from None
        if file_vocabulary != vocabulary:
            raise RulebaseFileError(
                f"{path}: its vocabulary differs from the soccer vocabulary this player is played with"
            )
    else:
        return load_rulebase_text(path, text, vocabulary)
    return _not_empty(path, rulebase)


def load_rulebase_text(path: Path, text: str, vocabulary: Vocabulary) -> Rulebase:
    try:
        rulebase = parse_rulebase(text, vocabulary)
    except RuleSyntaxError as exc:
        more = len(exc.errors) - 1
        suffix = f" (and {more} more error{'s' if more > 1 else ''})" if more else ""
        raise RulebaseFileError(f"{path}: {exc}{suffix}") from None
    return _not_empty(path, rulebase)


def _not_empty(path: Path, rulebase: Rulebase) -> Rulebase:
    if len(rulebase) == 0:
        raise RulebaseFileError(f"{path}: holds no rule")
    return rulebase


def legacy_trial_rules(text: str) -> str | None:
    """The rule text of an experiment trial's best.json written before it carried the rulebase JSON
    (no "format", the rules as text under "rules"); None for any other JSON."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError:
        return None
    if isinstance(data, dict) and "format" not in data and isinstance(data.get("rules"), str):
        return data["rules"]
    return None


def rulebase_text(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    """Rule text as written to `.rules` files (ends with a newline)."""
    return format_rulebase(rulebase, vocabulary) + "\n"


def rulebase_json(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    return to_json(rulebase, vocabulary) + "\n"
