"""Checkpoints: the full RunState as JSON (floats round-trip exactly), written atomically."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from soccer_lab.fuzzy.vocabulary import Vocabulary, VocabularyError
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.hall_of_fame import HallOfFame
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.state import ALGORITHMS, RunState
from soccer_lab.ga.statistics import GenerationStats

FORMAT = "soccer-lab-ga-checkpoint"
VERSION = 1


class CheckpointError(ValueError):
    pass


def save_checkpoint(path: str | Path, state: RunState) -> None:
    """Write to a temporary file beside `path`, then rename over it: a kill leaves the old or the new file."""
    path = Path(path)
    document = {
        "format": FORMAT,
        "version": VERSION,
        "algorithm": state.algorithm,
        "config": state.config.model_dump(),
        "vocabulary": state.vocabulary.to_dict(),
        "rng_state": state.rng_state,
        "history": [stats.to_dict() for stats in state.history],
        "best": state.best.to_dict() if state.best else None,
        "population": [individual.to_dict() for individual in state.population],
        **({"hall_of_fame": state.hall.to_dict()} if state.hall is not None else {}),
    }
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "w") as file:
            json.dump(document, file)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def load_checkpoint(path: str | Path) -> RunState:
    try:
        document = json.loads(Path(path).read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise CheckpointError(f"cannot read checkpoint {path}: {exc}") from None
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise CheckpointError(f"{path} is not a GA checkpoint")
    if document.get("version") != VERSION:
        raise CheckpointError(f"{path}: unsupported checkpoint version {document.get('version')!r}")
    try:
        return _state(document)
    except (KeyError, TypeError, ValueError, ValidationError, VocabularyError) as exc:
        raise CheckpointError(f"{path}: malformed checkpoint: {exc}") from None


def _state(document: dict[str, Any]) -> RunState:
    if document["algorithm"] not in ALGORITHMS:
        raise ValueError(f"unknown algorithm {document['algorithm']!r}")
    return RunState(
        algorithm=document["algorithm"],
        config=GAConfig(**document["config"]),
        vocabulary=Vocabulary.from_dict(document["vocabulary"]),
        population=[Individual.from_dict(i) for i in document["population"]],
        rng_state=document["rng_state"],
        history=[GenerationStats.from_dict(s) for s in document["history"]],
        best=Individual.from_dict(document["best"]) if document["best"] else None,
        hall=HallOfFame.from_dict(document["hall_of_fame"]) if document.get("hall_of_fame") else None,
    )
