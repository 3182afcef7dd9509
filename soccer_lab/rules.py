"""Rulebases from Python: read, print, infer, export, and (playing games) rule usage and simplification,
as `soccer-lab rules ...` does. Rules are written in the soccer vocabulary unless a `vocabulary` is given."""

from __future__ import annotations

import math
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Union

from soccer_lab.app.rule_inspection import DEFAULT_USAGE_GAMES
from soccer_lab.fuzzy.export import FORMATS, export_rulebase
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

if TYPE_CHECKING:  # these play games (numba kernels): imported by the functions that play
    from soccer_lab.soccer.engine import GameResult
    from soccer_lab.soccer.usage import Usage

EXPORT_FORMATS = FORMATS  # "json", "fcl", "fll", "fis"
Rules = Union[Rulebase, str, PathLike]  # a rulebase, or the path of a .rules or .json file


def _vocabulary(vocabulary: Vocabulary | None) -> Vocabulary:
    return Vocabulary.default() if vocabulary is None else vocabulary


def parse_rules(text: str, vocabulary: Vocabulary | None = None) -> Rulebase:
    """The rulebase written in `text` (one rule a line; `#` starts a comment). A syntax error raises
    soccer_lab.fuzzy.parser.RuleSyntaxError (a ValueError) whose `.errors` give each line and column.

    >>> rules = parse_rules('''
    ... if Ball is At and Goal is not At then KickTowardGoal High
    ... if Ball is not At then GoToBall VeryHigh
    ... ''')
    >>> len(rules)
    2
    >>> parse_rules("if Ball is Near then Jump")
    Traceback (most recent call last):
    ...
    soccer_lab.fuzzy.parser.RuleSyntaxError: line 1, column 22: expected an action (Turn, ...), found 'Jump'
    """
    return parse_rulebase(text, _vocabulary(vocabulary))


def format_rules(rules: Rulebase, vocabulary: Vocabulary | None = None) -> str:
    """The rules as text, one a line, normalised as `soccer-lab rules check` prints them.

    >>> print(format_rules(parse_rules("IF ball IS near THEN gotoball high")))
    if Ball is Near then GoToBall High
    """
    return format_rulebase(rules, _vocabulary(vocabulary))


def load_rules(path: str | PathLike, vocabulary: Vocabulary | None = None) -> Rulebase:
    """The rulebase in a file: rule text (.rules) or our JSON (.json, what `export(rules, "json")` writes,
    a run folder's best.json). soccer_lab.app.rulebase_files.RulebaseFileError (a ValueError, one line naming the
    file) when it cannot be read, does not parse, or holds no rule.

    >>> len(load_rules("soccer/data/examples/striker.rules")) > 0
    True
    """
    from soccer_lab.app.rulebase_files import load_rulebase

    return load_rulebase(Path(path), _vocabulary(vocabulary))


def example(name: str = "demo") -> Rulebase:
    """A built-in example player: "demo", "striker", "dribbler" or "hunter" (the app's examples).

    >>> print(format_rules(example("demo")))
    if Ball is At and Goal is not At then KickTowardGoal High
    if Ball is At then Dribble VeryLeft Low
    if Ball is not At or Ball is not Near then GoToBall VeryHigh
    """
    from soccer_lab.soccer.examples import example as built_in

    return built_in(name).rulebase(Vocabulary.default())


def rulebase_of(rules: Rules, vocabulary: Vocabulary | None = None) -> Rulebase:
    """`rules` itself, or the rulebase in the file it names."""
    if isinstance(rules, Rulebase):
        return rules
    if isinstance(rules, (str, PathLike)):
        return load_rules(rules, vocabulary)
    raise TypeError(f"expected a Rulebase or the path of a rulebase file, not {type(rules).__name__}")


# ---- inference --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Inference:
    """One decision on crisp inputs. `action` is the skill performed (None: no rule fired, the player hunts),
    `parameters` its values; `strengths` each rule's firing strength, in rule order; `report` the whole
    document `soccer-lab rules infer` prints (every premise's degree, every fired action)."""

    action: str | None
    parameters: dict[str, float]
    strengths: list[float]
    visible: dict[str, bool]
    report: dict[str, Any]

    @property
    def hunt(self) -> bool:
        return self.action is None


def infer(rules: Rules, vocabulary: Vocabulary | None = None, **inputs: float) -> Inference:
    """Evaluate the rules on crisp inputs given by name (`ball_distance=3.5, ball_direction=0`). An object
    none of whose inputs is given is not visible; give all of an object's inputs or none. ValueError for an
    unknown input, a value that is not a finite number, or an object given in part.

    >>> rules = parse_rules('''
    ... if Ball is At then KickTowardGoal High
    ... if Ball is not At then GoToBall VeryHigh
    ... ''')
    >>> decision = infer(rules, ball_distance=4.0, ball_direction=10.0)
    >>> decision.action, decision.parameters, decision.strengths
    ('GOTOBALL', {'power': 100.0}, [0.0, 1.0])
    >>> infer(rules).hunt  # nothing in view: no rule fires, the player hunts
    True
    """
    from soccer_lab.app.cli.rules import inference_report
    from soccer_lab.fuzzy.engine import Engine

    rulebase, vocab = rulebase_of(rules, vocabulary), _vocabulary(vocabulary)
    crisp = _checked_inputs(inputs, vocab)
    engine = Engine(rulebase, vocab)
    inference = engine.infer(crisp)
    report = inference_report(rulebase, vocab, crisp, inference, engine.visible_objects(crisp))
    selected = inference.selected
    return Inference(None if selected is None else selected.action,
                     {} if selected is None else dict(selected.parameters),
                     list(inference.strengths), report["visible"], report)


def _checked_inputs(given: dict[str, Any], vocabulary: Vocabulary) -> dict[str, float | None]:
    """Every input of the vocabulary, None where not given (its object is then not visible)."""
    values: dict[str, float | None] = {name: None for name in vocabulary.input_names}
    for name, value in given.items():
        if name not in values:
            raise ValueError(f"unknown input {name!r}; expected one of {', '.join(vocabulary.input_names)}")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{name}={value!r}: the value must be a finite number")
        values[name] = float(value)
    for obj, kinds in vocabulary.objects.items():
        missing = [n for n in kinds.values() if values[n] is None]
        if missing and len(missing) != len(kinds):
            raise ValueError(f"{vocabulary.display(obj)} is visible but {', '.join(missing)} is missing: give all "
                             "of its inputs, or none when it is not visible")
    return values


# ---- export -----------------------------------------------------------------------------------------
def export(rules: Rules, fmt: str = "json", vocabulary: Vocabulary | None = None) -> str:
    """The rules as our JSON, FCL (IEC 61131-7), fuzzylite's FLL or MATLAB's .fis: the text
    `soccer-lab rules export --format FMT` prints. ValueError for another format.

    >>> text = export(example("demo"), "fll")
    >>> text.splitlines()[0]
    'Engine: soccer_lab'
    """
    return export_rulebase(rulebase_of(rules, vocabulary), fmt, _vocabulary(vocabulary))


# ---- usage and simplification (they play games) -------------------------------------------------------------
def rule_usage(rules: Rules, games: int = DEFAULT_USAGE_GAMES, seed: int = 0, **game: Any) -> "Usage":
    """Play `games` SimpleSoccer games (game i from seed + i) and count, per rule, the ticks it fired
    (`.fired`), won (its action was performed: `.won`), decided (`.decided`) and its mean strength; per
    action the ticks it was performed (`.actions`); the ticks no rule fired (`.hunt`); each game's result
    (`.results`). `game`: GameConfig's options (max_ticks, skills, ...), as `soccer-lab rules usage`.

    >>> usage = rule_usage(example("demo"), games=2, max_ticks=300)
    >>> len(usage.rules), len(usage.results)
    (3, 2)
    >>> usage.rules[2].fired > 0  # "if Ball is not At then GoToBall": the player starts away from the ball
    True
    """
    from soccer_lab.app.rule_inspection import rule_usage as measured_usage

    return measured_usage(rulebase_of(rules), Vocabulary.default(), games, seed, _game_config(game))


@dataclass(frozen=True)
class Simplified:
    """A shorter rulebase that plays the same: `rules`, made from `original` by `steps` (each with its kind,
    "exact" or "checked", and its changes); with games, `before` and `after` are their results."""

    rules: Rulebase
    original: Rulebase
    steps: tuple
    before: tuple["GameResult", ...]
    after: tuple["GameResult", ...]


def simplify(rules: Rules, games: int = 0, seed: int = 0, drop_unused_fields: bool = False,
             **game: Any) -> Simplified:
    """The exact steps of `soccer-lab rules simplify` (each provably changes no decision); with `games`,
    also drop the rules that never won in those games, when every game replays identically.

    >>> rules = parse_rules('''
    ... if Ball is Near then GoToBall High
    ... if Ball is Near then GoToBall High
    ... ''')
    >>> print(format_rules(simplify(rules).rules))
    if Ball is Near then GoToBall High
    """
    from soccer_lab.app.rule_inspection import simplification

    checked = simplification(rulebase_of(rules), Vocabulary.default(), games, seed, _game_config(game),
                             drop_unused_fields)
    done = checked.simplification
    before = checked.usage.results if checked.usage is not None else ()
    return Simplified(done.rulebase, done.original, done.steps, before, checked.results)


def _game_config(options: dict[str, Any]):
    """GameConfig from keyword options; pydantic's ValidationError (a ValueError) names a bad one."""
    from soccer_lab.soccer.config import GameConfig

    unknown = sorted(set(options) - set(GameConfig.model_fields))
    if unknown:
        raise TypeError(f"unknown game option{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; expected "
                        f"{', '.join(GameConfig.model_fields)}")
    return GameConfig(**options)
