"""Messy-coded genetic algorithm over fuzzy rulebases (the chapter, 4). Imports fuzzy, never soccer.

The names below are imported from their modules on first use (PEP 562), so importing one light module
(`ga.config` for GAConfig's defaults in a command's help) does not import the whole algorithm and numpy.
"""

from __future__ import annotations

import importlib
from typing import Any

_MODULES = {
    "evolve": "ga.algorithms", "random_search": "ga.algorithms", "resume": "ga.algorithms",
    "CheckpointError": "ga.checkpoint", "load_checkpoint": "ga.checkpoint", "save_checkpoint": "ga.checkpoint",
    "ChromosomeCodec": "ga.codec", "GAConfig": "ga.config", "INVALID_FITNESS": "ga.evaluation",
    "EvaluationError": "ga.evaluation", "GeneSpace": "ga.genes", "Individual": "ga.individual",
    "NotationError": "ga.notation", "format_compact": "ga.notation", "parse_compact": "ga.notation",
    "RunResult": "ga.result", "GenerationStats": "ga.statistics",
}
__all__ = list(_MODULES)


def __getattr__(name: str) -> Any:
    if name not in _MODULES:
        raise AttributeError(f"module 'ga' has no attribute {name!r}")
    return getattr(importlib.import_module(_MODULES[name]), name)


def __dir__() -> list[str]:
    return sorted(__all__)
