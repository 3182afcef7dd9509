"""Our own JSON for a rulebase and its vocabulary: versioned, lossless, with a checking loader.

    {"format": "soccer-lab-rulebase", "version": 1, "vocabulary": {...},
     "rules": [{"premises": [{"object": "BALL", "term": "NEAR", "negated": false}, ...],
                "connectors": ["OR", ...],
                "consequent": {"action": "TURN", "direction": "LEFT", "power": null}}, ...]}
"""

from __future__ import annotations

import json
from typing import Any

from soccer_lab.fuzzy.rule import CONNECTORS, Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary, VocabularyError

FORMAT = "soccer-lab-rulebase"
VERSION = 1
PREMISE_KEYS = ("object", "term", "negated")
RULE_KEYS = ("premises", "connectors", "consequent")


class RulebaseFormatError(ValueError):
    """Malformed rulebase JSON; the message names where (e.g. `rules[2].premises[0].term`)."""


def rulebase_to_dict(rulebase: Rulebase, vocabulary: Vocabulary) -> dict[str, Any]:
    return {
        "format": FORMAT,
        "version": VERSION,
        "vocabulary": vocabulary.to_dict(),
        "rules": [
            {
                "premises": [{"object": p.object, "term": p.term, "negated": p.negated} for p in rule.premises],
                "connectors": list(rule.connectors),
                "consequent": {"action": rule.consequent.action}
                | {output: getattr(rule.consequent, output) for output in vocabulary.output_names},
            }
            for rule in rulebase
        ],
    }


def to_json(rulebase: Rulebase, vocabulary: Vocabulary) -> str:
    return json.dumps(rulebase_to_dict(rulebase, vocabulary), indent=2)


def rulebase_from_json(text: str) -> tuple[Rulebase, Vocabulary]:
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise RulebaseFormatError(f"not valid JSON: {exc}") from exc
    return rulebase_from_dict(data)


def rulebase_from_dict(data: Any) -> tuple[Rulebase, Vocabulary]:
    _require(isinstance(data, dict), "top level", "an object")
    _require(data.get("format") == FORMAT, "format", f"'{FORMAT}'", data.get("format"))
    _require(data.get("version") == VERSION, "version", f"{VERSION} (the version this soccer-lab reads)",
             data.get("version"))
    try:
        vocabulary = Vocabulary.from_dict(data["vocabulary"]) if "vocabulary" in data else Vocabulary.default()
    except (VocabularyError, AttributeError) as exc:
        raise RulebaseFormatError(f"vocabulary: {exc}") from exc
    rules = data.get("rules")
    _require(isinstance(rules, list), "rules", "a list of rules", rules)
    return Rulebase(tuple(_rule(r, f"rules[{i}]", vocabulary) for i, r in enumerate(rules))), vocabulary


def _require(condition: bool, where: str, expected: str, found: Any = ...) -> None:
    if not condition:
        suffix = "" if found is ... else f", found {json.dumps(found)}"
        raise RulebaseFormatError(f"{where}: expected {expected}{suffix}")


def _keys(data: Any, where: str, keys: tuple[str, ...]) -> None:
    _require(isinstance(data, dict), where, "an object", data)
    unknown = sorted(set(data) - set(keys))
    _require(not unknown, where, f"only the keys {', '.join(keys)}", unknown)
    missing = [k for k in keys if k not in data]
    _require(not missing, where, f"the keys {', '.join(keys)}; missing {', '.join(missing)}")


def _rule(data: Any, where: str, vocabulary: Vocabulary) -> Rule:
    _keys(data, where, RULE_KEYS)
    premises = data["premises"]
    _require(isinstance(premises, list) and len(premises) > 0, f"{where}.premises", "a non-empty list", premises)
    parsed = tuple(_premise(p, f"{where}.premises[{i}]", vocabulary) for i, p in enumerate(premises))
    connectors = data["connectors"]
    _require(
        isinstance(connectors, list) and len(connectors) == len(parsed) - 1,
        f"{where}.connectors", f"a list of {len(parsed) - 1} connectors (one between each two premises)", connectors,
    )
    for i, connector in enumerate(connectors):
        _require(connector in CONNECTORS, f"{where}.connectors[{i}]", " or ".join(CONNECTORS), connector)
    return Rule(parsed, tuple(connectors), _consequent(data["consequent"], f"{where}.consequent", vocabulary))


def _premise(data: Any, where: str, vocabulary: Vocabulary) -> Premise:
    _keys(data, where, PREMISE_KEYS)
    _require(data["object"] in vocabulary.object_names, f"{where}.object",
             f"one of {', '.join(vocabulary.object_names)}", data["object"])
    _require(data["term"] in vocabulary.premise_terms, f"{where}.term",
             f"one of {', '.join(vocabulary.premise_terms)}", data["term"])
    _require(isinstance(data["negated"], bool), f"{where}.negated", "true or false", data["negated"])
    return Premise(data["object"], data["term"], data["negated"])


def _consequent(data: Any, where: str, vocabulary: Vocabulary) -> Consequent:
    _keys(data, where, ("action",) + vocabulary.output_names)
    _require(data["action"] in vocabulary.action_names, f"{where}.action",
             f"one of {', '.join(vocabulary.action_names)}", data["action"])
    for output in vocabulary.output_names:
        terms = vocabulary.output_variable(output).term_names
        _require(data[output] is None or data[output] in terms, f"{where}.{output}",
                 f"null or one of {', '.join(terms)}", data[output])
    return Consequent(data["action"], **{output: data[output] for output in vocabulary.output_names})
