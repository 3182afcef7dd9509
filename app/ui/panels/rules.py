"""The decoded rules with their live strengths, the fired actions and the chosen one."""

from __future__ import annotations

from typing import Sequence

from app.ui import style
from app.ui.panels.svg import escape, format_value
from fuzzy.engine import Inference
from fuzzy.vocabulary import Vocabulary

HUNT_TEXT = "No rule fired: the player hunts (turns toward the ball, or 45° toward where it was last seen)."


def decision_html(vocabulary: Vocabulary, inference: Inference) -> str:
    """The chosen action with its parameters, then every fired action with its support."""
    selected = inference.selected
    if selected is None:
        head = f'<div class="decision" data-action="HUNT" style="color:{style.MUTED}">{escape(HUNT_TEXT)}</div>'
        return f'<div style="{style.FONT}; font-size:{style.FONT_SIZE}px">{head}</div>'
    head = (
        f'<div class="decision" data-action="{escape(selected.action)}" style="font-size:{style.FONT_SIZE + 6}px; '
        f'font-weight:700; color:{style.SELECTED}">{escape(vocabulary.display(selected.action))} '
        f'<span style="font-weight:400; color:{style.INK}">{escape(_parameters(vocabulary, selected.parameters))}'
        f"</span></div>"
    )
    others = "".join(
        f'<span style="margin-right:12px; color:{style.SELECTED if a is selected else style.INK}">'
        f"{escape(vocabulary.display(a.action))} {a.support:.2f}</span>"
        for a in inference.fired
    )
    return (
        f'<div style="{style.FONT}; font-size:{style.FONT_SIZE}px">{head}'
        f'<div style="color:{style.MUTED}; font-size:{style.SMALL_FONT_SIZE + 1}px">support of fired actions: '
        f"{others}</div></div>"
    )


def _parameters(vocabulary: Vocabulary, parameters: dict[str, float]) -> str:
    return "  ".join(
        f"{name} {format_value(value, vocabulary.output_variable(name).unit)}" for name, value in parameters.items()
    )


def rules_html(rule_texts: Sequence[str], inference: Inference | None, only_fired: bool) -> str:
    """A row per rule: number, text, a strength bar. The rule that decided the action is highlighted;
    with `only_fired`, rules of strength 0 are left out."""
    strengths = inference.strengths if inference is not None else [0.0] * len(rule_texts)
    deciding = inference.selected.first_rule if inference is not None and inference.selected else None
    rows = []
    for index, (text, strength) in enumerate(zip(rule_texts, strengths)):
        if only_fired and strength <= 0.0:
            continue
        rows.append(_row(index, text, strength, index == deciding))
    if not rule_texts:
        rows.append(f'<div style="color:{style.MUTED}">This rulebase has no rules.</div>')
    elif not rows:
        rows.append(f'<div style="color:{style.MUTED}">No rule fired this tick.</div>')
    return f'<div class="rules" style="{style.FONT}; font-size:{style.FONT_SIZE}px">{"".join(rows)}</div>'


def _row(index: int, text: str, strength: float, deciding: bool) -> str:
    fired = strength > 0.0
    colour = style.SELECTED if deciding else (style.FIRED if fired else style.MUTED)
    background = "rgba(230,81,0,0.10)" if deciding else "transparent"
    bar = (
        f'<div style="width:70px; height:10px; background:{style.GRID}; border-radius:3px; flex:none">'
        f'<div style="width:{70 * strength:.1f}px; height:10px; background:{colour}; border-radius:3px"></div></div>'
    )
    return (
        f'<div class="rule" data-index="{index}" data-strength="{strength:.4f}" data-fired="{str(fired).lower()}" '
        f'style="display:flex; align-items:center; gap:8px; padding:2px 4px; background:{background}; '
        f'border-radius:4px; color:{style.INK if fired else style.MUTED}; font-weight:{600 if deciding else 400}">'
        f'<span style="width:22px; text-align:right; color:{style.MUTED}; flex:none">{index + 1}</span>'
        f'<span style="flex:1">{escape(text)}</span>{bar}'
        f'<span style="width:38px; text-align:right; flex:none; color:{colour}">{strength:.2f}</span></div>'
    )
