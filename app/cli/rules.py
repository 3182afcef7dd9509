"""`soccer-lab rules ...`: check, infer, export and decode rulebases (rule text, our JSON, compact notation);
rule usage over games and simplification."""

from __future__ import annotations

import json
import math
from statistics import fmean
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import typer

from soccer_lab.app.cli.common import TYPER_SETTINGS, CommandList, OneLineErrors, fail
from soccer_lab.app.cli.play import (CountTouchesOption, FitnessOption, GoalCapOption, IdleTicksOption, MaxTicksOption,
                                     NoiseOption, SkillsOption, game_config)
from soccer_lab.app.words import plural
from soccer_lab.app.rule_inspection import DEFAULT_USAGE_GAMES
from soccer_lab.app.rulebase_files import JSON_SUFFIX, legacy_trial_rules
from soccer_lab.fuzzy.engine import Engine, Inference
from soccer_lab.fuzzy.export import FORMATS, RulebaseFormatError, export_rulebase, rulebase_from_json, to_json
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.printer import format_premise, format_rule, format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.simplify import CHECKED, EXACT
from soccer_lab.fuzzy.vocabulary import Vocabulary, VocabularyError

if TYPE_CHECKING:  # these play games (numba kernels): imported by the commands that need them
    from soccer_lab.soccer.engine import GameResult
    from soccer_lab.soccer.simplify import CheckedSimplification
    from soccer_lab.soccer.usage import Usage

app = typer.Typer(help="Work with rulebases: check, infer, export, decode, usage, simplify.", no_args_is_help=True,
                  cls=CommandList, **TYPER_SETTINGS)

VOCABULARY_OPTION = typer.Option(None, "--vocabulary", help="Vocabulary JSON for rule text (default: the soccer one).")


def load_rulebase(path: Path, vocabulary_path: Path | None = None) -> tuple[Rulebase, Vocabulary]:
    """Read FILE as our JSON (if it starts with '{') or as rule text; bad input ends the command.
    Reads every file soccer-lab writes, as app/rulebase_files.py does (other vocabularies too)."""
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        fail(f"cannot read {path}: {exc}")
    try:
        vocabulary = Vocabulary.load(vocabulary_path) if vocabulary_path else Vocabulary.default()
    except VocabularyError as exc:
        fail(str(exc))
    if text.lstrip().startswith("{"):
        legacy = legacy_trial_rules(text)  # an older experiment folder's best: its rules as text
        if legacy is None:
            try:
                return rulebase_from_json(text)
            except RulebaseFormatError as exc:
                fail(f"{path}: {exc}")
        text = legacy
    try:
        return parse_rulebase(text, vocabulary), vocabulary
    except RuleSyntaxError as error:
        for each in error.errors:
            typer.echo(f"{path}:{each.line}:{each.column}: {each.message}", err=True)
        raise typer.Exit(2)


@app.command(cls=OneLineErrors)
def check(file: Path = typer.Argument(..., metavar="FILE", help="Rule text or rulebase JSON."),
          vocabulary: Optional[Path] = VOCABULARY_OPTION) -> None:
    """Parse FILE and print its rules normalised, or every error as FILE:LINE:COL: message (exit 2)."""
    rulebase, vocab = load_rulebase(file, vocabulary)
    if len(rulebase):
        typer.echo(format_rulebase(rulebase, vocab))


def parse_inputs(pairs: list[str], vocabulary: Vocabulary) -> dict[str, float | None]:
    """`name=value` pairs -> crisp inputs; an object none of whose inputs is given is not visible."""
    values: dict[str, float | None] = {name: None for name in vocabulary.input_names}
    for pair in pairs:
        name, sep, text = pair.partition("=")
        name = name.strip()
        if not sep:
            fail(f"--input {pair!r}: expected NAME=VALUE")
        if name not in values:
            fail(f"--input {pair!r}: unknown input {name!r}; expected one of {', '.join(vocabulary.input_names)}")
        try:
            value = float(text)
        except ValueError:
            fail(f"--input {pair!r}: {text.strip()!r} is not a number")
        if not math.isfinite(value):
            fail(f"--input {pair!r}: the value must be a finite number")
        values[name] = value
    for obj, kinds in vocabulary.objects.items():
        given = [n for n in kinds.values() if values[n] is not None]
        if given and len(given) != len(kinds):
            missing = [n for n in kinds.values() if values[n] is None]
            fail(f"{vocabulary.display(obj)} is visible ({', '.join(given)} given) but {', '.join(missing)} "
                 "is missing: give all of its inputs, or none when it is not visible")
    return values


def inference_report(rulebase: Rulebase, vocabulary: Vocabulary, inputs: dict[str, float | None],
                     inference: Inference, visible: set[str]) -> dict:
    def action(a):
        return None if a is None else {"action": a.action, "support": a.support, "parameters": a.parameters}

    return {
        "inputs": {name: value for name, value in inputs.items() if value is not None},
        "visible": {obj: obj in visible for obj in vocabulary.object_names},
        "rules": [
            {
                "rule": format_rule(rule, vocabulary),
                "premises": [{"premise": format_premise(p, vocabulary), "degree": d}
                             for p, d in zip(rule.premises, degrees)],
                "strength": strength,
            }
            for rule, degrees, strength in zip(rulebase, inference.premise_degrees, inference.strengths)
        ],
        "fired": [action(a) for a in inference.fired],
        "selected": action(inference.selected),
        "hunt": inference.no_rule_fired,
    }


@app.command(cls=OneLineErrors)
def infer(
    file: Path = typer.Argument(..., metavar="FILE", help="Rule text or rulebase JSON."),
    input: list[str] = typer.Option([], "--input", "-i", help="NAME=VALUE, e.g. ball_distance=3.5 (repeatable)."),
    vocabulary: Optional[Path] = VOCABULARY_OPTION,
) -> None:
    """Evaluate FILE on crisp inputs and print every degree, strength and fired action as JSON."""
    rulebase, vocab = load_rulebase(file, vocabulary)
    inputs = parse_inputs(input, vocab)
    engine = Engine(rulebase, vocab)
    inference = engine.infer(inputs)
    report = inference_report(rulebase, vocab, inputs, inference, engine.visible_objects(inputs))
    typer.echo(json.dumps(report, indent=2))


@app.command(cls=OneLineErrors)
def export(
    file: Path = typer.Argument(..., metavar="FILE", help="Rule text or rulebase JSON."),
    format: str = typer.Option("json", "--format", "-f", help=f"One of {', '.join(FORMATS)}."),
    output: Optional[Path] = typer.Option(None, "--output", "-o", help="Write here instead of standard output."),
    vocabulary: Optional[Path] = VOCABULARY_OPTION,
) -> None:
    """Export FILE as our JSON, FCL (IEC 61131-7), fuzzylite's FLL or MATLAB's .fis."""
    if format not in FORMATS:
        fail(f"unknown format {format!r}; expected one of {', '.join(FORMATS)}")
    rulebase, vocab = load_rulebase(file, vocabulary)
    text = export_rulebase(rulebase, format, vocab)
    if output is None:
        typer.echo(text, nl=False)
        return
    try:
        output.write_text(text)
    except OSError as exc:
        fail(f"cannot write {output}: {exc}")


@app.command()
def decode(
    notation: str = typer.Argument(..., metavar="NOTATION",
                                   help='A chromosome in compact notation, e.g. "(B,N,O) (RB,n,L)".'),
) -> None:
    """Decode a chromosome in the chapter's compact notation (Figs. 6, 7) and print its rules."""
    from soccer_lab.ga.codec import ChromosomeCodec
    from soccer_lab.ga.notation import NotationError, parse_compact

    try:
        vocabulary = Vocabulary.default()
        rulebase = ChromosomeCodec(vocabulary).decode(parse_compact(notation, vocabulary))
    except NotationError as exc:
        fail(f"malformed chromosome notation: {exc}")
    if not len(rulebase):
        typer.echo("# no valid rule: an invalid ruleset, fitness 1.0")
    for rule in rulebase:
        typer.echo(format_rule(rule, vocabulary))


# ---- usage and simplify ------------------------------------------------------------------------------


@app.command(cls=OneLineErrors)
def usage(
    file: Path = typer.Argument(..., metavar="FILE", help="Rule text or rulebase JSON."),
    games: int = typer.Option(DEFAULT_USAGE_GAMES, "--games", "-n", min=1, help="Games to play."),
    seed: int = typer.Option(0, "--seed", min=0, help="Seed of the first game's start; game i uses seed + i."),
    as_json: bool = typer.Option(False, "--json", help="Print the counts as JSON."),
    fitness: FitnessOption = None,
    max_ticks: MaxTicksOption = None,
    goal_cap: GoalCapOption = None,
    idle_ticks: IdleTicksOption = None,
    noise: NoiseOption = None,
    skills: SkillsOption = None,
    count_touches: CountTouchesOption = None,
    vocabulary: Optional[Path] = VOCABULARY_OPTION,
) -> None:
    """Play FILE in SimpleSoccer and show, per rule, how often it fired, won and decided, and its mean strength;
    per action how often it was performed; and how often the player hunted."""
    from soccer_lab.app.rule_inspection import rule_usage, usage_document

    config = game_config(fitness=fitness, max_ticks=max_ticks, goal_cap=goal_cap, idle_ticks=idle_ticks, noise=noise,
                         skills=skills, count_touches=count_touches)
    rulebase, vocab = _playable(file, vocabulary)
    result = _played(lambda: rule_usage(rulebase, vocab, games, seed, config))
    if as_json:
        typer.echo(json.dumps(usage_document(result, vocab), indent=2))
        return
    for line in usage_lines(result, vocab):
        typer.echo(line)


@app.command(cls=OneLineErrors)
def simplify(
    file: Path = typer.Argument(..., metavar="FILE", help="Rule text or rulebase JSON."),
    games: int = typer.Option(0, "--games", "-n", min=0,
                              help="Also drop the rules that never won in this many games, if the games replay "
                                   "identically (0: only the exact steps)."),
    seed: int = typer.Option(0, "--seed", min=0, help="Seed of the first game's start; game i uses seed + i."),
    output: Optional[Path] = typer.Option(None, "--output", "-o",
                                          help="Write the simplified rulebase here (.json: our JSON; else rule text)."),
    drop_unused_fields: bool = typer.Option(False, "--drop-unused-fields",
                                            help="Also drop consequent fields the action does not use."),
    as_json: bool = typer.Option(False, "--json", help="Print the steps and the result as JSON."),
    fitness: FitnessOption = None,
    max_ticks: MaxTicksOption = None,
    goal_cap: GoalCapOption = None,
    idle_ticks: IdleTicksOption = None,
    noise: NoiseOption = None,
    skills: SkillsOption = None,
    count_touches: CountTouchesOption = None,
    vocabulary: Optional[Path] = VOCABULARY_OPTION,
) -> None:
    """A shorter rulebase that plays the same: exact steps (proved on every input), then, with --games, the rules
    that never won in those games (kept only when every game replays identically)."""
    from soccer_lab.app.rule_inspection import simplification, simplification_document

    config = game_config(fitness=fitness, max_ticks=max_ticks, goal_cap=goal_cap, idle_ticks=idle_ticks, noise=noise,
                         skills=skills, count_touches=count_touches)
    rulebase, vocab = _playable(file, vocabulary) if games else load_rulebase(file, vocabulary)
    result = _played(lambda: simplification(rulebase, vocab, games, seed, config, drop_unused_fields))
    simplified = result.simplification.rulebase
    if output is not None:
        _write(output, simplified, vocab)
    if as_json:
        typer.echo(json.dumps(simplification_document(result, vocab), indent=2))
        return
    for line in simplification_lines(result, vocab):
        typer.echo(line)
    if output is not None:
        typer.echo(f"simplified rulebase written to {output}")
    else:
        typer.echo("")
        typer.echo(format_rulebase(simplified, vocab) if len(simplified) else NO_RULE_LEFT)


NO_RULE_LEFT = "# no rule can ever fire: the player only hunts"


def _playable(file: Path, vocabulary: Path | None) -> tuple[Rulebase, Vocabulary]:
    rulebase, vocab = load_rulebase(file, vocabulary)
    if not len(rulebase):
        fail(f"{file}: holds no rule")
    return rulebase, vocab


def _played(play):
    """Run the games; a vocabulary SimpleSoccer cannot play ends the command with one line."""
    try:
        return play()
    except VocabularyError as exc:
        fail(f"cannot play this rulebase in SimpleSoccer: {exc}")


def _write(path: Path, rulebase: Rulebase, vocabulary: Vocabulary) -> None:
    if path.is_dir():
        fail(f"--output: {path} is a folder")
    if path.suffix.lower() == JSON_SUFFIX:
        text = to_json(rulebase, vocabulary) + "\n"
    else:
        text = (format_rulebase(rulebase, vocabulary) if len(rulebase) else NO_RULE_LEFT) + "\n"
    try:
        path.write_text(text)
    except OSError as exc:
        fail(f"cannot write {path}: {exc.strerror or exc}")


def usage_lines(usage: Usage, vocabulary: Vocabulary) -> list[str]:
    seeds = usage.seeds
    lines = [f"rule usage over {plural(len(seeds), 'game')} (seeds {seeds[0]}-{seeds[-1]}), "
             f"{plural(usage.ticks, 'tick')}; the player hunted (no rule fired) {_percent(usage.hunt_share)} of them",
             f"{'rule':>4} {'fired':>7} {'won':>7} {'decided':>7} {'strength':>8}  text"]
    ticks = usage.ticks or 1
    for i, (rule, u) in enumerate(zip(usage.rulebase, usage.rules)):
        strength = "-" if u.mean_strength is None else f"{u.mean_strength:.2f}"
        lines.append(f"{i + 1:>4} {_percent(u.fired / ticks):>7} {_percent(u.won / ticks):>7} "
                     f"{_percent(u.decided / ticks):>7} {strength:>8}  {format_rule(rule, vocabulary)}")
    performed = [(a, n) for a, n in usage.actions.items() if n]
    lines.append("actions performed: " + (", ".join(f"{vocabulary.display(a)} {_percent(n / ticks)}"
                                                     for a, n in performed) or "none") + f", hunt {_percent(usage.hunt_share)}")
    lines.append(_results_line(usage.results))
    lines.append("fired: ticks its strength was above 0; won: ticks it fired and its action was performed; decided: "
                 "ticks it was that action's strongest rule; strength: its mean when it fired")
    return lines


def simplification_lines(result: CheckedSimplification, vocabulary: Vocabulary) -> list[str]:
    simplified = result.simplification
    lines = []
    for kind, title in ((EXACT, "exact steps (each provably changes no decision, on any input):"),
                        (CHECKED, "checked steps (kept only when every game replays identically):")):
        steps = [s for s in simplified.steps if s.kind == kind]
        if not steps:
            continue
        lines.append(title)
        for step in steps:
            lines.append(f"  {step.name:<20} {_step_outcome(step)}")
            lines.extend(f"      rule {c.rule}: {c.reason}" for c in step.changes)
    from soccer_lab.app.rule_inspection import size

    before, after = size(simplified.original), size(simplified.rulebase)
    lines.append(f"size: {before['rules']} rules, {before['premises']} premises -> "
                 f"{after['rules']} rules, {after['premises']} premises")
    if result.usage is not None:
        lines.append(f"before: {_results_line(result.usage.results)}")
        lines.append(f"after:  {_results_line(result.results)}")
    return lines


def _step_outcome(step) -> str:
    count = len(step.changes)
    if not count:
        return "nothing to do" if step.kind == EXACT else step.summary
    what = f"{count} change{'s' if count > 1 else ''}"
    if step.kind == CHECKED:
        return f"{what}, checked on {step.games} games: {step.summary}"
    if not step.applied:
        return f"{what} listed, not applied (--drop-unused-fields applies them)"
    return what


def _results_line(results: tuple[GameResult, ...]) -> str:
    if not results:
        return "no games"
    return (f"{plural(len(results), 'game')}: mean goals {fmean(r.goals for r in results):.2f}, "
            f"mean fitness {fmean(r.fitness for r in results):.4f}")


def _percent(share: float) -> str:
    return f"{100 * share:.1f}%"
