"""mkdocs hook: the `<!-- generated: vocabulary -->` block of a page
(docs/hooks/generated_block.py) holds the soccer vocabulary's tables, read
from the one file that defines it, fuzzy/data/soccer_vocabulary.json: the linguistic variables with each
term's membership parameters, the objects and their inputs, the outputs, the actions with the parameters
each uses, and the compact notation's abbreviations."""

from __future__ import annotations

import json
from pathlib import Path

from generated_block import has_block, with_block  # docs/hooks/, on sys.path as mkdocs loads hooks

NAME = "vocabulary"
VOCABULARY = Path(__file__).resolve().parents[2] / "fuzzy" / "data" / "soccer_vocabulary.json"


def number(value: float) -> str:
    return f"{value:g}"


def vocabulary_reference() -> str:
    data = json.loads(VOCABULARY.read_text(encoding="utf-8"))
    names = {key.upper(): value for key, value in data.get("display_names", {}).items()}
    abbreviations = {key.upper(): value for key, value in data.get("abbreviations", {}).items()}

    def shown(name: str) -> str:
        return names.get(name, name.capitalize())

    lines = [f"Read from `fuzzy/data/soccer_vocabulary.json` ({data['format']}, version {data['version']}). "
             + data.get("comment", ""), ""]
    lines += ["## Variables and terms", ""]
    for variable, spec in data["variables"].items():
        low, high = spec["universe"]
        unit = f" {spec['unit']}" if spec.get("unit") else ""
        lines += [f"### {variable}", "", f"Universe {number(low)} to {number(high)}{unit}.", "",
                  "| term | a | b | c | d | abbreviation |", "|---|---|---|---|---|---|"]
        for term, (a, b, c, d) in spec["terms"].items():
            lines.append(f"| {shown(term)} | {number(a)} | {number(b)} | {number(c)} | {number(d)} | "
                         f"`{abbreviations.get(term, '')}` |")
        lines.append("")
    lines += ["## Objects and inputs", "", "| object | abbreviation | inputs |", "|---|---|---|"]
    for obj, inputs in data["objects"].items():
        listed = ", ".join(f"`{name}` ({kind}, variable {data['inputs'][name]})" for kind, name in inputs.items())
        lines.append(f"| {shown(obj)} | `{abbreviations.get(obj, '')}` | {listed} |")
    lines += ["", "## Outputs", "", "| output | variable | when no rule sets it |", "|---|---|---|"]
    for output, spec in data["outputs"].items():
        lines.append(f"| {output} | {spec['variable']} | {number(spec['default'])} |")
    lines += ["", "## Actions", "", "| action | abbreviation | parameters it uses |", "|---|---|---|"]
    for action, parameters in data["actions"].items():
        lines.append(f"| {shown(action)} | `{abbreviations.get(action, '')}` | {', '.join(parameters) or 'none'} |")
    others = {key: value for key, value in abbreviations.items()
              if key not in data["objects"] and key not in data["actions"]
              and not any(key in spec["terms"] for spec in data["variables"].values())}
    if others:
        lines += ["", "## Other abbreviations of the compact notation", "", "| word | abbreviation |", "|---|---|"]
        lines += [f"| {shown(word)} | `{abbreviation}` |" for word, abbreviation in others.items()]
    return "\n".join(lines) + "\n"


def on_page_markdown(markdown: str, **_: object) -> str:
    return with_block(markdown, NAME, vocabulary_reference()) if has_block(markdown, NAME) else markdown
