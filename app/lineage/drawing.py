"""A family tree (app/lineage/family_tree.py's FamilyTreeView) drawn three ways: text for the terminal, SVG (the UI's
Lineage tab and `soccer-lab lineage --svg`) and Graphviz DOT (`--dot`). Ancestors stand in rows, one per
generation, the oldest at the top and the player at the bottom; an ancestor that a rule of the player
came from wears that rule's letter and colour."""

from __future__ import annotations

import html
from typing import Sequence

from soccer_lab.app.lineage.family_tree import MUTATED_COLOUR, FamilyTreeView
from soccer_lab.app.words import plural
from soccer_lab.ga.lineage import Ancestor

FONT = "font-family: Inter, 'Segoe UI', Helvetica, Arial, sans-serif"
MONO = "font-family: 'DejaVu Sans Mono', Menlo, Consolas, monospace"
INK, MUTED, LINE, ACCENT = "#1f2933", "#616e7c", "#9aa5b1", "#1976d2"
NODE_WIDTH, NODE_HEIGHT, NODE_GAP, ROW_HEIGHT = 104, 52, 14, 78
LABEL_WIDTH, MARGIN = 58, 10
MAX_ROW_NODES = 8  # more ancestors in one generation are summed up in a last box
RULE_LINE_HEIGHT, GENES_PER_LINE, CHARACTER_WIDTH = 22, 10, 7.4


def escape(text: object) -> str:
    return html.escape(str(text), quote=True)


# ---- text -------------------------------------------------------------------------------------
def tree_text(view: FamilyTreeView) -> str:
    chosen = view.tree.ancestors[view.chosen]
    lines = [view.title(), f"born: {view.birth_text(chosen)}", "",
             f"Family tree: the ancestors whose genes it carries, back to generation {view.tree.oldest}"]
    for row in view.rows():
        for ancestor in row:
            lines.append(_ancestor_line(view, ancestor))
    if view.opponents:
        lines += ["", "Scored against (co-evolution: the hall of fame members each generation played):"]
        lines += [f"  gen {g:>3}: {', '.join(labels)}" for g, labels in sorted(view.opponents.items(), reverse=True)]
    lines += ["", "Rules, each with the ancestor it came from:"]
    for rule in view.rules:
        lines.append(f"{rule.number:>3} [{rule.letter}] {rule.text}")
        lines.append(f"        {rule.genes}")
        lines.append(f"        {rule.summary}")
        lines += [f"        mutated here: {change}" for change in rule.mutated]
    lines += ["", "Chromosome in compact notation, each gene with the letter of its rule's origin "
              "(- in no rule, * mutated at this player's birth):"]
    genes = [f"{gene.origin or '-'}{gene.compact}{'*' if gene.mutated else ''}" for gene in view.genes()]
    lines += ["  " + " ".join(genes[i:i + GENES_PER_LINE]) for i in range(0, len(genes), GENES_PER_LINE)]
    lines.append("Origins: " + ", ".join(f"{letter} = {place}" for place, letter in view.letters.items()))
    return "\n".join(lines) + "\n"


def _ancestor_line(view: FamilyTreeView, ancestor: Ancestor) -> str:
    individual = ancestor.individual
    letter = view.letters.get(ancestor.place)
    marks = [f"origin of rules {letter}"] if letter else []
    if ancestor.place == view.chosen:
        marks.insert(0, "the player")
    elif ancestor.place == view.best:
        marks.insert(0, "the best so far")
    parents = ", ".join(f"#{p.index}" for p in ancestor.parents)
    return (f"  gen {ancestor.place.generation:>3} #{ancestor.place.index:<4} fitness {individual.fitness:.3f} "
            f"{plural(individual.goals, 'goal'):<8} {view.short_birth(ancestor):<16} "
            f"{plural(len(ancestor.genes), 'gene'):<9} {('from ' + parents) if parents else '':<14} "
            f"{'; '.join(marks)}").rstrip()


# ---- SVG --------------------------------------------------------------------------------------
def tree_svg(view: FamilyTreeView, *, with_rules: bool = False, max_row_nodes: int = MAX_ROW_NODES) -> str:
    """The tree as an SVG document at its natural size (shrunk to fit a narrower page, never grown);
    `with_rules` adds the player's rules and chromosome below it (a file that stands alone). A generation
    with more than `max_row_nodes` ancestors shows the first ones and how many more."""
    rows = list(reversed(view.rows()))  # the oldest at the top
    shown = [row[:max_row_nodes - 1] if len(row) > max_row_nodes else row for row in rows]
    columns = max(len(row) + (len(row) < len(full)) for row, full in zip(shown, rows))
    tree_width = LABEL_WIDTH + columns * (NODE_WIDTH + NODE_GAP) + MARGIN
    positions: dict = {}
    for r, (row, full) in enumerate(zip(shown, rows)):
        count = len(row) + (len(row) < len(full))
        left = LABEL_WIDTH + (columns - count) * (NODE_WIDTH + NODE_GAP) / 2
        for c, ancestor in enumerate(row):
            positions[ancestor.place] = (left + c * (NODE_WIDTH + NODE_GAP), MARGIN + r * ROW_HEIGHT)
    parts = []
    for ancestor in (a for row in shown for a in row):  # edges first, under the boxes
        x, y = positions[ancestor.place]
        for parent in ancestor.parents:
            if parent in positions:
                px, py = positions[parent]
                x1, y1, x2, y2 = px + NODE_WIDTH / 2, py + NODE_HEIGHT, x + NODE_WIDTH / 2, y
                middle = (y1 + y2) / 2
                parts.append(f'<path d="M{x1:.1f},{y1:.1f} C{x1:.1f},{middle:.1f} {x2:.1f},{middle:.1f} {x2:.1f},{y2:.1f}" '
                             f'fill="none" stroke="{LINE}" stroke-width="1.6"/>')
    for r, (row, full) in enumerate(zip(shown, rows)):
        y = MARGIN + r * ROW_HEIGHT
        parts.append(f'<text x="4" y="{y + NODE_HEIGHT / 2 + 5:.1f}" font-size="13" fill="{MUTED}">gen {full[0].place.generation}</text>')
        for ancestor in row:
            parts.append(_node_svg(view, ancestor, *positions[ancestor.place]))
        if len(row) < len(full):
            x = LABEL_WIDTH + ((columns - len(row) - 1) / 2 + len(row)) * (NODE_WIDTH + NODE_GAP)
            parts.append(f'<rect x="{x:.1f}" y="{y}" width="{NODE_WIDTH}" height="{NODE_HEIGHT}" rx="6" fill="#f5f7fa" '
                         f'stroke="{LINE}" stroke-dasharray="4 3"/><text x="{x + NODE_WIDTH / 2:.1f}" y="{y + 30}" '
                         f'font-size="13" text-anchor="middle" fill="{MUTED}">+{len(full) - len(row)} more</text>')
    height = MARGIN + len(rows) * ROW_HEIGHT
    total_width = tree_width
    if with_rules:
        extra, extra_height, extra_width = _rules_svg(view, height)
        parts.append(extra)
        height += extra_height
        total_width = max(tree_width, extra_width)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" class="family-tree" width="{total_width:.0f}" '
            f'height="{height:.0f}" viewBox="0 0 {total_width:.0f} {height:.0f}" '
            f'style="{FONT}; background:white; max-width:100%; height:auto">'
            f'<title>{escape(view.title())}</title>{"".join(parts)}</svg>')


def _node_svg(view: FamilyTreeView, ancestor: Ancestor, x: float, y: float) -> str:
    individual = ancestor.individual
    colour = view.colour(ancestor.place)
    chosen = ancestor.place == view.chosen
    stroke = ACCENT if chosen else colour or LINE
    fill = colour or "white"
    letter = view.letters.get(ancestor.place)
    badge = ""
    if letter:
        badge = (f'<circle cx="{x + NODE_WIDTH - 13}" cy="{y + 13}" r="10" fill="{colour}"/>'
                 f'<text x="{x + NODE_WIDTH - 13}" y="{y + 17.5}" font-size="13" font-weight="700" fill="white" '
                 f'text-anchor="middle">{escape(letter)}</text>')
    return (f'<g class="ancestor" data-generation="{ancestor.place.generation}" data-index="{ancestor.place.index}">'
            f'<title>{escape(ancestor.place)}: {escape(view.birth_text(ancestor))}</title>'
            f'<rect x="{x:.1f}" y="{y}" width="{NODE_WIDTH}" height="{NODE_HEIGHT}" rx="6" fill="{fill}" '
            f'fill-opacity="{0.16 if colour else 1}" stroke="{stroke}" stroke-width="{3 if chosen else 1.5}"/>'
            f'<text x="{x + 7:.1f}" y="{y + 17}" font-size="14" font-weight="700" fill="{INK}">#{ancestor.place.index}'
            f'<tspan font-weight="400" fill="{MUTED}" font-size="12"> {plural(individual.goals, "goal")}</tspan></text>'
            f'<text x="{x + 7:.1f}" y="{y + 32}" font-size="12" fill="{INK}">fitness {individual.fitness:.3f}</text>'
            f'<text x="{x + 7:.1f}" y="{y + 46}" font-size="11" fill="{MUTED}">{escape(view.short_birth(ancestor))}</text>'
            f"{badge}</g>")


def _rules_svg(view: FamilyTreeView, top: float) -> tuple[str, float, float]:
    """The rules (letter, text, genes, where from) and the chromosome below the tree: (svg, height, width)."""
    parts, y, width = [], top + 24, 0.0
    parts.append(f'<text x="{MARGIN}" y="{y}" font-size="15" font-weight="700" fill="{INK}">Rules of '
                 f'{escape(view.chosen)}, each with the ancestor it came from</text>')
    for rule in view.rules:
        y += RULE_LINE_HEIGHT + 6
        parts.append(_letter_badge(rule.letter, rule.colour, MARGIN + 10, y - 5))
        parts.append(f'<text x="{MARGIN + 26}" y="{y}" font-size="13" fill="{INK}">{rule.number}. {escape(rule.text)}</text>')
        y += RULE_LINE_HEIGHT - 4
        note = rule.summary + "".join(f"; mutated here: {change}" for change in rule.mutated)
        parts.append(f'<text x="{MARGIN + 26}" y="{y}" font-size="12" fill="{MUTED}"><tspan style="{MONO}">'
                     f'{escape(rule.genes)}</tspan>  {escape(note)}</text>')
        width = max(width, MARGIN + 30 + CHARACTER_WIDTH * max(len(rule.text) + 4, len(rule.genes) + len(note) + 2))
    y += RULE_LINE_HEIGHT + 10
    parts.append(f'<text x="{MARGIN}" y="{y}" font-size="15" font-weight="700" fill="{INK}">Chromosome in compact '
                 f'notation (colour: its rule\'s origin; red underline: mutated at this birth)</text>')
    genes = view.genes()
    for start in range(0, len(genes), GENES_PER_LINE):
        y += RULE_LINE_HEIGHT
        x = MARGIN
        for gene in genes[start:start + GENES_PER_LINE]:
            colour = _letter_colour(view, gene.origin) or MUTED
            length = CHARACTER_WIDTH * len(gene.compact)
            parts.append(f'<text x="{x:.1f}" y="{y}" font-size="13" fill="{colour}" style="{MONO}">'
                         f'{escape(gene.compact)}</text>')
            if gene.mutated:
                parts.append(f'<line x1="{x:.1f}" y1="{y + 4}" x2="{x + length:.1f}" y2="{y + 4}" '
                             f'stroke="{MUTATED_COLOUR}" stroke-width="2"><title>{escape(gene.mutated)}</title></line>')
            x += length + CHARACTER_WIDTH
        width = max(width, x)
    return "".join(parts), y + 14 - top, width + MARGIN


def _letter_badge(letter: str, colour: str, x: float, y: float) -> str:
    return (f'<circle cx="{x}" cy="{y}" r="9" fill="{colour}"/><text x="{x}" y="{y + 4.5}" font-size="12" '
            f'font-weight="700" fill="white" text-anchor="middle">{escape(letter)}</text>')


def _letter_colour(view: FamilyTreeView, letter: str | None) -> str | None:
    for place, own in view.letters.items():
        if own == letter:
            return view.colour(place)
    return None


# ---- DOT --------------------------------------------------------------------------------------
def tree_dot(view: FamilyTreeView) -> str:
    """Graphviz DOT: one node per ancestor (rows of equal rank per generation), an edge from each parent."""
    lines = ["digraph family_tree {", "  rankdir=TB;", '  node [shape=box, style="rounded,filled", '
             'fontname="Helvetica", fontsize=11, fillcolor=white];',
             f"  label={_dot_string(view.title())}; labelloc=t;"]
    for row in view.rows():
        names = []
        for ancestor in row:
            name = _dot_name(ancestor)
            names.append(name)
            individual = ancestor.individual
            letter = view.letters.get(ancestor.place)
            label = (f"gen {ancestor.place.generation} #{ancestor.place.index}"
                     f"{f' [{letter}]' if letter else ''}\\nfitness {individual.fitness:.3f}, "
                     f"{plural(individual.goals, 'goal')}\\n{view.short_birth(ancestor)}")
            colour = view.colour(ancestor.place)
            style = f", fillcolor={_dot_string(colour + '33')}, color={_dot_string(colour)}" if colour else ""
            if ancestor.place == view.chosen:
                style += ", penwidth=3"
            lines.append(f"  {name} [label=\"{label}\", tooltip={_dot_string(view.birth_text(ancestor))}{style}];")
        lines.append(f"  {{ rank=same; {'; '.join(names)}; }}")
    for row in view.rows():
        for ancestor in row:
            for parent in ancestor.parents:
                lines.append(f"  {_dot_name_of(parent)} -> {_dot_name(ancestor)};")
    for rule in view.rules:
        lines.append(f"  // rule {rule.number} [{rule.letter}] {rule.text.replace(chr(10), ' ')} -- {rule.summary}")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _dot_name(ancestor: Ancestor) -> str:
    return _dot_name_of(ancestor.place)


def _dot_name_of(place: Sequence[int]) -> str:
    return f"g{place[0]}_{place[1]}"


def _dot_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'
