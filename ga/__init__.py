"""Messy-coded genetic algorithm over fuzzy rulebases (the chapter, 4). Imports fuzzy, never soccer.

The names below are imported from their modules on first use (PEP 562), so importing one light module
(`soccer_lab.ga.config` for GAConfig's defaults in a command's help) does not import the whole algorithm and numpy.
"""

from __future__ import annotations

import importlib
from typing import Any

_MODULES = {
    "evolve": "soccer_lab.ga.algorithms", "random_search": "soccer_lab.ga.algorithms", "resume": "soccer_lab.ga.algorithms",
    "CheckpointError": "soccer_lab.ga.checkpoint", "load_checkpoint": "soccer_lab.ga.checkpoint", "save_checkpoint": "soccer_lab.ga.checkpoint",
    "ChromosomeCodec": "soccer_lab.ga.codec", "GAConfig": "soccer_lab.ga.config", "INVALID_FITNESS": "soccer_lab.ga.evaluation",
    "EvaluationError": "soccer_lab.ga.evaluation", "GeneSpace": "soccer_lab.ga.genes", "Individual": "soccer_lab.ga.individual",
    "NotationError": "soccer_lab.ga.notation", "format_compact": "soccer_lab.ga.notation", "parse_compact": "soccer_lab.ga.notation",
    "RunResult": "soccer_lab.ga.result", "GenerationStats": "soccer_lab.ga.statistics",
}
__all__ = list(_MODULES)


def __getattr__(name: str) -> Any:
    if name not in _MODULES:
        raise AttributeError(f"module 'ga' has no attribute {name!r}")
    return getattr(importlib.import_module(_MODULES[name]), name)


def __dir__() -> list[str]:
    return sorted(__all__)
