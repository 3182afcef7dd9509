"""soccer-lab from Python: `import soccer_lab as sl` does what the `soccer-lab` command does.

Rules: `parse_rules`, `format_rules`, `load_rules`, `example`, `infer`, `export`, `rule_usage`, `simplify`.
Games: `play`. Matches: `match`. Runs: `evolve`, `random_search`, `resume`, `open_run`, `lineage`. Experiments: `open_experiment`.
The guide is docs/python-api.md; every function's docstring has an example.

>>> import soccer_lab as sl
>>> rules = sl.parse_rules("if Ball is not At then GoToBall VeryHigh")
>>> print(sl.format_rules(rules))
if Ball is not At then GoToBall VeryHigh

The names are imported from their modules on first use (PEP 562): `import soccer_lab` loads neither
numpy, numba nor pymunk; the first game played does.
"""

from __future__ import annotations

import importlib
from typing import Any

_MODULES = {
    "parse_rules": "soccer_lab.rules", "format_rules": "soccer_lab.rules", "load_rules": "soccer_lab.rules",
    "example": "soccer_lab.rules", "infer": "soccer_lab.rules", "export": "soccer_lab.rules",
    "rule_usage": "soccer_lab.rules", "simplify": "soccer_lab.rules", "EXPORT_FORMATS": "soccer_lab.rules",
    "Inference": "soccer_lab.rules", "Simplified": "soccer_lab.rules",
    "play": "soccer_lab.games", "Game": "soccer_lab.games",
    "match": "soccer_lab.matches", "Matches": "soccer_lab.matches", "Match": "soccer_lab.matches",
    "evolve": "soccer_lab.runs", "random_search": "soccer_lab.runs", "resume": "soccer_lab.runs",
    "open_run": "soccer_lab.runs",
    "lineage": "soccer_lab.runs", "RunRecord": "soccer_lab.runs", "Best": "soccer_lab.runs",
    "FamilyTree": "soccer_lab.runs",
    "open_experiment": "soccer_lab.experiments", "Experiment": "soccer_lab.experiments",
    "Finding": "soccer_lab.experiments",
}
__all__ = list(_MODULES)


def __getattr__(name: str) -> Any:
    if name not in _MODULES:
        raise AttributeError(f"module 'soccer_lab' has no attribute {name!r}")
    return getattr(importlib.import_module(_MODULES[name]), name)


def __dir__() -> list[str]:
    return sorted(__all__)
