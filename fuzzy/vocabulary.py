"""The vocabulary a rulebase is written in: variables and terms, objects, inputs, actions.

The soccer vocabulary lives in one data file, `fuzzy/data/soccer_vocabulary.json`, together with
the abbreviations of the chapter's compact chromosome notation; the edges (the CLI, the app, the
soccer package's entry points) load it with `Vocabulary.default()` and pass it down explicitly.
Everything else (parser, printer, engines, GA genes, compiled arrays, the skills' action table)
takes the vocabulary as an argument and derives its indices from it by name, never from literals.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

from soccer_lab.fuzzy.rule import CONNECTORS, PARAMETERS
from soccer_lab.fuzzy.term import Term
from soccer_lab.fuzzy.variable import LinguisticVariable

DEFAULT_VOCABULARY_FILE = Path(__file__).parent / "data" / "soccer_vocabulary.json"
OPPONENT_VOCABULARY_FILE = Path(__file__).parent / "data" / "opponent_vocabulary.json"
FORMAT = "soccer-lab-vocabulary"


class VocabularyError(ValueError):
    pass


@dataclass(frozen=True)
class Vocabulary:
    variables: dict[str, LinguisticVariable]  # "distance", "direction", "power"
    objects: dict[str, dict[str, str]]  # BALL -> {"distance": "ball_distance", "direction": ...}
    inputs: dict[str, str]  # input name -> variable name, in input-index order
    outputs: dict[str, tuple[str, float]]  # output name -> (variable name, default value)
    actions: dict[str, tuple[str, ...]]  # action -> the outputs it uses, in action-index order
    display_names: dict[str, str]
    # name (object, connector, term, action) -> its compact-notation abbreviation. How chromosomes are
    # written, not what rules mean: two vocabularies differing only here compare equal.
    abbreviations: dict[str, str] = field(default_factory=dict, compare=False)

    # ---- construction -------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "Vocabulary":
        try:
            variables = {
                name: LinguisticVariable(
                    name=name,
                    minimum=float(spec["universe"][0]),
                    maximum=float(spec["universe"][1]),
                    unit=spec.get("unit", ""),
                    terms=tuple(Term(t.upper(), *map(float, p)) for t, p in spec["terms"].items()),
                )
                for name, spec in data["variables"].items()
            }
            objects = {o.upper(): dict(v) for o, v in data["objects"].items()}
            inputs = dict(data["inputs"])
            outputs = {o: (s["variable"], float(s["default"])) for o, s in data["outputs"].items()}
            actions = {a.upper(): tuple(uses) for a, uses in data["actions"].items()}
            display = {k.upper(): v for k, v in data.get("display_names", {}).items()}
            abbreviations = {k.upper(): str(v) for k, v in data.get("abbreviations", {}).items()}
        except (KeyError, TypeError, IndexError, ValueError, AttributeError) as exc:
            raise VocabularyError(f"malformed vocabulary: {exc}") from exc
        vocabulary = cls(variables, objects, inputs, outputs, actions, display, abbreviations)
        vocabulary._validate()
        return vocabulary

    @classmethod
    def load(cls, path: str | Path) -> "Vocabulary":
        try:
            data = json.loads(Path(path).read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise VocabularyError(f"cannot read vocabulary {path}: {exc}") from exc
        return cls.from_dict(data)

    @staticmethod
    @cache
    def default() -> "Vocabulary":
        return Vocabulary.load(DEFAULT_VOCABULARY_FILE)

    @staticmethod
    @cache
    def with_opponent() -> "Vocabulary":
        """The default vocabulary with a third object, the opponent (OPPONENT_VOCABULARY_FILE: matches only)."""
        return Vocabulary.default().extended(OPPONENT_VOCABULARY_FILE)

    def extended(self, path: str | Path) -> "Vocabulary":
        """This vocabulary with the objects, inputs, display names and abbreviations an extension file adds
        (its terms, actions and outputs stay this vocabulary's, so they are tuned in one place)."""
        try:
            extension = json.loads(Path(path).read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise VocabularyError(f"cannot read vocabulary extension {path}: {exc}") from exc
        data = self.to_dict()
        for key in ("objects", "inputs", "display_names", "abbreviations"):
            added = extension.get(key, {})
            if not isinstance(added, dict):
                raise VocabularyError(f"malformed vocabulary extension {path}: {key} is not a mapping")
            data[key] = {**data[key], **added}
        return Vocabulary.from_dict(data)

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "version": 1,
            "variables": {
                name: {
                    "universe": [v.minimum, v.maximum],
                    "unit": v.unit,
                    "terms": {t.name: list(t.parameters) for t in v.terms},
                }
                for name, v in self.variables.items()
            },
            "objects": {obj: dict(kinds) for obj, kinds in self.objects.items()},
            "inputs": dict(self.inputs),
            "outputs": {o: {"variable": v, "default": d} for o, (v, d) in self.outputs.items()},
            "actions": {a: list(u) for a, u in self.actions.items()},
            "display_names": dict(self.display_names),
            "abbreviations": dict(self.abbreviations),
        }

    def _validate(self) -> None:
        for obj, kinds in self.objects.items():
            for kind, input_name in kinds.items():
                if kind not in self.variables or self.inputs.get(input_name) != kind:
                    raise VocabularyError(f"object {obj}: input {input_name} is not a {kind} input")
        if set(self.outputs) != set(PARAMETERS):
            raise VocabularyError(f"the outputs must be {' and '.join(PARAMETERS)} (a consequent's parameters), "
                                  f"found {', '.join(self.outputs) or 'none'}")
        for out, (var, _) in self.outputs.items():
            if var not in self.variables:
                raise VocabularyError(f"output {out}: unknown variable {var}")
        for action, uses in self.actions.items():
            for out in uses:
                if out not in self.outputs:
                    raise VocabularyError(f"action {action}: unknown output {out}")
        names = [t for kind in self.premise_variables for t in self.variables[kind].term_names]
        if len(set(names)) != len(names):
            raise VocabularyError("premise term names must be unique across variables")
        named = {*self.objects, *CONNECTORS, *self.actions, *(t for v in self.variables.values() for t in v.term_names)}
        unknown = [name for name in self.abbreviations if name not in named]
        if unknown:
            raise VocabularyError(f"abbreviations of unknown names: {', '.join(unknown)}")

    # ---- derived views ------------------------------------------------------------------
    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(self.objects)

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(self.inputs)

    @property
    def action_names(self) -> tuple[str, ...]:
        return tuple(self.actions)

    @property
    def output_names(self) -> tuple[str, ...]:
        return tuple(self.outputs)

    @property
    def premise_variables(self) -> tuple[str, ...]:
        """The variables premises are written over (distance, direction), in object-key order."""
        first = next(iter(self.objects.values()))
        return tuple(first)

    @property
    def premise_terms(self) -> tuple[str, ...]:
        return tuple(t for kind in self.premise_variables for t in self.variables[kind].term_names)

    def premise_variable(self, term: str) -> str:
        """Which variable (distance or direction) a premise term belongs to."""
        for kind in self.premise_variables:
            if term in self.variables[kind].term_names:
                return kind
        raise KeyError(f"{term} is not a premise term")

    def premise_input(self, obj: str, term: str) -> str:
        return self.objects[obj][self.premise_variable(term)]

    def output_variable(self, output: str) -> LinguisticVariable:
        return self.variables[self.outputs[output][0]]

    def output_default(self, output: str) -> float:
        return self.outputs[output][1]

    def display(self, name: str) -> str:
        return self.display_names.get(name, name.capitalize())

    def canonical(self, word: str) -> str:
        """UPPER-case key for a word written in any case (`SlightlyNear` -> `SLIGHTLYNEAR`)."""
        return word.upper()
