"""Rule usage and simplification for the CLI, the API and the UI: one place that plays the games
(SimpleSoccer, game i from seed + i) and turns the results into plain documents (`--json` and the
API's bodies)."""

from __future__ import annotations

from statistics import fmean
from typing import TYPE_CHECKING, Any

from soccer_lab.fuzzy.printer import format_rule, format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.simplify import premise_count
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig

if TYPE_CHECKING:  # these compile the game kernels: imported when games are played
    from soccer_lab.soccer.engine import GameResult
    from soccer_lab.soccer.simplify import CheckedSimplification
    from soccer_lab.soccer.usage import Usage

DEFAULT_USAGE_GAMES = 100
# The API's and UI's limits: a request plays its games while the client waits (docs/reference/limits.md)
MAX_GAMES = 1000
MAX_RULES = 1000  # rules in a rulebase to play or simplify (an evolved one has at most max_length / 2)
# A request's work: (weight + TICK_COST_RULES) x games x (max_ticks + GAME_COST_TICKS) x plays. A game tick
# costs the world's part (physics, observation, skills) and each rule's inference; the world's part is worth
# TICK_COST_RULES rules. A rule's inference grows with its premises: the rules' weight counts every
# PREMISES_PER_RULE premises past a rule's first as one rule more (a hundred rules of forty premises are no
# lighter than a thousand short ones). A game costs some more to set up (its world, its engine with the
# rules): worth GAME_COST_TICKS ticks (measured 40 to 150 as the load varied, the largest taken: the setup-heavy
# requests were the slowest at the limit), so a thousand one-tick games are not counted as nearly free.
# Simplification plays its games twice (the original recorded, then the candidate compared tick for tick).
# All measured by benchmarks/request_cost.py: MAX_WORK is about 1.5 s here, under 5 s on a slower
# machine, and it bounds the rows simplification keeps (one per game tick of each play).
TICK_COST_RULES = 60
PREMISES_PER_RULE = 5
GAME_COST_TICKS = 150
MAX_WORK = 50_000_000
USAGE_PLAYS, SIMPLIFY_PLAYS = 1, 2


def rules_weight(rules: int, premises: int = 0) -> int:
    """`rules` rules of `premises` premises in all, in rules of one premise."""
    return rules + max(0, premises - rules) // PREMISES_PER_RULE


def request_work(rules: int, games: int, max_ticks: int, plays: int, premises: int = 0) -> int:
    return (rules_weight(rules, premises) + TICK_COST_RULES) * games * (max_ticks + GAME_COST_TICKS) * plays


def affordable_games(rules: int, max_ticks: int, plays: int, premises: int = 0) -> int:
    """The most games of `max_ticks` a request with `rules` rules (`premises` in all) may play (`plays` times
    each)."""
    return min(MAX_GAMES, MAX_WORK // request_work(rules, 1, max_ticks, plays, premises))


def checked_cost(rulebase: Rulebase, games: int, max_ticks: int, plays: int = USAGE_PLAYS) -> None:
    """ValueError naming the limit when playing `games` games of `max_ticks` with `rulebase` costs too much (its
    rules and their premises counted: docs/reference/limits.md)."""
    rules, premises = len(rulebase), premise_count(rulebase)
    if rules > MAX_RULES:
        raise ValueError(f"the rulebase has {rules:,} rules; at most {MAX_RULES:,} are played or simplified")
    if request_work(rules, games, max_ticks, plays, premises) > MAX_WORK:
        most = affordable_games(rules, max_ticks, plays, premises)
        doing = "simplified on" if plays == SIMPLIFY_PLAYS else "played"
        allowed = f"at most {most:,} such games can be {doing}" if most else "not one such game fits: fewer ticks"
        raise ValueError(f"{games:,} games of {max_ticks:,} ticks with {rules:,} rules ({premises:,} premises) are "
                         f"more than a request plays while you wait (docs/reference/limits.md): {allowed}")


def seeds_from(seed: int, games: int) -> list[int]:
    """Game i (from 0) starts from seed + i, as `soccer-lab play` numbers them."""
    return [seed + i for i in range(games)]


def rule_usage(rulebase: Rulebase, vocabulary: Vocabulary, games: int, seed: int, config: GameConfig) -> Usage:
    from soccer_lab.soccer.usage import measure_usage

    return measure_usage(rulebase, seeds_from(seed, games), config, vocabulary)[0]


def simplification(rulebase: Rulebase, vocabulary: Vocabulary, games: int, seed: int, config: GameConfig,
                   drop_unused_fields: bool = False) -> CheckedSimplification:
    from soccer_lab.soccer.simplify import simplify_rulebase

    return simplify_rulebase(rulebase, vocabulary, seeds_from(seed, games), config, drop_unused_fields)


# ---- documents ------------------------------------------------------------------------------------


def usage_document(usage: Usage, vocabulary: Vocabulary) -> dict[str, Any]:
    ticks = usage.ticks or 1
    return {
        "games": len(usage.seeds),
        "seeds": list(usage.seeds),
        "ticks": usage.ticks,
        "rules": [
            {"rule": i + 1, "text": format_rule(rule, vocabulary), "action": rule.consequent.action,
             "fired": u.fired, "won": u.won, "decided": u.decided, "mean_strength": u.mean_strength,
             "fired_share": u.fired / ticks, "won_share": u.won / ticks}
            for i, (rule, u) in enumerate(zip(usage.rulebase, usage.rules))
        ],
        "actions": [{"action": a, "performed": n, "share": n / ticks} for a, n in usage.actions.items()],
        "hunt": usage.hunt,
        "hunt_share": usage.hunt_share,
        "results": results_document(usage.results, usage.seeds),
    }


def results_document(results: tuple[GameResult, ...], seeds: tuple[int, ...]) -> dict[str, Any]:
    return {
        "mean_goals": fmean(r.goals for r in results) if results else None,
        "mean_fitness": fmean(r.fitness for r in results) if results else None,
        "games": [{"seed": s, "goals": r.goals, "kicks": r.kicks, "ticks": r.ticks, "fitness": r.fitness}
                  for s, r in zip(seeds, results)],
    }


def simplification_document(result: CheckedSimplification, vocabulary: Vocabulary) -> dict[str, Any]:
    simplified = result.simplification
    document: dict[str, Any] = {
        "text": format_rulebase(simplified.rulebase, vocabulary),
        "origins": [i + 1 for i in simplified.origins],
        "before": size(simplified.original),
        "after": size(simplified.rulebase),
        "steps": [
            {"name": s.name, "kind": s.kind, "applied": s.applied, "summary": s.summary, "games": s.games,
             "changes": [vars(c) for c in s.changes]}
            for s in simplified.steps
        ],
        "games": len(result.usage.seeds) if result.usage else 0,
    }
    if result.usage is not None:
        document["results"] = {"before": results_document(result.usage.results, result.usage.seeds),
                               "after": results_document(result.results, result.usage.seeds)}
    return document


def size(rulebase: Rulebase) -> dict[str, int]:
    return {"rules": len(rulebase), "premises": premise_count(rulebase)}
