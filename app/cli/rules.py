"""`soccer-lab rules ...`: check, infer, export and decode rulebases (rule text, our JSON, compact notation)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Optional

import typer

from app.cli.common import OneLineErrors, fail
from fuzzy.engine import Engine, Inference
from fuzzy.export import FORMATS, RulebaseFormatError, export_rulebase, rulebase_from_json
from fuzzy.parser import RuleSyntaxError, parse_rulebase
from fuzzy.printer import format_premise, format_rule, format_rulebase
from fuzzy.rule import Rulebase
from fuzzy.vocabulary import Vocabulary, VocabularyError

app = typer.Typer(help="Work with rulebases: check, infer, export, decode.", no_args_is_help=True)

VOCABULARY_OPTION = typer.Option(None, "--vocabulary", help="Vocabulary JSON for rule text (default: the soccer one).")


def load_rulebase(path: Path, vocabulary_path: Path | None = None) -> tuple[Rulebase, Vocabulary]:
    """Read FILE as our JSON (if it starts with '{') or as rule text; bad input ends the command."""
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        fail(f"cannot read {path}: {exc}")
    try:
        vocabulary = Vocabulary.load(vocabulary_path) if vocabulary_path else Vocabulary.default()
    except VocabularyError as exc:
        fail(str(exc))
    if text.lstrip().startswith("{"):
        try:
            return rulebase_from_json(text)
        except RulebaseFormatError as exc:
            fail(f"{path}: {exc}")
    try:
        return parse_rulebase(text, vocabulary), vocabulary
    except RuleSyntaxError as error:
        for each in error.errors:
            typer.echo(f"{path}:{each.line}:{each.column}: {each.message}", err=True)
        raise typer.Exit(2)


@app.command(cls=OneLineErrors)
def check(file: Path = typer.Argument(..., help="Rule text or rulebase JSON."),
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
    file: Path = typer.Argument(..., help="Rule text or rulebase JSON."),
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
    file: Path = typer.Argument(..., help="Rule text or rulebase JSON."),
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
    notation: str = typer.Argument(..., help='A chromosome in compact notation, e.g. "(B,N,O) (RB,n,L)".'),
) -> None:
    """Decode a chromosome in the chapter's compact notation (Figs. 6, 7) and print its rules."""
    from ga.codec import ChromosomeCodec
    from ga.notation import NotationError, parse_compact

    try:
        vocabulary = Vocabulary.default()
        rulebase = ChromosomeCodec(vocabulary).decode(parse_compact(notation, vocabulary))
    except NotationError as exc:
        fail(f"malformed chromosome notation: {exc}")
    if not len(rulebase):
        typer.echo("# no valid rule: an invalid ruleset, fitness 1.0")
    for rule in rulebase:
        typer.echo(format_rule(rule, vocabulary))
