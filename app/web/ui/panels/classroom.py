"""Class (classroom mode): enter the rules on your pitch in the class tournament, see the entries and the
latest round's table, watch any entry's game from any of the round's starts. The teacher's tab also starts
rounds, names the teacher's own entries and removes entries. Every name is shown as text (escaped)."""

from __future__ import annotations

from typing import Callable

import viser

from soccer_lab.app.web.access import Forbidden, Visitor
from soccer_lab.app.web.classroom.settings import MAX_STARTS
from soccer_lab.app.web.classroom.tournament import Tournament, TournamentEvent, entry_game
from soccer_lab.app.words import plural
from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.store import NotFound, RoundRecord, StoreError
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig

NONE = "(no round yet)"


def _entry_label(row: dict) -> str:
    return f"{row['rank']}. {row['name']} [#{row['entry_id']}]"


def _entry_id(label: str) -> int | None:
    if not label.endswith("]") or "[#" not in label:
        return None
    return int(label.rsplit("[#", 1)[1][:-1])


class ClassPanel:
    """`current()`: the rules on this tab's pitch and their name; `on_watch(rulebase, name, seed, game)` plays
    an entry's game on the pitch."""

    def __init__(self, gui: viser.GuiApi, tournament: Tournament, visitor: Visitor, vocabulary: Vocabulary, *,
                 current: Callable[[], tuple[Rulebase, str]],
                 on_watch: Callable[[Rulebase, str, int, GameConfig], None]):
        self.tournament = tournament
        self.visitor = visitor
        self.vocabulary = vocabulary
        self.current = current
        self.on_watch = on_watch
        self.round: RoundRecord | None = None
        who = "the teacher" if visitor.teacher else visitor.name
        gui.add_html(f'<div class="class-you" style="{style.FONT}; font-size:{style.FONT_SIZE}px">'
                     f"You are <b>{escape(who)}</b>.</div>")
        if visitor.teacher:
            self.entry_name = gui.add_text("Entry name (empty: the rules' name)", "")
        enter = gui.add_button("Enter the rules on my pitch")
        self.message = gui.add_html("")
        self.entries_view = gui.add_html("")
        if visitor.teacher:
            self.starts = gui.add_number("Starts per entry", initial_value=tournament.settings.starts, min=1,
                                         max=MAX_STARTS, step=1)
            start_round = gui.add_button("Start a round")
            self.to_remove = gui.add_dropdown("Entry", ("(none)",))
            remove = gui.add_button("Remove this entry", color="red")

            @start_round.on_click
            def _(_: viser.GuiEvent) -> None:
                self.start_round()

            @remove.on_click
            def _(_: viser.GuiEvent) -> None:
                self.remove_entry()

        gui.add_markdown("**Latest round**")
        self.table = gui.add_html("")
        self.watch_entry = gui.add_dropdown("Watch entry", (NONE,))
        self.watch_start = gui.add_number("From start", initial_value=1, min=1, max=MAX_STARTS, step=1)
        watch = gui.add_button("Watch this game", color="gray")

        @enter.on_click
        def _(_: viser.GuiEvent) -> None:
            self.enter_current()

        @watch.on_click
        def _(_: viser.GuiEvent) -> None:
            self.watch()

        self._remove_listener = tournament.add_listener(self._on_event)
        self.refresh_entries()
        self.show_round(tournament.latest_round())

    def close(self) -> None:
        self._remove_listener()

    # ---- actions ----
    def enter_current(self) -> None:
        rulebase, name = self.current()
        try:
            entry_name = (self.entry_name.value.strip() or name) if self.visitor.teacher else None
            entry = self.tournament.submit(self.visitor, format_rulebase(rulebase, self.vocabulary),
                                           name=entry_name, source=name)
        except (StoreError, RuleSyntaxError) as exc:
            self._say(f"Not entered: {exc}", error=True)
            return
        self._say(f"Entered as “{entry.name}” ({plural(len(rulebase), 'rule')} of {name}).")

    def start_round(self) -> None:
        try:
            started = self.tournament.start_round(self.visitor, starts=int(self.starts.value))
        except (StoreError, RunStateError, Forbidden) as exc:
            self._say(f"Not started: {exc}", error=True)
            return
        entries, starts = plural(started["entries"], "entry", "entries"), plural(started["starts"], "start")
        self._say(f"Round started: {entries} x {starts} …")

    def remove_entry(self) -> None:
        label = self.to_remove.value
        entry_id = _entry_id(label)
        if entry_id is None:
            self._say("No entry selected.", error=True)
            return
        try:
            self.tournament.remove(self.visitor, entry_id)
        except (NotFound, Forbidden) as exc:
            self._say(str(exc), error=True)
            return
        self._say(f"Removed {label.rsplit(' [#', 1)[0]}.")

    def watch(self) -> None:
        entry_id = _entry_id(self.watch_entry.value)
        if self.round is None or entry_id is None:
            self._say("No round to watch yet.", error=True)
            return
        try:
            name, text, seed, game = entry_game(self.round, entry_id, int(self.watch_start.value))
            rulebase = parse_rulebase(text, self.vocabulary)
        except (NotFound, StoreError, RuleSyntaxError) as exc:
            self._say(str(exc), error=True)
            return
        self.on_watch(rulebase, f"{name} (round {self.round.id}, start {int(self.watch_start.value)})", seed, game)
        self._say(f"Watching {name}'s game from start {int(self.watch_start.value)} of round {self.round.id}.")

    # ---- what everyone sees ----
    def _on_event(self, event: TournamentEvent) -> None:
        if event.kind == "entries":
            self.refresh_entries()
        elif event.kind == "finished":
            self.show_round(event.round)
            # the line said "A round is being played …": it must not outlive the round
            self._say(f"Round {event.round.id} finished: its table is below." if event.round is not None
                      else "The round finished.")
        elif event.kind == "started":
            self._say(f"A round is being played: {event.message} …")
        elif event.kind == "failed":  # a pupil's line said the round was being played: it is not any more
            self._say(event.message if self.visitor.teacher else "The round stopped without a table.", error=True)

    def refresh_entries(self) -> None:
        entries = self.tournament.entries()
        mine = [e for e in entries if self.visitor.is_student and e.student_id == self.visitor.student_id]
        rows = "".join(f"<li>{escape(e.name)}"
                       f'<span style="color:{style.MUTED}"> · {escape(e.source)}</span></li>' for e in entries)
        yours = ("Your entry: " + escape(mine[0].source) + f" (entered {escape(mine[0].submitted[11:19])} UTC)."
                 if mine else ("You have not entered yet." if self.visitor.is_student else ""))
        self.entries_view.content = (
            f'<div class="class-entries" style="{style.FONT}; font-size:{style.FONT_SIZE}px">'
            f"<div>{yours}</div><div><b>{plural(len(entries), 'entry', 'entries')}</b></div><ol>{rows}</ol></div>")
        if self.visitor.teacher:
            labels = tuple(f"{e.name} [#{e.id}]" for e in entries) or ("(none)",)
            if tuple(self.to_remove.options) != labels:
                self.to_remove.options = labels

    def show_round(self, record: RoundRecord | None) -> None:
        self.round = record
        if record is None:
            self.table.content = (f'<div class="class-table" style="{style.FONT}; color:{style.MUTED}">'
                                  "No round played yet.</div>")
            return
        head = "".join(f'<th style="text-align:{align}; padding:2px 6px">{title}</th>'
                       for title, align in (("#", "right"), ("Name", "left"), ("Goals", "right"),
                                            ("Fitness", "right"), ("Kicks", "right")))
        cell, number = 'style="padding:2px 6px"', 'style="padding:2px 6px; text-align:right"'
        body = "".join(
            f'<tr data-entry="{row["entry_id"]}"><td {number}>{row["rank"]}</td>'
            f"<td {cell}>{escape(row['name'])}</td><td {number}>{row['goals']}</td>"
            f"<td {number}>{row['fitness']:.3f}</td><td {number}>{row['kicks']}</td>"
            "</tr>" for row in record.results)
        self.table.content = (
            f'<div class="class-table" data-round="{record.id}" style="{style.FONT}; font-size:{style.FONT_SIZE}px; '
            'margin-bottom:10px">'
            f"<div>Round {record.id}: {plural(len(record.results), 'entry', 'entries')} × "
            f"{plural(record.starts, 'start')}, seed {record.seed}, "
            f"{escape(record.game.get('skills', ''))} skills. Fitness: the chapter's (lower is better), mean over "
            f'the starts. <a href="/api/class/rounds/{record.id}/table.csv">CSV</a></div>'
            f'<table style="border-collapse:collapse; width:100%"><thead><tr>{head}</tr></thead>'
            f"<tbody>{body}</tbody></table></div>")
        labels = tuple(_entry_label(row) for row in record.results) or (NONE,)
        self.watch_entry.options = labels
        self.watch_entry.value = labels[0]
        self.watch_start.max = record.starts

    def _say(self, text: str, *, error: bool = False) -> None:
        self.message.content = (
            f'<div class="class-message" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{style.ERROR if error else style.FIRED}">{escape(text)}</div>')
