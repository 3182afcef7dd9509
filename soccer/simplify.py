"""Simplification checked by games: the exact steps (fuzzy/simplify.py), then the rules that never
won in N games of SimpleSoccer dropped, kept only when every one of those games replays identically.

The original rulebase is played once (one batch) to count rule usage and record every decision; the
candidate is played on the same seeds and its decisions (action, parameters, and the positions they
were made from) are compared with the original's, tick for tick, bit for bit, and the games' results
too. A rule that never won (never fired while its action was performed) had no say in any decision
of those games, so the replay is expected to match; the check makes the claim about these games a
measured fact rather than an argument. It says nothing about other starts: the step is "checked on
N games", not exact.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.simplify import CHECKED, Change, Simplification, Step, simplify_exactly
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import GameResult
from soccer_lab.soccer.usage import Decisions, Usage, measure_usage

NEVER_WON = "never-won-rules"


@dataclass(frozen=True)
class CheckedSimplification:
    simplification: Simplification  # the exact steps, then the checked one
    usage: Usage | None  # the original's games; None when no games were asked for
    results: tuple[GameResult, ...]  # the simplified rulebase's games (the same seeds)


def simplify_rulebase(rulebase: Rulebase, vocabulary: Vocabulary, seeds: Sequence[int] = (),
                      config: GameConfig = GameConfig(), drop_unused_fields: bool = False) -> CheckedSimplification:
    """The exact steps; with `seeds`, also the rules that never won in those games, if the games replay."""
    exact = simplify_exactly(rulebase, vocabulary, drop_unused_fields)
    if not seeds:
        return CheckedSimplification(exact, None, ())
    usage, original = measure_usage(rulebase, seeds, config, vocabulary, record=True)
    never_won = [i for i, origin in enumerate(exact.origins) if usage.rules[origin].won == 0]
    changes = tuple(Change(exact.origins[i] + 1, format_rule(exact.rulebase.rules[i], vocabulary), None,
                           f"never won in {len(seeds)} games") for i in never_won)
    if not never_won:
        step = Step(NEVER_WON, CHECKED, f"every rule won at least once in {len(seeds)} games", (), games=len(seeds))
        return CheckedSimplification(_with(exact, step), usage, usage.results)
    keep = [i for i in range(len(exact.rulebase)) if i not in never_won]
    if not keep:
        step = Step(NEVER_WON, CHECKED, f"no rule ever fired in {len(seeds)} games (the player only hunted): a "
                    "rulebase needs at least one rule, so none is dropped", changes, applied=False, games=len(seeds))
        return CheckedSimplification(_with(exact, step), usage, usage.results)
    candidate = Rulebase(tuple(exact.rulebase.rules[i] for i in keep))
    difference, results = replay_difference(original, usage.results, candidate, seeds, config, vocabulary)
    if difference is None:
        step = Step(NEVER_WON, CHECKED, f"all {len(seeds)} games replayed identically, tick for tick", changes,
                    games=len(seeds))
        checked = replace(exact, rulebase=candidate, origins=tuple(exact.origins[i] for i in keep))
        return CheckedSimplification(_with(checked, step), usage, results)
    step = Step(NEVER_WON, CHECKED, f"{difference}: not applied", changes, applied=False, games=len(seeds))
    return CheckedSimplification(_with(exact, step), usage, usage.results)


def replay_difference(recorded: Decisions, results: tuple[GameResult, ...], candidate: Rulebase,
                      seeds: Sequence[int], config: GameConfig,
                      vocabulary: Vocabulary) -> tuple[str | None, tuple[GameResult, ...]]:
    """Play `candidate` on `seeds` and compare with the recorded games: None when every decision and
    result is the same, else where they first differ; and the candidate's results."""
    replayed, decisions = measure_usage(candidate, seeds, config, vocabulary, record=True)
    difference = recorded.first_difference(decisions)
    if difference is not None:
        game, tick = difference
        return f"game {game + 1} (seed {seeds[game]}) differed at tick {tick}", replayed.results
    if replayed.results != results:
        return "the games' results differed", replayed.results
    return None, replayed.results


def _with(simplification: Simplification, step: Step) -> Simplification:
    return replace(simplification, steps=simplification.steps + (step,))
