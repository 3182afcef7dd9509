"""Messy-coded genetic algorithm over fuzzy rulebases (the chapter, 4). Imports fuzzy, never soccer."""

from ga.algorithms import evolve, random_search, resume
from ga.checkpoint import CheckpointError, load_checkpoint, save_checkpoint
from ga.codec import ChromosomeCodec
from ga.config import GAConfig
from ga.evaluation import INVALID_FITNESS, EvaluationError
from ga.genes import GeneSpace
from ga.individual import Individual
from ga.notation import NotationError, format_compact, parse_compact
from ga.result import RunResult
from ga.statistics import GenerationStats

__all__ = [
    "evolve", "random_search", "resume", "CheckpointError", "load_checkpoint", "save_checkpoint",
    "ChromosomeCodec", "GAConfig", "INVALID_FITNESS", "EvaluationError", "GeneSpace",
    "Individual", "NotationError", "format_compact", "parse_compact", "RunResult", "GenerationStats",
]
