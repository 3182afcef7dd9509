"""The chosen action's clipped output sets, their max aggregate and the mean of maximum marked."""

from __future__ import annotations

from app.ui import style
from app.ui.panels.svg import Axis, escape, format_value, svg_open, term_points
from fuzzy.engine import Inference
from fuzzy.vocabulary import Vocabulary

WIDTH = 520
TOP = 40
BOTTOM = 108
HEIGHT = 128
PAD = 14
QUIRK_NOTE = "Left180 and Right180 sit at opposite ends of the line, so together they average to 0 (the chapter's quirk)."


def outputs_html(vocabulary: Vocabulary, inference: Inference) -> str:
    selected = inference.selected
    if selected is None:
        return f'<div style="{style.FONT}; color:{style.MUTED}">No output sets: no rule fired.</div>'
    uses = vocabulary.actions[selected.action]
    if not uses:
        return (
            f'<div style="{style.FONT}; color:{style.MUTED}">{escape(vocabulary.display(selected.action))} '
            f"takes no parameters.</div>"
        )
    charts = [
        _output_chart(vocabulary, output, inference.clipped_sets[selected.action][output], selected.parameters[output])
        for output in uses
    ]
    return f'<div style="{style.FONT}">{"".join(charts)}</div>'


def _output_chart(vocabulary: Vocabulary, output: str, sets: list[tuple[str, float]], value: float) -> str:
    variable = vocabulary.output_variable(output)
    axis = Axis(variable, PAD, WIDTH - PAD)
    parts = [svg_open(WIDTH, HEIGHT)]
    parts.append(
        f'<text x="{PAD}" y="14" font-size="{style.FONT_SIZE}" font-weight="600" fill="{style.INK}">'
        f"{escape(output)}</text>"
    )
    parts.append(
        f'<line x1="{PAD}" y1="{BOTTOM}" x2="{WIDTH - PAD}" y2="{BOTTOM}" stroke="{style.MUTED}"/>'
    )
    for term in variable.terms:
        parts.append(
            f'<polygon points="{term_points(term, axis, TOP, BOTTOM)}" fill="none" stroke="{style.GRID}" '
            f'stroke-width="1.5"/>'
        )
    for term_name, level in sets:
        term = variable.term(term_name)
        parts.append(
            f'<polygon class="clipped" data-term="{escape(term_name)}" data-level="{level:.4f}" '
            f'points="{term_points(term, axis, TOP, BOTTOM, level)}" fill="{style.CLIP_FILL}" opacity="0.6" '
            f'stroke="{style.SELECTED}" stroke-width="1.5"/>'
        )
        centre = axis((term.b + term.c) / 2)
        parts.append(
            f'<text x="{centre:.1f}" y="{BOTTOM + 14}" font-size="{style.SMALL_FONT_SIZE}" text-anchor="middle" '
            f'fill="{style.INK}">{escape(vocabulary.display(term_name))} {level:.2f}</text>'
        )
    x = axis(value)
    label = "default " if not sets else "mean of max "
    anchor = "end" if x > WIDTH / 2 else "start"
    offset = -6 if anchor == "end" else 6
    parts.append(
        f'<line class="mom" data-value="{value:.4f}" x1="{x:.1f}" y1="{TOP - 8}" x2="{x:.1f}" y2="{BOTTOM}" '
        f'stroke="{style.ACCENT}" stroke-width="3" stroke-dasharray="5,3"/>'
        f'<text x="{x + offset:.1f}" y="{TOP - 10}" font-size="{style.FONT_SIZE}" font-weight="600" '
        f'text-anchor="{anchor}" fill="{style.ACCENT}">{label}{escape(format_value(value, variable.unit))}</text>'
    )
    parts.append("</svg>")
    if {t for t, _ in sets} >= {"LEFT180", "RIGHT180"}:
        parts.append(f'<div style="color:{style.MUTED}; font-size:{style.SMALL_FONT_SIZE}px">{QUIRK_NOTE}</div>')
    return "".join(parts)
