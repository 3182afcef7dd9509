"""The top-down pitch in viser's 3D scene: the field (lines, goal), player with facing and view cone,
ball and trail, each a flat picture (see pitch_pictures.py) but the trail, and what the player did this
tick (an arrow or arc, and a label: command_mark.py). A match (match_game.py) lays a pitch with a goal at
each end over the field and shows its second player in its own colour, each player's name under it with
the way it attacks; the view cone and the mark are the player's whose thinking the panels show. The pictures are the server's, sent once to every
tab (draw_pitch); each tab moves the frames they hang from (PitchView).

Nothing is drawn off the grass: the canvas around it is the STADIUM colour, and a frame of that colour
lies above every drawing but the bodies, hiding what would reach past the grass (the view cone, the
trail, an arrow). The labels, drawn over everything, are placed on the grass.

World coordinates are the simulator's (x toward the attacked goal, y to the player's right when it
faces +x, as in rcssserver). Seen from above with x to the right, +y points down the screen, so the
scene stores (x, -y) and turns angles the other way. Drawing only: the session feeds it frames.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import viser

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.command_mark import LABELS, CommandMark, PlacedShape, label_half_width, mark_shapes
from soccer_lab.app.web.ui.pitch_pictures import (Picture, ball_picture, cone_picture, field_picture, player_picture,
                                                  solid_picture)
from soccer_lab.soccer.config import WorldConfig

CAMERA_FOV = math.radians(20.0)  # a narrow lens from far above looks orthographic
FIELD_NODE = "/field"
PLAYER_NODE = "/pitch/player"
CONE_NODES = {False: f"{PLAYER_NODE}/view_cone_no_ball", True: f"{PLAYER_NODE}/view_cone_ball"}  # ball seen?
BALL_NODE = "/pitch/ball"
TRAIL_NODE = "/pitch/trail"
COMMAND_NODE = "/pitch/command"  # + "_" + a mark shape's name: the frame its lines hang from
COMMAND_LABEL_NODE = "/pitch/command_label"  # + "_" + the label's index in LABELS
FRAME_NODE = "/stadium"  # the frame around the grass
MATCH_FIELD_NODE = "/match_field"  # a match's pitch, a goal at each end, over the field (hidden but in a match)
OPPONENT_NODE = "/pitch/opponent"  # a match's second player
OPPONENT_CONE_NODES = {seen: name.replace(PLAYER_NODE, OPPONENT_NODE, 1) for seen, name in CONE_NODES.items()}
NAME_LABEL_NODES = ("/pitch/player_name", "/pitch/opponent_name")
Z_MATCH_FIELD = -0.04  # just over the field
Z_WATCHED = 0.01  # a match's second player lies this much over A when watched, under it otherwise
NAMES_GAP = 2.0  # metres between two players' names side by side: "A →" and "← B", never "A →← B"
Z_GRASS, Z_CONE, Z_TRAIL, Z_COMMAND, Z_FRAME, Z_BODY = -0.05, 0.02, 0.03, 0.04, 0.1, 0.2
Z_BALL = 0.25  # over the player: a ball at its feet stays in sight
FRAME_WIDTH = 1000.0  # metres: far past any canvas's edge


@dataclass(frozen=True)
class PitchGeometry:
    half_length: float
    half_width: float
    goal_half_width: float
    goal_depth: float
    view_half_angle: float  # degrees
    ball_speed_max: float  # m/tick: a longer step between trail points is a restart, not a flight

    @classmethod
    def from_world(cls, world: WorldConfig) -> "PitchGeometry":
        c = world.constants()
        return cls(c.half_length, c.half_width, c.goal_half_width, c.goal_depth, c.view_half_angle, c.ball_speed_max)

    @property
    def grass(self) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1): the grass, the lines and the goal with a margin, in world metres."""
        margin = style.PITCH_MARGIN
        return (-self.half_length - margin, self.half_length + self.goal_depth + margin,
                -self.half_width - margin, self.half_width + margin)

    @property
    def goal(self) -> tuple[float, float]:
        return (self.half_length, 0.0)


@dataclass(frozen=True)
class PitchFrame:
    player: tuple[float, float]
    facing: float  # radians, from +x toward +y (the player's right)
    ball: tuple[float, float]
    trail: np.ndarray  # float[N, 2], oldest first
    ball_visible: bool
    command: CommandMark | None = None  # what the player did this tick (None: nothing yet)
    match: MatchMarks | None = None  # a match's second player (None: one player on the pitch)


@dataclass(frozen=True)
class MatchMarks:
    """A match's second player (B; PitchFrame's player is A), the names shown under A and B, and whose view cone
    is shown (0: A's, 1: B's: the player whose thinking the panels show)."""

    player: tuple[float, float]
    facing: float  # radians
    ball_visible: bool  # whether B sees the ball
    labels: tuple[str, str]
    watched: int


def to_scene(x: float, y: float, z: float = 0.0) -> tuple[float, float, float]:
    return (x, -y, z)


def yaw_quaternion(facing: float) -> tuple[float, float, float, float]:
    half = -facing / 2.0  # the flipped y axis turns world angles the other way in the scene
    return (math.cos(half), 0.0, 0.0, math.sin(half))


def mirrored_yaw_quaternion(facing: float) -> tuple[float, float, float, float]:
    """Flipped across the local x axis (y and z negated: the flat shapes stay flat), then turned to `facing`."""
    w, _, _, z = yaw_quaternion(facing)
    return (0.0, w, z, 0.0)


def scene_segments(segments: np.ndarray, z: float) -> np.ndarray:
    """float32[N, 2, 3]: world segments [N, 2, 2] in the scene at height z."""
    points = np.zeros((len(segments), 2, 3), np.float32)
    points[..., 0] = segments[..., 0]
    points[..., 1] = -segments[..., 1]
    points[..., 2] = z
    return points


def show_picture(scene: viser.SceneApi, name: str, picture: Picture, z: float, **kwargs) -> viser.ImageHandle:
    """`picture` as a flat quad at height z, centred where it belongs. Every picture is symmetric about
    its x axis (the pitch; the player, ball and view facing +x), so the scene's flipped y needs no
    flipping of its rows."""
    x, y = picture.centre
    return scene.add_image(name, picture.pixels, picture.size[0], picture.size[1], format="png",
                           position=to_scene(x, y, z), cast_shadow=False, receive_shadow=False, **kwargs)


def draw_pitch(scene: viser.SceneApi, geometry: PitchGeometry, start: PitchFrame) -> None:
    """Every picture of the pitch, the same for every tab, drawn once into the server's scene, which
    viser sends each tab as it connects, before the tab's session exists: the field, the player, its
    view cones, the ball and the marks' line shapes (command_mark.py), hung from frames placed as every
    new tab's game starts (the demo player, the first seed). A tab's session then moves frames of its own with the same names (PitchView): in
    the browser a tab's node stands in for the server's of its name, the pictures hanging from it.
    So a new tab draws the whole pitch from the first message, and no tab sends a picture again."""
    # Unlit: no environment map (its loading keeps the canvas transparent for seconds) and no lights
    # (the pictures carry their own colours).
    scene.configure_environment_map(None)
    scene.configure_default_lights(enabled=False, cast_shadow=False)
    scene.set_background_image(solid_picture(style.STADIUM))
    show_picture(scene, FIELD_NODE, field_picture(geometry), Z_GRASS)
    draw_frame(scene, geometry)
    PitchView(scene, geometry).show(start)
    show_picture(scene, f"{PLAYER_NODE}/body", player_picture(), 0.0)
    for seen, name in CONE_NODES.items():
        colour = style.BALL if seen else style.VIEW_CONE
        show_picture(scene, f"{name}/picture", cone_picture(geometry.view_half_angle, colour), 0.0)
    show_picture(scene, f"{BALL_NODE}/picture", ball_picture(), 0.0)
    for name, (segments, colour) in mark_shapes().items():
        scene.add_line_segments(f"{COMMAND_NODE}_{name}/lines", scene_segments(segments, 0.0),
                                colors=colour, thickness=style.COMMAND_MARK_THICKNESS)
    show_picture(scene, f"{MATCH_FIELD_NODE}/picture", field_picture(geometry, both_goals=True), Z_MATCH_FIELD)
    show_picture(scene, f"{OPPONENT_NODE}/body", player_picture(colour=style.OPPONENT), 0.0)
    for seen, name in OPPONENT_CONE_NODES.items():
        colour = style.BALL if seen else style.VIEW_CONE
        show_picture(scene, f"{name}/picture", cone_picture(geometry.view_half_angle, colour), 0.0)


def draw_frame(scene: viser.SceneApi, geometry: PitchGeometry) -> None:
    """Four wide bands of the stadium's colour around the grass, above every drawing but the bodies."""
    x0, x1, y0, y1 = geometry.grass
    w = FRAME_WIDTH
    bands = {"left": (x0 - w / 2, (y0 + y1) / 2, w, y1 - y0 + 2 * w),
             "right": (x1 + w / 2, (y0 + y1) / 2, w, y1 - y0 + 2 * w),
             "top": ((x0 + x1) / 2, y0 - w / 2, x1 - x0, w),
             "bottom": ((x0 + x1) / 2, y1 + w / 2, x1 - x0, w)}
    pixels = solid_picture(style.STADIUM)
    for name, (cx, cy, width, height) in bands.items():
        show_picture(scene, f"{FRAME_NODE}/{name}", Picture(pixels, (cx, cy), (width, height)), Z_FRAME)


class PitchView:
    """The frames that move on a pitch (player with facing and view cones, ball, the marks' shapes), the mark's
    labels and the ball's trail; the pictures and shapes hang from the frames (draw_pitch). `show(frame)` sends
    only what changed, and while a game plays only poses and visibilities (command_mark.py says why), but the
    trail's points."""

    def __init__(self, scene: viser.SceneApi, geometry: PitchGeometry):
        self.geometry = geometry
        self.player = scene.add_frame(PLAYER_NODE, show_axes=False, position=to_scene(0, 0, Z_BODY))
        # One cone for each colour, the one shown switched: a colour change would be a new picture.
        self.cones = {seen: scene.add_frame(name, show_axes=False, position=(0.0, 0.0, Z_CONE - Z_BODY))
                      for seen, name in CONE_NODES.items()}
        self.ball = scene.add_frame(BALL_NODE, show_axes=False, position=to_scene(0, 0, Z_BALL))
        self.trail = scene.add_line_segments(
            TRAIL_NODE, np.zeros((1, 2, 3), np.float32), colors=style.BALL_TRAIL, thickness=style.TRAIL_THICKNESS,
            visible=False,
        )
        self._trail_shown: np.ndarray | None = None
        # Every mark shape's frame and every label, hidden: a tick shows some and moves them.
        self.mark_frames = {name: scene.add_frame(f"{COMMAND_NODE}_{name}", show_axes=False, visible=False)
                            for name in mark_shapes()}
        self.command_labels = {text: scene.add_label(
            f"{COMMAND_LABEL_NODE}_{i}", text, position=to_scene(0, 0, Z_BODY), visible=False, font_size_mode="scene",
            font_scene_height=style.COMMAND_LABEL_HEIGHT, anchor="bottom-center") for i, text in enumerate(LABELS)}
        self._command_shown: CommandMark | None = None
        # A match's pitch and second player, hidden until a match is shown (their pictures are draw_pitch's).
        self.match_field = scene.add_frame(MATCH_FIELD_NODE, show_axes=False, visible=False)
        self.opponent = scene.add_frame(OPPONENT_NODE, show_axes=False, position=to_scene(0, 0, Z_BODY), visible=False)
        self.opponent_cones = {seen: scene.add_frame(name, show_axes=False, position=(0.0, 0.0, Z_CONE - Z_BODY))
                               for seen, name in OPPONENT_CONE_NODES.items()}
        self.names = tuple(scene.add_label(node, "", position=to_scene(0, 0, Z_BODY), visible=False,
                                           font_size_mode="scene", font_scene_height=style.COMMAND_LABEL_HEIGHT,
                                           anchor="bottom-center") for node in NAME_LABEL_NODES)
        self._match_shown = False

    def show(self, frame: PitchFrame) -> None:
        self.player.position = to_scene(*frame.player, Z_BODY)
        self.player.wxyz = yaw_quaternion(frame.facing)
        self.ball.position = to_scene(*frame.ball, Z_BALL)
        match = frame.match
        for seen, cone in self.cones.items():
            cone.visible = seen == frame.ball_visible and (match is None or match.watched == 0)
        self._show_match(frame, match)
        self._show_trail(frame.trail)
        self._show_command(frame.command)

    def _show_match(self, frame: PitchFrame, match: MatchMarks | None) -> None:
        if (match is not None) != self._match_shown:
            self._match_shown = match is not None
            self.match_field.visible = self.opponent.visible = self._match_shown
            for label in self.names:
                label.visible = self._match_shown
        if match is None:
            return
        # the watched player over the other when they overlap (both are drawn larger than life)
        self.opponent.position = to_scene(*match.player, Z_BODY + (Z_WATCHED if match.watched == 1 else -Z_WATCHED))
        self.opponent.wxyz = yaw_quaternion(match.facing)
        for seen, cone in self.opponent_cones.items():
            cone.visible = seen == match.ball_visible and match.watched == 1
        places = name_places(self.geometry.grass, (frame.player, match.player), match.labels)
        for label, text, at in zip(self.names, match.labels, places):
            if label.text != text:
                label.text = text
            label.position = to_scene(*at, Z_BODY)

    def _show_command(self, mark: CommandMark | None) -> None:
        shown = self._command_shown
        if shown == mark:
            return
        self._command_shown = mark
        placed = {p.shape: p for p in mark.shapes} if mark is not None else {}
        for old in (shown.shapes if shown is not None else ()):
            if old.shape not in placed:
                self.mark_frames[old.shape].visible = False
        for name, shape in placed.items():
            self._place(self.mark_frames[name], shape)
        label = mark.label if mark is not None else None
        if shown is not None and shown.label != label:
            self.command_labels[shown.label].visible = False
        if mark is not None:
            handle = self.command_labels[mark.label]
            handle.position = to_scene(*mark.label_at, Z_BODY)
            handle.visible = True

    @staticmethod
    def _place(frame: viser.FrameHandle, shape: PlacedShape) -> None:
        heading = math.radians(shape.heading)
        frame.position = to_scene(*shape.at, Z_COMMAND)
        frame.wxyz = mirrored_yaw_quaternion(heading) if shape.mirrored else yaw_quaternion(heading)
        frame.visible = True

    def _show_trail(self, trail: np.ndarray) -> None:
        # The one content change while playing: the trail is history up to the ball, so a frame that draws
        # the ball's new place before the trail's new end shows nothing wrong.
        if self._trail_shown is not None and np.array_equal(trail, self._trail_shown):
            return  # the ball rests: nothing to send
        self._trail_shown = trail.copy()
        points = np.stack([trail[:-1], trail[1:]], axis=1) if len(trail) >= 2 else np.zeros((0, 2, 2))
        # The ball jumps to the centre line after a goal: no trail segment across that jump.
        # A resting ball's ticks add no segment.
        step = np.linalg.norm(points[:, 1] - points[:, 0], axis=1)
        points = points[(step > 0) & (step <= self.geometry.ball_speed_max * 1.01)]
        if len(points):
            self.trail.points = scene_segments(points, Z_TRAIL)
        self.trail.visible = len(points) > 0

    def fit_camera(self, camera: viser.CameraHandle) -> None:
        """Look straight down on the whole pitch, sized to the client's canvas."""
        g = self.geometry
        half_x = g.half_length + style.PITCH_MARGIN + g.goal_depth
        half_y = g.half_width + style.PITCH_MARGIN
        aspect = camera.aspect if camera.aspect > 0 else 16 / 9
        half_height = max(half_y, half_x / aspect) * 1.02
        distance = half_height / math.tan(CAMERA_FOV / 2)
        camera.fov = CAMERA_FOV
        camera.far = distance * 2
        camera.up_direction = (0.0, 1.0, 0.0)
        camera.position = (g.goal_depth / 2, 0.0, distance)
        camera.look_at = (g.goal_depth / 2, 0.0, 0.0)


def name_places(grass: tuple[float, float, float, float], players: tuple[tuple[float, float], ...],
                labels: tuple[str, ...]) -> list[tuple[float, float]]:
    """Where the names of a match's two players go (each label's bottom centre): under each player (the mark's
    label goes above it), whole on the grass; when the two would overlap (the players close), side by side, B's
    on the side away from A's."""
    x0, x1, _, y1 = grass
    rooms = [label_half_width(f"{label}  ") for label in labels]  # an arrow is wider than a letter
    places = []
    for (px, py), room in zip(players, rooms):
        y = py + style.PLAYER_DRAW_RADIUS + 1.0 + style.COMMAND_LABEL_HEIGHT
        if y > y1 - 0.5:  # no room below: above the player
            y = py - style.PLAYER_DRAW_RADIUS - 1.0
        places.append((min(max(px, x0 + room), x1 - room), y))
    (ax, ay), (bx, by) = places
    apart = rooms[0] + rooms[1] + NAMES_GAP
    if abs(ax - bx) < apart and abs(ay - by) < style.COMMAND_LABEL_HEIGHT:
        side = 1.0 if bx >= ax else -1.0
        if not x0 + rooms[1] <= ax + side * apart <= x1 - rooms[1]:  # no room on that side: the other
            side = -side
        places[1] = (ax + side * apart, ay)
    return places
