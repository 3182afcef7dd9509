"""mkdocs hook: the `<!-- generated: api -->` block of a page
(docs/hooks/generated_block.py) holds the HTTP API's reference, rendered from the
OpenAPI document the FastAPI app itself builds (the one `serve` publishes at /openapi.json), as plain
Markdown: no script, nothing fetched, so the page reads the same offline.
"""

from __future__ import annotations

from typing import Any

from generated_block import has_block, with_block  # docs/hooks/, on sys.path as mkdocs loads hooks

NAME = "api"
METHODS = ("get", "post", "put", "patch", "delete")


def openapi() -> dict[str, Any]:
    from soccer_lab.app.web.api import create_app

    return create_app(None, None).openapi()  # the document needs the routes, not a store or runs


def schema_name(reference: str) -> str:
    return reference.rsplit("/", 1)[-1]


def anchor(name: str) -> str:
    return f"schema-{name.lower()}"


def type_of(schema: dict[str, Any]) -> str:
    """A schema in a few words: `integer`, `[RunOut](#schema-runout)`, `array of string`, `a | b`."""
    if "$ref" in schema:
        name = schema_name(schema["$ref"])
        return f"[{name}](#{anchor(name)})"
    for combined in ("anyOf", "oneOf", "allOf"):
        if combined in schema:
            return " or ".join(type_of(part) for part in schema[combined])
    if "enum" in schema:
        return "one of " + ", ".join(f"`{value}`" for value in schema["enum"])
    if "const" in schema:
        return f"`{schema['const']}`"
    kind = schema.get("type", "any")
    if kind == "array":
        return f"array of {type_of(schema.get('items', {}))}"
    if kind == "object" and "additionalProperties" in schema and isinstance(schema["additionalProperties"], dict):
        return f"object of {type_of(schema['additionalProperties'])}"
    return kind


def cell(text: object) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def operation(path: str, method: str, spec: dict[str, Any]) -> list[str]:
    lines = [f"### `{method.upper()} {path}`", ""]
    if spec.get("summary"):
        lines += [spec["summary"] + ".", ""]
    if spec.get("description"):
        lines += [spec["description"], ""]
    parameters = spec.get("parameters", [])
    if parameters:
        lines += ["| parameter | in | type | required | description |", "|---|---|---|---|---|"]
        lines += [f"| `{p['name']}` | {p['in']} | {cell(type_of(p.get('schema', {})))} | "
                  f"{'yes' if p.get('required') else 'no'} | {cell(p.get('description', ''))} |" for p in parameters]
        lines.append("")
    body = spec.get("requestBody", {}).get("content", {})
    for media, content in body.items():
        lines += [f"Body ({media}): {type_of(content.get('schema', {}))}", ""]
    lines += ["| status | meaning | body |", "|---|---|---|"]
    for status, response in spec.get("responses", {}).items():
        content = response.get("content", {})
        shown = "; ".join(f"{type_of(c.get('schema', {}))} ({media})" for media, c in content.items())
        lines.append(f"| {status} | {cell(response.get('description', ''))} | {cell(shown)} |")
    return lines + [""]


def schema(name: str, spec: dict[str, Any]) -> list[str]:
    # an HTML anchor, not attr_list's `{#id}`: GitHub shows that as text and gives the heading an id of its own
    lines = [f'<a id="{anchor(name)}"></a>', "", f"### {name}", ""]
    if spec.get("description"):
        lines += [cell(spec["description"]), ""]
    properties = spec.get("properties", {})
    if not properties:
        return lines + [f"Type: {type_of(spec)}", ""]
    required = set(spec.get("required", []))
    lines += ["| field | type | required | default | description |", "|---|---|---|---|---|"]
    for field, field_spec in properties.items():
        default = f"`{field_spec['default']}`" if "default" in field_spec else ""
        lines.append(f"| `{field}` | {cell(type_of(field_spec))} | {'yes' if field in required else 'no'} | "
                     f"{cell(default)} | {cell(field_spec.get('description', ''))} |")
    return lines + [""]


def api_reference() -> str:
    document = openapi()
    lines = [f"OpenAPI {document['openapi']}, {document['info']['title']} {document['info']['version']}.", ""]
    by_tag: dict[str, list[tuple[str, str, dict[str, Any]]]] = {}
    for path, methods in document["paths"].items():
        for method in METHODS:
            if method in methods:
                spec = methods[method]
                by_tag.setdefault((spec.get("tags") or ["other"])[0], []).append((path, method, spec))
    for tag, operations in by_tag.items():
        lines += [f"## {tag.capitalize()}", ""]
        for path, method, spec in operations:
            lines += operation(path, method, spec)
    lines += ["## Schemas", ""]
    for name, spec in document.get("components", {}).get("schemas", {}).items():
        lines += schema(name, spec)
    return "\n".join(lines)


def on_page_markdown(markdown: str, **_: object) -> str:
    return with_block(markdown, NAME, api_reference()) if has_block(markdown, NAME) else markdown
