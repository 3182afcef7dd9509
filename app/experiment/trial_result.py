"""What a finished trial hands back (its statistics and its best player's record, trials/*.best.json) and the
seeds a trial derives from its own: shared by the runner and the studies whose trials run their own way
(app/experiment/matches.py's co-evolved trials, app/experiment/transfer.py's seeded ones)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from soccer_lab.ga.config import SEED_BOUND
from soccer_lab.ga.evaluation import Evaluator


def derived_seeds(seed: int, key: int, count: int) -> list[int]:
    """`count` seeds drawn from (seed, key): apart from every seed the run itself draws."""
    state = np.random.SeedSequence(seed, spawn_key=(key,)).generate_state(count, np.uint64)
    return [int(value) % SEED_BOUND for value in state]


def crowd_file(checkpoint: Path) -> Path:
    """Where a checkpointed co-evolved trial keeps its crowd share by generation (app/experiment/matches.py)."""
    return checkpoint.with_name(checkpoint.name + ".crowd")


@dataclass(frozen=True)
class TrialResult:
    rows: list[dict[str, Any]]  # statistics per generation (restarts one after another)
    best: dict[str, Any]  # the best player, the fitness the GA saw and its replays (trials/*.best.json)


def best_record(result: Any, rows: list[dict[str, Any]], replay: Evaluator, seeds: list[int]) -> dict[str, Any]:
    """The trial's best: what the GA saw, its replays (app/runs/true_quality.py) and its rules, as a rulebase
    file every tool opens (trials/*.best.json: the rulebase JSON with the trial's figures beside it)."""
    from soccer_lab.app.rulebase_files import rulebase_json
    from soccer_lab.app.runs.true_quality import replayed_quality
    from soccer_lab.fuzzy.printer import format_rulebase

    best = result.best
    quality = replayed_quality(result.best_rulebase, replay, seeds)
    return {**json.loads(rulebase_json(result.best_rulebase, result.vocabulary)),
            "generation": next(row["generation"] for row in rows if row["best"] <= best.fitness),
            "fitness_seen": best.fitness, "evaluations_seen": best.evaluations, "replays": quality.starts,
            "replay_fitness": quality.fitness, "replay_fitness_std": quality.fitness_std,
            "replay_goals": quality.goals, "replay_scoring": quality.scoring,
            "chromosome": best.chromosome.tolist(),
            "rule_text": format_rulebase(result.best_rulebase, result.vocabulary)}
