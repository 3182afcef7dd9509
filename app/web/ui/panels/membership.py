"""Live membership degrees of every term of the four inputs, greyed when the object is out of view.

The terms' outlines and the axis never change: `terms_html` draws them once, as SVG definitions each
input's chart then shows with `<use>`. Each tick only the value, the clipped terms and the degrees
are sent, for each input on its own (`input_html`), and only when they changed.

The ball distance's chart also marks the kicking reach (`kick_reach`): "Ball is At" reaches 2 m but a
kick only the world's kickable distance, so a player can decide to kick a ball it cannot reach.
"""

from __future__ import annotations

from typing import Mapping

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import Axis, escape, format_value, svg_open, term_points
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.perception import BALL, DISTANCE

WIDTH = 520
CHART_TOP = 8
CHART_BOTTOM = 70
AXIS_LABELS = 88
PAD = 14


def membership_html(vocabulary: Vocabulary, inputs: Mapping[str, float | None],
                    reaches: Mapping[str, float] | None = None) -> str:
    """Every input's block after the shared term outlines (what the panel shows, in one piece)."""
    reaches = reaches or {}
    names = input_names(vocabulary)
    blocks = [input_html(vocabulary, name, inputs.get(name), reaches.get(name)) for name in names]
    return terms_html(vocabulary) + "".join(blocks)


def kick_reach(vocabulary: Vocabulary, world: WorldConfig) -> dict[str, float]:
    """{ball distance input: the distance within which the ball can be kicked}, as `reaches` takes it."""
    return {vocabulary.objects[BALL][DISTANCE]: world.kickable_distance}


def input_names(vocabulary: Vocabulary) -> list[str]:
    return [input_name for kinds in vocabulary.objects.values() for input_name in kinds.values()]


def _terms_id(kind: str) -> str:
    return f"membership-terms-{kind}"


def terms_html(vocabulary: Vocabulary) -> str:
    """An invisible SVG holding, per kind of input (distance, direction), its terms' outlines and axis."""
    groups = []
    for kind in dict.fromkeys(kind for kinds in vocabulary.objects.values() for kind in kinds):
        variable = vocabulary.variables[kind]
        axis = Axis(variable, PAD, WIDTH - PAD)
        parts = [f'<line x1="{PAD}" y1="{CHART_BOTTOM}" x2="{WIDTH - PAD}" y2="{CHART_BOTTOM}" stroke="{style.MUTED}"/>']
        parts += [
            f'<polygon points="{term_points(term, axis, CHART_TOP, CHART_BOTTOM)}" fill="none" '
            f'stroke="{style.ACCENT}" stroke-width="1.5" opacity="0.8"/>'
            for term in variable.terms
        ]
        parts += [
            f'<text x="{axis(tick):.1f}" y="{AXIS_LABELS - 4}" font-size="{style.SMALL_FONT_SIZE - 1}" '
            f'text-anchor="middle" fill="{style.MUTED}">{tick:g}</text>'
            for tick in axis.ticks()
        ]
        groups.append(f'<g id="{_terms_id(kind)}">{"".join(parts)}</g>')
    return (f'<svg class="membership-terms" width="0" height="0" style="position:absolute" aria-hidden="true">'
            f'<defs>{"".join(groups)}</defs></svg>')


def input_html(vocabulary: Vocabulary, input_name: str, value: float | None, reach: float | None = None) -> str:
    """One input's block: its terms drawn on the universe with the crisp value marked, then a chip per
    term with its degree. `value` is None when the object is not in view; `reach`, when given, is marked
    on the axis (the ball's kicking reach)."""
    obj, kind = next((obj, kind) for obj, kinds in vocabulary.objects.items()
                     for kind, name in kinds.items() if name == input_name)
    block = _input_block(vocabulary, obj, kind, value, reach)
    return f'<div style="{style.FONT}; color:{style.INK}">{block}</div>'


def _input_block(vocabulary: Vocabulary, obj: str, kind: str, value: float | None, reach: float | None) -> str:
    variable = vocabulary.variables[kind]
    visible = value is not None
    degrees = variable.fuzzify(value) if visible else {t: 0.0 for t in variable.term_names}
    title = f"{vocabulary.display(obj)} {kind}"
    reading = format_value(value, variable.unit) if visible else "not in view"
    opacity = "1" if visible else "0.35"
    chips = "".join(_chip(vocabulary.display(term), degrees[term], visible) for term in variable.term_names)
    return (
        f'<div class="membership-input" data-input="{escape(vocabulary.objects[obj][kind])}" '
        f'data-visible="{str(visible).lower()}" style="margin:0 0 10px 0; opacity:{opacity}">'
        f'<div style="font-size:{style.FONT_SIZE + 1}px; font-weight:600">{escape(title)} '
        f'<span class="reading" style="font-weight:400; color:{style.ACCENT if visible else style.MUTED}">'
        f"{escape(reading)}</span></div>"
        f"{_chart(variable, kind, value, degrees, reach)}"
        f'<div style="display:flex; flex-wrap:wrap; gap:3px">{chips}</div></div>'
    )


def _chart(variable, kind: str, value, degrees, reach: float | None) -> str:
    axis = Axis(variable, PAD, WIDTH - PAD)
    parts = [svg_open(WIDTH, AXIS_LABELS + 4), f'<use href="#{_terms_id(kind)}"/>']
    if reach is not None:
        parts.append(_reach_mark(axis(reach), reach, variable.unit))
    parts += [
        f'<polygon points="{term_points(term, axis, CHART_TOP, CHART_BOTTOM, degrees[term.name])}" '
        f'fill="{style.CLIP_FILL}" opacity="0.55"/>'
        for term in variable.terms if degrees[term.name] > 0
    ]
    if value is not None:
        x = axis(value)
        parts.append(
            f'<line x1="{x:.1f}" y1="{CHART_TOP - 4}" x2="{x:.1f}" y2="{CHART_BOTTOM + 4}" '
            f'stroke="{style.SELECTED}" stroke-width="3"/>'
        )
    parts.append("</svg>")
    return "".join(parts)


def _reach_mark(x: float, reach: float, unit: str) -> str:
    """A dashed line at the kicking reach, labelled inside the chart: left of it the ball can be kicked."""
    label = f"kick reach {reach:g} {unit}".strip()
    return (f'<g class="kick-reach" data-reach="{reach:g}">'
            f'<line x1="{x:.1f}" y1="{CHART_TOP - 6}" x2="{x:.1f}" y2="{CHART_BOTTOM}" stroke="{style.FIRED}" '
            f'stroke-width="2" stroke-dasharray="4 3"/>'
            f'<text x="{x + 4:.1f}" y="{CHART_TOP + 4}" font-size="{style.SMALL_FONT_SIZE}" fill="{style.FIRED}" '
            f'stroke="white" stroke-width="3" paint-order="stroke">'
            f'{escape(label)}</text></g>')


def _chip(name: str, degree: float, visible: bool) -> str:
    active = visible and round(degree, 2) > 0  # what the chip prints decides how it looks
    background = f"rgba(255,152,0,{0.15 + 0.6 * degree:.2f})" if active else style.GRID
    colour = style.INK if active else style.MUTED
    weight = 700 if active else 400
    return (
        f'<span class="term" data-degree="{degree:.4f}" style="background:{background}; color:{colour}; '
        f'font-weight:{weight}; font-size:{style.SMALL_FONT_SIZE + 1}px; padding:1px 6px; border-radius:4px">'
        f"{escape(name)} {degree:.2f}</span>"
    )
