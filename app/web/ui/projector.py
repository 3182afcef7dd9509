"""The projector view of one tab: the pitch fills the window, the score, the tick, the action and what the
player did in the world stand in large type in a band above it, and the side panels fold into their rails.
The band's other tabs hold the population grid drawn larger, the class round's table and the class knockout's
bracket (classroom mode), so a teacher can show them without leaving the view.

The side panels are the server's (app/web/ui/layout.py); folding them for one tab only sends that tab the
placement command viser's own `main_panel` handle sends (a client-scoped command for a panel every client
renders). The key "P" is the page's (app/web/api/ui_page.py, PROJECTOR_KEY_SCRIPT): it clicks the button.
"""

from __future__ import annotations

import math
from typing import Callable

import viser
from viser._gui_handles import _PlacementMixin  # the placement commands main_panel's handle sends

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.game import Game
from soccer_lab.app.web.ui.match_game import LETTERS, MatchGame
from soccer_lab.app.web.ui.panels.rules import HUNT_TEXT, parameters_text
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.app.web.ui.pitch import CAMERA_FOV, PitchView

TOGGLE_LABEL = "Projector view (P)"
LEAVE_LABEL = "Leave projector view (P)"
TOGGLE_TAB, LEAVE_TAB = "Play", "View"  # the tabs the two buttons are on


class _ClientPlacement(_PlacementMixin):
    """Placement commands for a server panel, sent to one client only (as viser's MainPanelHandle does)."""

    def __init__(self, gui: viser.GuiApi, panel_id: str):
        self._placement_uuid = panel_id
        self._placement_gui_api = gui

    def _placement_removed(self) -> bool:
        return False


class ProjectorView:
    """`right_panel_id`: the right panel's (folded with the main panel while on); `on_leave()`: the way back's
    click (the session toggles under its lock); `on_toggle()`: redraw after a switch; `on_watch(p)`: a
    match's thinking switch (0 for A, 1 for B); `on_measure()`: the
    population grid's "Measure these 12" button, here as in its panel. The band (a floating panel over the
    canvas's top PROJECTOR_BAND px) has the tabs Game (the large type), Population and, in classroom mode,
    Class; beside it a small panel holds the way back."""

    def __init__(self, client: viser.ClientHandle, pitch: PitchView, right_panel_id: str,
                 on_leave: Callable[[], None], on_toggle: Callable[[], None], on_watch: Callable[[int], None],
                 on_measure: Callable[[], None] = lambda: None):
        self.client = client
        self.pitch = pitch
        self.on = False
        self._sides = (client.gui.main_panel, _ClientPlacement(client.gui, right_panel_id))
        self._on_toggle = on_toggle
        gui = client.gui
        self.gui = gui
        # The band: the large type, and in its other tabs what the teacher opens over the pitch.
        self.band = gui.add_panel(visible=False)
        with self._band_tab("Game"):
            self.status = gui.add_html("")
        with self._band_tab("Population"):
            self.measure = gui.add_button("Measure these players", visible=False)  # never "play": tests find Play
            self.measure.on_click(lambda _: on_measure())
            self.population = gui.add_html("")
        self._population_shown: str | None = None
        self._measure_shown: tuple[str, bool] | None = None
        # Beside it, the way back.
        self.way_back = gui.add_panel(visible=False)
        with self.way_back.add_tab(LEAVE_TAB):
            leave = gui.add_button(LEAVE_LABEL)
            leave.on_click(lambda _: on_leave())
            # a match's: whose thinking the band shows (on_watch(0) for A, 1 for B)
            self.thinking = gui.add_button_group(THINKING_LABEL, LETTERS, visible=False)
            self.thinking.on_click(lambda event: on_watch(LETTERS.index(event.target.value)))

    def class_tab(self) -> viser.GuiTabHandle:
        """The band's tab the class round's table goes in (classroom mode)."""
        return self._band_tab("Class")

    def knockout_tab(self) -> viser.GuiTabHandle:
        """The band's tab the class knockout's bracket goes in (classroom mode)."""
        return self._band_tab("Knockout")

    def _band_tab(self, name: str) -> viser.GuiTabHandle:
        """A tab of the band whose buttons, fields and their labels a class reads from the back of the room.
        viser draws only the shown tab, so each carries the style's marker."""
        tab = self.band.add_tab(name)
        with tab:
            self.gui.add_html(BAND_CONTROLS_STYLE)
        return tab

    def toggle(self) -> None:
        self.on = not self.on
        for side in self._sides:
            if self.on:
                side.minimize()
            else:
                side.expand()
        self.band.visible = self.way_back.visible = self.on
        if self.on:
            self._place()
        self.fit_camera()
        self._on_toggle()

    def canvas_changed(self) -> None:
        """The canvas took a new shape (a panel folded, a window resized): the band and the pitch follow."""
        if self.on:
            self._place()
        self.fit_camera()

    def _place(self) -> None:
        gap, way_back = style.PROJECTOR_GAP, style.PROJECTOR_WAY_BACK_WIDTH
        width = self.client.camera.image_width or 960
        self.band.float(x=gap, y=gap, width=max(width - way_back - 3 * gap, 320))
        self.way_back.float(x=-gap, y=gap, width=way_back)

    def fit_camera(self) -> None:
        """The whole pitch in view; in the projector view, its lines below the band (which may cover the grass's
        margin above them): the pitch as large as the rest of the canvas allows."""
        camera = self.client.camera
        if not self.on or camera.image_height <= style.PROJECTOR_BAND:
            self.pitch.fit_camera(camera)
            return
        self.pitch.fit_camera(camera)  # lens, far plane, up: as in the panels' view
        band = style.PROJECTOR_BAND / camera.image_height  # of the canvas's height
        g, margin = self.pitch.geometry, style.PITCH_MARGIN
        grass_length = 2 * (g.half_length + margin) + g.goal_depth
        below_band = 2 * g.half_width + margin  # metres from the top line to the grass's bottom edge
        half_height = max(below_band / (1.0 - band), grass_length / camera.aspect) * 1.01 / 2  # the canvas's
        distance = half_height / math.tan(CAMERA_FOV / 2)
        # The middle of those metres (scene y = -margin / 2: the scene's y is the world's, flipped) in the
        # middle of the canvas under the band.
        centre = -margin / 2 + half_height * band
        camera.far = distance * 2
        camera.position = (g.goal_depth / 2, centre, distance)
        camera.look_at = (g.goal_depth / 2, centre, 0.0)

    def show(self, game: Game | MatchGame) -> None:
        match = isinstance(game, MatchGame)
        if self.thinking.visible != match:
            self.thinking.visible = match
        if not self.on:
            return
        html = match_projector_html(game) if match else projector_html(game)
        if self.status.content != html:
            self.status.content = html

    def show_population(self, grid_html: str, measure: tuple[str, bool] | None = None) -> None:
        """The population grid, larger than in its panel (style.PROJECTOR_ZOOM) and in more columns (the panel's
        three made four rows, the last below a 1280 x 800 window); above it the panel's button (`measure`: its
        label and whether it is disabled; None: hidden), so the class's figures need no way back."""
        if not self.on:
            return
        if measure != self._measure_shown:
            self._measure_shown = measure
            self.measure.visible = measure is not None
            if measure is not None:
                self.measure.label, self.measure.disabled = measure
        if grid_html == self._population_shown:
            return
        self._population_shown = grid_html
        self.population.content = (
            f"<style>.projector-population .population {{grid-template-columns: "  # over the grid's own inline columns
            f"repeat({style.PROJECTOR_POPULATION_COLUMNS}, 1fr) !important}}</style>"
            f'<div class="projector-population" style="zoom:{style.PROJECTOR_ZOOM}">{grid_html}</div>')


def projector_html(game: Game) -> str:
    """Goals, tick, the action and what the player did in the world, in type a class reads from the back."""
    s, inference = game.state, game.inference()
    selected = inference.selected
    action = (f"{escape(game.vocabulary.display(selected.action))} "
              f'<span style="font-weight:400">{escape(parameters_text(game.vocabulary, selected.parameters))}</span>'
              if selected is not None else escape(HUNT_TEXT))
    outcome = game.outcome_text()
    refused = game.outcome_refused()
    world = f"Then in the world: {outcome}" if outcome is not None else "Then in the world: nothing yet."
    over = ""
    if game.done:
        over = (f'<span class="projector-over" style="color:{style.ERROR}"> · game over: '
                f"{escape(game.end_sentence())}</span>")
    big = style.PROJECTOR_FONT_SIZE
    return (
        f'<div class="projector-status" data-tick="{s.tick}" style="{style.FONT}; color:{style.INK}; '
        f'font-size:{big}px; line-height:1.25">'
        f'<div style="{ONE_LINE}"><b class="projector-score">Goals {s.goals}</b> <span class="projector-tick">· tick '
        f'{s.tick} / {game.config.max_ticks} ·</span> <span class="projector-action" style="font-weight:700; '
        f'color:{style.SELECTED}">{action}</span>{over}</div>'
        f'<div class="projector-world" title="{escape(world)}" style="{ONE_LINE}; font-weight:600; '
        f'color:{style.ERROR if refused else style.FIRED}">{escape(world)}</div></div>'
    )


def match_projector_html(match: MatchGame) -> str:
    """The score with both names in their colours, the half and the tick; then whose thinking, the action it chose
    and what it then did (or half time, full time)."""
    s, inference = match.state, match.inference()
    selected = inference.selected
    action = (f"{escape(match.vocabulary.display(selected.action))} "
              f"{escape(parameters_text(match.vocabulary, selected.parameters))}"
              if selected is not None else "no rule fired: hunts")
    outcome = match.outcome_text()
    pause = match.break_sentence()
    who = LETTERS[match.watched]
    second = pause if pause else f"{who} thinks: {action}" + (f" · then: {outcome}" if outcome else "")
    colour = style.ERROR if pause or match.outcome_refused() else style.SELECTED
    big = style.PROJECTOR_FONT_SIZE
    return (
        f'<div class="projector-status projector-match" data-tick="{s.tick}" data-half="{s.half}" '
        f'data-watched="{who}" style="{style.FONT}; color:{style.INK}; font-size:{big}px; line-height:1.25">'
        f'<div style="{ONE_LINE}">{match.score_html(big)} <span class="projector-tick">· {match.clock()}</span></div>'
        f'<div class="projector-world" title="{escape(second)}" style="{ONE_LINE}; font-weight:600; '
        f'color:{colour}">{escape(second)}</div></div>'
    )


THINKING_LABEL = "Show the thinking of"
# The band's controls in large type (viser draws them at 12-13 px, unreadable from the back of a room): the
# match chosen, the buttons. Only the band's panel holds the marker: the side panels and the way back (the
# teacher's, at the laptop) keep viser's type.
_BAND = "[data-dock-group]:has(.projector-controls)"
BAND_CONTROLS_STYLE = (
    '<span class="projector-controls"></span><style>'
    f"{_BAND} .mantine-Button-root {{--button-height:auto; height:auto; min-height:40px; padding:4px 10px}}"
    f"{_BAND} .mantine-Button-inner {{height:auto}}"
    f"{_BAND} .mantine-Button-label {{font-size:{style.PROJECTOR_CONTROL_FONT_SIZE}px; white-space:normal; line-height:1.2}}"
    f"{_BAND} :is(input, select, .mantine-InputWrapper-label, label) "
    f"{{font-size:{style.PROJECTOR_CONTROL_FONT_SIZE}px !important}}"
    f"{_BAND} :is(input, select) {{height:auto !important; min-height:36px !important}}"
    "</style>")

# Each of the band's two lines stays one line: a longer sentence wrapped, the band grew over the pitch's lines
# (the camera leaves PROJECTOR_BAND px for it); what does not fit ends in "..." and shows whole on hover.
ONE_LINE = "white-space:nowrap; overflow:hidden; text-overflow:ellipsis"


# The page's key for the view (viser has no keys of its own): "P" clicks the button that enters or leaves it,
# first opening the tab it is on (viser mounts only the open tab), unless the user is typing (a rule, a name).
PROJECTOR_KEY_SCRIPT = """
document.addEventListener("keydown", (event) => {
  if (event.key !== "p" && event.key !== "P") return;
  if (event.ctrlKey || event.metaKey || event.altKey || event.repeat) return;
  const typing = event.target;
  if (typing && (typing.isContentEditable || /^(INPUT|TEXTAREA|SELECT)$/.test(typing.tagName))) return;
  const on = document.querySelector(".projector-status") !== null;
  const [label, tab] = on ? [%r, %r] : [%r, %r];
  const find = (selector, text) => [...document.querySelectorAll(selector)].find((e) => e.textContent.trim() === text);
  event.preventDefault();
  const button = find("button", label);
  if (button) { button.click(); return; }
  const opener = find('[role="tab"]', tab);
  if (opener) { opener.click(); setTimeout(() => { const b = find("button", label); if (b) b.click(); }, 150); }
});
""" % (LEAVE_LABEL, LEAVE_TAB, TOGGLE_LABEL, TOGGLE_TAB)
