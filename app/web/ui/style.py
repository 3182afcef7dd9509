"""Every tunable of the UI's look and pacing in one place: colours, sizes, frame rate, speeds.

Sizes are chosen for a projector: large type, thick lines, strong contrast.
"""

from __future__ import annotations

FRAME_RATE = 30.0  # at most this many frames a second go to the browser (faster games skip ticks)
ALL_TABS_FRAME_RATE = 100.0  # frames a second all tabs together: past it each tab draws fewer (frame_share.py)
DEFAULT_SPEED = 2.0  # times real time (WorldConfig.tick_seconds per tick at 1x): lively yet watchable
SPEED_RANGE = (0.25, 20.0)
DEFAULT_SEED = 1

# Player and ball are drawn larger than life so they read on a projector; the legend says so.
PLAYER_DRAW_RADIUS = 1.6
BALL_DRAW_RADIUS = 0.9
VIEW_CONE_LENGTH = 30.0  # the view is unbounded in distance; the cone shows its angle
FACING_LINE_REACH = 1.9  # the facing line ends this many player radii from the centre
PITCH_MARGIN = 5.0  # grass beyond the lines, metres
GRASS_STRIPES = 12  # mown stripes across the pitch's length
LINE_WIDTH = 0.3  # metres: painted lines, wider than FIFA's 12 cm to read on a projector
NET_LINE_WIDTH = 0.1
POST_DRAW_RADIUS = 0.4
TRAIL_THICKNESS = 0.42  # the ball's trail (a line drawn by the browser), in viser's line units
# Resolution of the pitch's pictures (pixels per metre): sharp on a 1920-pixel-wide projector.
FIELD_PIXELS_PER_METRE = 14.0
BODY_PIXELS_PER_METRE = 24.0
CONE_PIXELS_PER_METRE = 6.0

GRASS = (46, 125, 50)
GRASS_STRIPE = (56, 142, 60)
LINE = (245, 245, 245)
PLAYER = (25, 118, 210)
OPPONENT = (211, 47, 47)  # a match's second player (B), beside the first (A) in PLAYER's blue
PLAYER_FACING = (255, 255, 255)
BALL = (255, 193, 7)
BALL_TRAIL = (255, 224, 130)
VIEW_CONE = (255, 255, 255)
VIEW_CONE_OPACITY = 0.18
GOAL_NET = (230, 230, 230)
# Around the grass: the canvas's background, and the frame that hides any drawing beyond the grass (the view
# cone, the trail, an arrow) so nothing is drawn off the pitch. Dark, so the pitch stands out on a projector.
STADIUM = (38, 50, 56)
# What the player did this tick (app/web/ui/command_mark.py): arrows, arcs, a red dashed line for what was missing.
KICK_MARK = (255, 111, 0)
DASH_MARK = (255, 255, 255)
TURN_MARK = (129, 212, 250)
REFUSED_MARK = (211, 47, 47)
COMMAND_MARK_THICKNESS = 0.6  # metres, as the trail's
COMMAND_LABEL_HEIGHT = 3.6  # metres: the label's letters scale with the pitch (about 12 px at 1280 x 800)
COMMAND_LABEL_CHARACTER = 0.5  # a character's width over the height, with the box's padding (measured on a screenshot: 0.44)

# Panel palette (HTML/SVG): hex strings.
INK = "#1f2933"
MUTED = "#9aa5b1"
GRID = "#e4e7eb"
ACCENT = "#1976d2"
BRAND = (25, 118, 210)  # ACCENT as RGB: the theme's colour (buttons, selected tabs)
FIRED = "#2e7d32"
SELECTED = "#e65100"
ERROR = "#c62828"
CLIP_FILL = "#ff9800"
FONT = "font-family: Inter, 'Segoe UI', Helvetica, Arial, sans-serif"
FONT_SIZE = 15  # px, panel body text
SMALL_FONT_SIZE = 12

# One colour per action, for the policy map and the rule list (index = vocabulary action order).
ACTION_COLOURS = (
    "#8e24aa", "#3949ab", "#e53935", "#00897b", "#1e88e5",
    "#43a047", "#fb8c00", "#f4511e", "#6d4c41", "#9e9e9e",
)
HUNT_COLOUR = "#cfd8dc"

USAGE_GAMES = 20  # games the rule usage and the Simplify button's check play (from the pitch's seed)
USAGE_BAR_WIDTH = 50  # px: the share of ticks a rule won, beside its strength bar
NEVER_WON_OPACITY = 0.45  # a rule that never won in those games is greyed

LEFT_PANEL_WIDTH = 380
# The rule text's box is as high as the rules on the pitch need (lines of RULE_EDITOR_LINE_CHARACTERS, wrapped,
# plus room to type), between RULE_EDITOR_MIN_LINES lines and RULE_EDITOR_MAX_HEIGHT: Apply stays in view.
RULE_EDITOR_LINE_CHARACTERS = 50  # at 14 px the 380 px panel fits about 57; fewer, so nothing is cut
RULE_EDITOR_MIN_LINES = 6
RULE_EDITOR_MAX_HEIGHT = "70vh"
RULE_EDITOR_LINE_HEIGHT = 1.45  # em
RIGHT_PANEL_WIDTH = 500
# The projector view (app/web/ui/projector.py): a band of large type above the pitch, which fills the rest.
PROJECTOR_FONT_SIZE = 26  # px: the score, the tick, the action and what the player did
PROJECTOR_CONTROL_FONT_SIZE = 20  # px: the buttons, fields and their labels in the projector view
PROJECTOR_BAND = 130  # px of the canvas's height above the pitch, for the band's floating panel
PROJECTOR_GAP = 8  # px between the band's panel and the canvas's edges
PROJECTOR_WAY_BACK_WIDTH = 250  # px: the panel beside the band, with the way back
PROJECTOR_ZOOM = 1.6  # the population grid in the projector view, this many times its size in the panel
PROJECTOR_POPULATION_COLUMNS = 4  # the grid's columns there: its 12 small pitches in 3 rows, all in a 1280 x 800 window
POLICY_REFRESH_SECONDS = 0.2  # the policy map's marker follows the player at 5 Hz (the map is ~12 kB)
POPULATION_GRID = (3, 4)  # columns, rows of small pitches in the population view
POPULATION_REPLAY_SHARE = 0.05  # of the wall time, at most, re-playing the population view's players
POPULATION_REPLAY_SAVED_SECONDS = 60.0  # re-play time saved up at most, in wall seconds (share of them)
POPULATION_REFRESH_SECONDS = 0.1  # the small pitches redraw at 10 Hz
MINI_PITCH_WIDTH = 160  # px
MINI_PITCH_MARGIN = 3.0  # grass beyond the lines, metres
MINI_PITCH_GRASS = "#2e7d32"
MINI_PITCH_DONE = "#607d8b"  # grey grass: the game is over
MINI_PITCH_PLAYER = "#64b5f6"  # lighter than PLAYER, to read on the small dark pitch
BALL_HEX = "#ffc107"  # BALL as a hex string for SVG
PLOT_PADDING = (14, 14, 0, 0)  # px above and right of a plot: the top tick's label (1) is not cut off
# The steps uPlot may put between a plot's generation ticks: whole generations only (never "0.2")
GENERATION_STEPS = (1, 2, 5, 10, 20, 50, 100, 200, 500, 1_000, 2_000, 5_000, 10_000, 20_000, 50_000, 100_000)
SCROLLBAR_ROOM = "padding-right:12px"  # a panel's scrollbar lies over its content's right edge
