"""pydantic's validation errors as one line for a person: `where: message (got value)`, problems joined by
"; ". The one formatter the CLI, the API and the UI share; each names the place its own way (an option,
a JSON path, a field's label)."""

from __future__ import annotations

from typing import Any, Callable, Iterable, Mapping

Location = tuple[Any, ...]


def dotted(location: Location) -> str:
    """`("ga", "population_size")` -> "ga.population_size"."""
    return ".".join(str(part) for part in location)


def problem_message(error: Mapping[str, Any]) -> str:
    """pydantic's message without the "Value error, " it puts before a validator's own message."""
    return str(error.get("msg", "")).removeprefix("Value error, ")


def describe_problem(error: Mapping[str, Any], where: Callable[[Location], str] = dotted) -> str:
    """One error of `ValidationError.errors()`; the value given is shown when it is a plain value."""
    place = where(tuple(error.get("loc", ())))
    given = error.get("input")
    shown = f" (got {_short(repr(given))})" if place and "input" in error and not isinstance(given, (dict, list)) else ""
    return f"{place}: {problem_message(error)}{shown}" if place else f"{problem_message(error)}{shown}"


def _short(text: str, characters: int = 80) -> str:
    """A value given, shown in part: an error never echoes a long input whole."""
    return text if len(text) <= characters else f"{text[:characters]}... ({len(text):,} characters)"


def describe_problems(errors: Iterable[Mapping[str, Any]], where: Callable[[Location], str] = dotted) -> str:
    return "; ".join(describe_problem(error, where) for error in errors)
