"""Live membership degrees of every term of the four inputs, greyed when the object is out of view."""

from __future__ import annotations

from typing import Mapping

from app.ui import style
from app.ui.panels.svg import Axis, escape, format_value, svg_open, term_points
from fuzzy.vocabulary import Vocabulary

WIDTH = 520
CHART_TOP = 8
CHART_BOTTOM = 70
AXIS_LABELS = 88
PAD = 14


def membership_html(vocabulary: Vocabulary, inputs: Mapping[str, float | None]) -> str:
    """One block per input: its terms drawn on the universe with the crisp value marked, then a chip per
    term with its degree. `inputs[name]` is None when the object is not in view."""
    blocks = []
    for obj, kinds in vocabulary.objects.items():
        for kind, input_name in kinds.items():
            blocks.append(_input_block(vocabulary, obj, kind, inputs.get(input_name)))
    return f'<div style="{style.FONT}; color:{style.INK}">{"".join(blocks)}</div>'


def _input_block(vocabulary: Vocabulary, obj: str, kind: str, value: float | None) -> str:
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
        f"{_chart(variable, value, degrees)}"
        f'<div style="display:flex; flex-wrap:wrap; gap:3px">{chips}</div></div>'
    )


def _chart(variable, value, degrees) -> str:
    axis = Axis(variable, PAD, WIDTH - PAD)
    parts = [svg_open(WIDTH, AXIS_LABELS + 4)]
    parts.append(
        f'<line x1="{PAD}" y1="{CHART_BOTTOM}" x2="{WIDTH - PAD}" y2="{CHART_BOTTOM}" stroke="{style.MUTED}"/>'
    )
    for term in variable.terms:
        degree = degrees[term.name]
        fill = style.CLIP_FILL if degree > 0 else "none"
        parts.append(
            f'<polygon points="{term_points(term, axis, CHART_TOP, CHART_BOTTOM)}" fill="none" '
            f'stroke="{style.ACCENT}" stroke-width="1.5" opacity="0.8"/>'
        )
        if degree > 0:
            parts.append(
                f'<polygon points="{term_points(term, axis, CHART_TOP, CHART_BOTTOM, degree)}" '
                f'fill="{fill}" opacity="0.55"/>'
            )
    for tick in axis.ticks():
        x = axis(tick)
        parts.append(
            f'<text x="{x:.1f}" y="{AXIS_LABELS - 4}" font-size="{style.SMALL_FONT_SIZE - 1}" '
            f'text-anchor="middle" fill="{style.MUTED}">{tick:g}</text>'
        )
    if value is not None:
        x = axis(value)
        parts.append(
            f'<line x1="{x:.1f}" y1="{CHART_TOP - 4}" x2="{x:.1f}" y2="{CHART_BOTTOM + 4}" '
            f'stroke="{style.SELECTED}" stroke-width="3"/>'
        )
    parts.append("</svg>")
    return "".join(parts)


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
