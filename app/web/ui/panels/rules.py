"""The decoded rules with their live strengths, the fired actions and the chosen one; beside each rule,
once measured, its usage over games (a bar: the share of ticks it won; grey: it never won)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

from soccer_lab.app.words import plural
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape, format_value
from soccer_lab.fuzzy.engine import Inference
from soccer_lab.fuzzy.vocabulary import Vocabulary

if TYPE_CHECKING:
    from soccer_lab.soccer.usage import Usage

HUNT_TEXT = "No rule fired: the player hunts (turns toward the ball, or 45° toward where it was last seen)."


def outcome_html(outcome: str | None, refused: bool) -> str:
    """What the player then did in the world, under the decision (`refused`: a command that could not
    happen, in red)."""
    if outcome is None:
        text, colour = "Then in the world: nothing yet (the player acts on the next tick).", style.MUTED
    else:
        text, colour = f"Then in the world: {outcome}", style.ERROR if refused else style.FIRED
    return (f'<div class="outcome" data-refused="{str(refused).lower()}" style="margin:2px 0 4px; '
            f'font-size:{style.FONT_SIZE}px; font-weight:600; color:{colour}">{escape(text)}</div>')


def decision_html(vocabulary: Vocabulary, inference: Inference, outcome: str | None = None,
                  refused: bool = False, tick: int | None = None) -> str:
    """The chosen action with its parameters, what the player then did (`outcome`, a sentence), then every
    fired action with its support. `tick`: the game's tick it explains (data-tick: the page can check that the
    panel and the pitch show the same one)."""
    tick_mark = f' data-tick="{tick}"' if tick is not None else ""
    selected = inference.selected
    did = outcome_html(outcome, refused)
    if selected is None:
        head = f'<div class="decision" data-action="HUNT" style="color:{style.MUTED}">{escape(HUNT_TEXT)}</div>'
        return f'<div class="inference-decision"{tick_mark} style="{style.FONT}; font-size:{style.FONT_SIZE}px">{head}{did}</div>'
    head = (
        f'<div class="decision" data-action="{escape(selected.action)}" style="font-size:{style.FONT_SIZE + 6}px; '
        f'font-weight:700; color:{style.SELECTED}">{escape(vocabulary.display(selected.action))} '
        f'<span style="font-weight:400; color:{style.INK}">{escape(parameters_text(vocabulary, selected.parameters))}'
        f"</span></div>"
    )
    others = "".join(
        f'<span style="margin-right:12px; white-space:nowrap; color:{style.SELECTED if a is selected else style.INK}">'
        f"{escape(vocabulary.display(a.action))} {a.support:.2f}</span>"
        for a in inference.fired
    )
    return (
        f'<div class="inference-decision"{tick_mark} style="{style.FONT}; font-size:{style.FONT_SIZE}px">{head}{did}'
        f'<div style="color:{style.MUTED}; font-size:{style.SMALL_FONT_SIZE + 1}px">support of fired actions: '
        f"{others}</div></div>"
    )


def parameters_text(vocabulary: Vocabulary, parameters: dict[str, float]) -> str:
    return "  ".join(
        f"{name} {format_value(value, vocabulary.output_variable(name).unit)}" for name, value in parameters.items()
    )


def rules_html(rule_texts: Sequence[str], inference: Inference | None, only_fired: bool,
               usage: "Usage | None" = None) -> str:
    """A row per rule: number, text, a strength bar, and with `usage` a bar of the share of ticks the
    rule won over those games (grey row: never won). The rule that decided the action is highlighted;
    with `only_fired`, rules of strength 0 are left out."""
    strengths = inference.strengths if inference is not None else [0.0] * len(rule_texts)
    deciding = inference.selected.first_rule if inference is not None and inference.selected else None
    rows = []
    for index, (text, strength) in enumerate(zip(rule_texts, strengths)):
        if only_fired and strength <= 0.0:
            continue
        won = usage.rules[index].won / max(usage.ticks, 1) if usage is not None else None
        rows.append(_row(index, text, strength, index == deciding, won, usage is not None and won == 0))
    if not rule_texts:
        rows.append(f'<div style="color:{style.MUTED}">This rulebase has no rules.</div>')
    elif not rows:
        rows.append(f'<div style="color:{style.MUTED}">No rule fired this tick.</div>')
    caption = usage_caption(usage) if usage is not None else ""
    return f'<div class="rules" style="{style.FONT}; font-size:{style.FONT_SIZE}px">{caption}{"".join(rows)}</div>'


def usage_caption(usage: "Usage") -> str:
    seeds = usage.seeds
    return (
        f'<div class="usage-caption" data-games="{len(seeds)}" style="color:{style.MUTED}; '
        f'font-size:{style.SMALL_FONT_SIZE + 1}px; margin-bottom:4px">Usage over {plural(len(seeds), "game")} (seeds '
        f"{seeds[0]}–{seeds[-1]}): the blue bar is the share of ticks each rule won (it fired and its action was "
        f"performed); grey rules never won. The player hunted {100 * usage.hunt_share:.1f}% of the ticks.</div>"
    )


def _bar(share: float, colour: str, width: int) -> str:
    return (
        f'<div style="width:{width}px; height:10px; background:{style.GRID}; border-radius:3px; flex:none">'
        f'<div style="width:{width * share:.1f}px; height:10px; background:{colour}; border-radius:3px"></div></div>'
    )


def _row(index: int, text: str, strength: float, deciding: bool, won: float | None, never_won: bool) -> str:
    fired = strength > 0.0
    colour = style.SELECTED if deciding else (style.FIRED if fired else style.MUTED)
    background = "rgba(230,81,0,0.10)" if deciding else "transparent"
    usage = "" if won is None else (
        f'<span class="usage" data-won="{won:.4f}" title="won {100 * won:.1f}% of the ticks" '
        f'style="display:flex; flex:none">{_bar(won, style.ACCENT, style.USAGE_BAR_WIDTH)}</span>')
    return (
        f'<div class="rule" data-index="{index}" data-strength="{strength:.4f}" data-fired="{str(fired).lower()}" '
        f'data-never-won="{str(never_won).lower()}" '
        f'style="display:flex; align-items:center; gap:8px; padding:2px 4px; background:{background}; '
        f'border-radius:4px; color:{style.INK if fired else style.MUTED}; font-weight:{600 if deciding else 400}'
        f'{"; opacity:" + str(style.NEVER_WON_OPACITY) if never_won else ""}">'
        f'<span style="width:22px; text-align:right; color:{style.MUTED}; flex:none">{index + 1}</span>'
        f'<span style="flex:1">{escape(text)}</span>{usage}{_bar(strength, colour, 70)}'
        f'<span style="width:38px; text-align:right; flex:none; color:{colour}">{strength:.2f}</span></div>'
    )
