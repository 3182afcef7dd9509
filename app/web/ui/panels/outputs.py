"""The chosen action's clipped output sets, their max aggregate and the mean of maximum marked."""

from __future__ import annotations

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import Axis, escape, format_value, svg_open, term_points
from soccer_lab.fuzzy.engine import Inference
from soccer_lab.fuzzy.vocabulary import Vocabulary

WIDTH = 520
TOP = 40
BOTTOM = 108
HEIGHT = 128
PAD = 14
LABEL_ROW = 14  # px between rows of set labels: neighbouring sets' labels take turns rows, never overlap
CHAR_WIDTH = 0.6  # of the font size: an upper estimate of a label character's width
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
    parts = []
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
    labels = []
    for term_name, level in sets:
        term = variable.term(term_name)
        parts.append(
            f'<polygon class="clipped" data-term="{escape(term_name)}" data-level="{level:.4f}" '
            f'points="{term_points(term, axis, TOP, BOTTOM, level)}" fill="{style.CLIP_FILL}" opacity="0.6" '
            f'stroke="{style.SELECTED}" stroke-width="1.5"/>'
        )
        labels.append((axis((term.b + term.c) / 2), f"{vocabulary.display(term_name)} {level:.2f}"))
    placed = _placed_labels(labels)
    rows = 1 + max((row for _, _, row, _ in placed), default=0)
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
    for x, text, row, width in placed:
        parts.append(
            f'<text class="set-label" x="{x:.1f}" y="{BOTTOM + 14 + row * LABEL_ROW}" data-width="{width:.1f}" '
            f'font-size="{style.SMALL_FONT_SIZE}" text-anchor="middle" fill="{style.INK}">{escape(text)}</text>')
    parts.insert(0, svg_open(WIDTH, HEIGHT + (rows - 1) * LABEL_ROW))
    parts.append("</svg>")
    if {t for t, _ in sets} >= {"LEFT180", "RIGHT180"}:
        parts.append(f'<div style="color:{style.MUTED}; font-size:{style.SMALL_FONT_SIZE}px">{QUIRK_NOTE}</div>')
    return "".join(parts)


def _placed_labels(labels: list[tuple[float, str]]) -> list[tuple[float, str, int, float]]:
    """(x, text, row, width) for each (centre x, text): kept inside the chart, each in the first row where it
    overlaps no label already placed (left to right)."""
    placed: list[tuple[float, str, int, float]] = []
    row_ends: list[float] = []  # the right edge of the last label in each row
    for centre, text in sorted(labels):
        width = len(text) * style.SMALL_FONT_SIZE * CHAR_WIDTH
        x = min(max(centre, width / 2), WIDTH - width / 2)
        row = next((r for r, end in enumerate(row_ends) if x - width / 2 > end + 4), len(row_ends))
        if row == len(row_ends):
            row_ends.append(0.0)
        row_ends[row] = x + width / 2
        placed.append((x, text, row, width))
    return placed
