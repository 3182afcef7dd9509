"""Knockout (classroom mode): the class knockout's bracket, filled in live as its ties finish, on every tab's
Class tab and in the projector view; any played match watched on the tab's pitch. The teacher's Class tab
also starts a knockout (best of N, seed, ticks a half). Names are the class's own text: escaped, and a long one
ends in "..." (shown whole on hover)."""

from __future__ import annotations

from typing import Callable

import viser

from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.store import KnockoutRecord, KnockoutStatus, NotFound, StoreError
from soccer_lab.app.web.access import Forbidden, Visitor
from soccer_lab.app.web.classroom.knockout import (DEFAULT_BEST_OF, MAX_BEST_OF, bracket, champion, knockout_match,
                                                  round_name, rounds_of)
from soccer_lab.app.web.classroom.tournament import Tournament, TournamentEvent
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.words import plural
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig

NO_MATCH = "(no match played yet)"
ONE_LINE = "white-space:nowrap; overflow:hidden; text-overflow:ellipsis; min-width:0"
PROJECTOR_BRACKET_FONT_SIZE = 20  # px: the bracket read from the back of the class (four rounds fit 1280 px)
# The projector shows a bracket's last rounds, the ones a class cheers (a class of 30 has 5 rounds, and its first
# round's 16 ties would push the final off the screen at 1280 x 800); the Class tab and the CSV have them all
PROJECTOR_ROUNDS = 3
# A tie not decided by matches won says so under it.
DECIDED = {"goal difference": "level: on goal difference", "higher in the draw": "level: higher in the draw"}
WatchMatch = Callable[[Rulebase, Rulebase, tuple[str, str], int, GameConfig, Vocabulary], None]


class KnockoutPanel:
    """`on_watch(a, b, names, seed, game, vocabulary)` puts a knockout's match on the tab's pitch (the session's
    watch_match). `controls`: the teacher's Start (the Class tab's; the projector's copy shows the bracket and
    Watch only). `large`: the projector's type."""

    def __init__(self, gui: viser.GuiApi, tournament: Tournament, visitor: Visitor, vocabulary: Vocabulary, *,
                 on_watch: WatchMatch, controls: bool = True, large: bool = False):
        self.tournament = tournament
        self.knockout = tournament.knockout
        self.visitor = visitor
        self.vocabulary = vocabulary
        self.on_watch = on_watch
        self.font_size = PROJECTOR_BRACKET_FONT_SIZE if large else style.FONT_SIZE
        self.rounds_shown = PROJECTOR_ROUNDS if large else None
        self.record: KnockoutRecord | None = None
        self._matches: dict[str, tuple[int, int, int]] = {}  # the dropdown's labels: (round, tie, match)
        gui.add_markdown("**Knockout**")
        if controls and visitor.teacher:
            settings = tournament.settings
            self.best_of = gui.add_number("Best of", initial_value=DEFAULT_BEST_OF, min=1,
                                          max=MAX_BEST_OF, step=2)
            self.seed = gui.add_text("Knockout seed", "", hint="empty: a fresh seed, shown with the bracket")
            self.max_ticks = gui.add_number("Ticks a half", initial_value=min(tournament.game.max_ticks,
                                                                              settings.max_run_ticks),
                                            min=1, max=settings.max_run_ticks, step=1)
            start = gui.add_button("Start a knockout")

            @start.on_click
            def _(_: viser.GuiEvent) -> None:
                self.start()

        self.message = gui.add_html("")
        self.bracket = gui.add_html("")
        self.match = gui.add_dropdown("Match", (NO_MATCH,))
        self.watch_button = gui.add_button("Watch this match", color="gray")

        @self.watch_button.on_click
        def _(_: viser.GuiEvent) -> None:
            self.watch()

        self._remove_listener = tournament.add_listener(self._on_event)
        self.show(self.knockout.latest())

    def close(self) -> None:
        self._remove_listener()

    # ---- actions ----
    def start(self) -> None:
        seed_text = self.seed.value.strip()
        try:
            if seed_text and not seed_text.isdigit():
                raise StoreError(f"the seed is a whole number (or empty for a fresh one), not {seed_text!r}")
            self.knockout.start(self.visitor, self.tournament.entries(), best_of=int(self.best_of.value),
                                seed=int(seed_text) if seed_text else None, max_ticks=int(self.max_ticks.value))
        except (StoreError, RunStateError, Forbidden) as exc:
            self._say(f"Not started: {exc}", error=True)

    def watch(self) -> None:
        chosen = self._matches.get(self.match.value)
        if self.record is None or chosen is None:
            self._say("No match played yet to watch.", error=True)
            return
        try:
            a_name, a_text, b_name, b_text, seed, game = knockout_match(self.record, *chosen)
            a, b = (parse_rulebase(text, self.vocabulary) for text in (a_text, b_text))
        except (NotFound, StoreError, RuleSyntaxError) as exc:
            self._say(str(exc), error=True)
            return
        round_number, tie, match = chosen
        self.on_watch(a, b, (a_name, b_name), seed, game, self.vocabulary)
        where = f"{round_name(round_number, rounds_of(len(self.record.draw)))}, tie {tie}, match {match}"
        self._say(f"Watching {a_name} against {b_name} ({where}) on your pitch.")

    # ---- what everyone sees ----
    def _on_event(self, event: TournamentEvent) -> None:
        if event.kind == "knockout" and event.knockout is not None:
            self.show(event.knockout)

    def show(self, record: KnockoutRecord | None) -> None:
        self.record = record
        if record is None:
            self.bracket.content = (f'<div class="knockout" style="{style.FONT}; font-size:{self.font_size}px; '
                                    f'color:{style.MUTED}">No knockout yet.</div>')
            self._say("")
            self._list_matches(None)
            return
        self.bracket.content = bracket_html(record, self.font_size, self.rounds_shown)
        self._say(status_line(record), error=record.status in (KnockoutStatus.FAILED, KnockoutStatus.INTERRUPTED))
        self._list_matches(record)

    def _list_matches(self, record: KnockoutRecord | None) -> None:
        """The played matches in the dropdown, the newest chosen unless the user chose another."""
        self._matches = {}
        if record is not None:
            names = {place["draw"]: place["name"] for place in record.draw}
            rounds = bracket(record)
            for tie in record.ties:
                where = round_name(tie["round"], len(rounds))
                if len(rounds[tie["round"] - 1]) > 1:
                    where += f" {tie['tie']}"
                for match in tie["matches"]:
                    label = (f"{where}, match {match['match']}: {names[tie['a']]} "
                             f"{match['goals'][0]}–{match['goals'][1]} {names[tie['b']]}")
                    self._matches[label] = (tie["round"], tie["tie"], match["match"])
        self.match.visible = self.watch_button.visible = bool(self._matches)  # nothing to watch: not shown
        labels = tuple(self._matches) or (NO_MATCH,)
        chosen = self.match.value
        # The newest match stays chosen as ties finish; a match the user picked stays picked
        following = chosen == self.match.options[-1] or chosen not in self._matches
        if tuple(self.match.options) != labels:
            self.match.options = labels
        self.match.value = labels[-1] if following else chosen

    def _say(self, text: str, *, error: bool = False) -> None:
        self.message.content = (
            f'<div class="knockout-message" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{self.font_size}px; color:{style.ERROR if error else style.FIRED}">{escape(text)}</div>')


def status_line(record: KnockoutRecord) -> str:
    ties = sum(len(ties) for ties in bracket(record))
    if record.status == KnockoutStatus.PLAYING:
        return f"Knockout {record.id} is being played: {len(record.ties)} of {plural(ties, 'tie')} done …"
    if record.status == KnockoutStatus.FINISHED:
        return f"Knockout {record.id} finished: every tie played."
    return f"Knockout {record.id} {record.status}: {record.error or 'no reason given'}"


def bracket_html(record: KnockoutRecord, font_size: int, last_rounds: int | None = None) -> str:
    """The bracket: one column per round (they wrap in a narrow panel), each tie its two players with the matches
    each won; the one who went through in bold. `last_rounds`: only the last so many rounds, a line saying where
    the earlier ones are."""
    names = {place["draw"]: place["name"] for place in record.draw}
    rounds = bracket(record)
    hidden = rounds[:-last_rounds] if last_rounds is not None and len(rounds) > last_rounds else []
    earlier = ""
    if hidden:
        first, last = (round_name(ties[0]["round"], len(rounds)) for ties in (hidden[0], hidden[-1]))
        span = first if len(hidden) == 1 else f"{first} to {last}"
        earlier = (f'<div class="knockout-earlier" style="color:{style.MUTED}">{span} '
                   f'({plural(sum(len(ties) for ties in hidden), "tie")}): in the Class tab and the CSV</div>')
    won = champion(record)
    winner = (f'<div class="knockout-champion" style="font-weight:700; color:{style.FIRED}; {ONE_LINE}" '
              f'title="{escape(won["name"])}">Winner: {escape(won["name"])}</div>' if won else "")
    columns = "".join(
        f'<div class="knockout-round" style="flex:1 1 9em; min-width:0">'
        f'<div style="font-weight:700; {ONE_LINE}">{round_name(ties[0]["round"], len(rounds))}</div>'
        + "".join(_tie_html(tie, names) for tie in ties) + "</div>"
        for ties in rounds[len(hidden):])
    return (
        f'<div class="knockout" data-knockout="{record.id}" data-status="{record.status}" style="{style.FONT}; '
        f'font-size:{font_size}px; color:{style.INK}; margin-bottom:8px; padding-right:10px">'
        f'<div style="color:{style.MUTED}">Knockout {record.id}: {plural(len(record.draw), "entry", "entries")}, '
        f"best of {record.best_of}, seed {record.seed}, {record.game.get('max_ticks')} ticks a half. "
        f'<a href="/api/class/knockouts/{record.id}/matches.csv">CSV</a></div>{winner}{earlier}'
        f'<div style="display:flex; flex-wrap:wrap; gap:6px 10px; margin-top:4px">{columns}</div></div>')


def _tie_html(tie: dict, names: dict[int, str]) -> str:
    played = tie["played"]
    lines = []
    for side, place in enumerate((tie["a"], tie["b"])):
        if place is None:
            name, score = ("bye" if tie["round"] == 1 and side == 1 else "…"), ""
        else:
            name = f"{place}. {names[place]}"
            score = "" if played is None or not played["matches"] else str(played["wins"][side])
        through = played is not None and place is not None and played["winner"] == place
        colour = style.INK if played is None or through or place is None else style.MUTED
        lines.append(
            f'<div class="knockout-player" data-through="{str(through).lower()}" style="display:flex; gap:6px; '
            f'color:{colour}; font-weight:{700 if through else 400}">'
            f'<span title="{escape(name)}" style="flex:1; {ONE_LINE}">{escape(name)}</span>'
            f"<span>{score}</span></div>")
    how = DECIDED.get(played["decided_by"], "") if played is not None else ""
    if how:
        how = f'<div style="color:{style.MUTED}; font-size:0.8em; {ONE_LINE}">{how}</div>'
    state = "played" if played is not None else "waiting"
    return (f'<div class="knockout-tie" data-round="{tie["round"]}" data-tie="{tie["tie"]}" data-state="{state}" '
            f'style="border:1px solid {style.GRID}; border-radius:4px; padding:2px 6px; margin:4px 0">'
            f'{"".join(lines)}{how}</div>')
