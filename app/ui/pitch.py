"""The top-down pitch in viser's 3D scene: lines, goal, player with facing and view cone, ball and trail.

World coordinates are the simulator's (x toward the attacked goal, y to the player's right when it
faces +x, as in rcssserver). Seen from above with x to the right, +y points down the screen, so the
scene stores (x, -y) and turns angles the other way. Drawing only: the session feeds it frames.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import viser

from app.pitch_markings import CENTRE_CIRCLE_RADIUS, GOAL_AREA, PENALTY_AREA
from app.ui import style
from soccer.config import WorldConfig

CAMERA_FOV = math.radians(20.0)  # a narrow lens from far above looks orthographic
CIRCLE_SEGMENTS = 64
Z_GRASS, Z_LINES, Z_CONE, Z_TRAIL, Z_BODY = -0.05, 0.01, 0.02, 0.03, 0.2


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


@dataclass(frozen=True)
class PitchFrame:
    player: tuple[float, float]
    facing: float  # radians, from +x toward +y (the player's right)
    ball: tuple[float, float]
    trail: np.ndarray  # float[N, 2], oldest first
    ball_visible: bool


def to_scene(x: float, y: float, z: float = 0.0) -> tuple[float, float, float]:
    return (x, -y, z)


def yaw_quaternion(facing: float) -> tuple[float, float, float, float]:
    half = -facing / 2.0  # the flipped y axis turns world angles the other way in the scene
    return (math.cos(half), 0.0, 0.0, math.sin(half))


def _segments(points: list[tuple[float, float]], closed: bool = False) -> list[tuple[tuple, tuple]]:
    pairs = list(zip(points, points[1:]))
    if closed:
        pairs.append((points[-1], points[0]))
    return pairs


def _circle(cx: float, cy: float, radius: float, start: float = 0.0, end: float = 2 * math.pi) -> list:
    n = max(4, int(CIRCLE_SEGMENTS * (end - start) / (2 * math.pi)))
    return [(cx + radius * math.cos(start + (end - start) * i / n), cy + radius * math.sin(start + (end - start) * i / n))
            for i in range(n + 1)]


def marking_segments(geometry: PitchGeometry) -> np.ndarray:
    """Every pitch line as segments float[N, 2, 3] in scene coordinates."""
    hl, hw = geometry.half_length, geometry.half_width
    pairs = _segments([(-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw)], closed=True)
    pairs += [((0.0, -hw), (0.0, hw))]
    pairs += _segments(_circle(0.0, 0.0, CENTRE_CIRCLE_RADIUS))
    for side in (-1.0, 1.0):
        for depth, width in (PENALTY_AREA, GOAL_AREA):
            line = side * hl
            inner = side * (hl - depth)
            pairs += _segments([(line, -width / 2), (inner, -width / 2), (inner, width / 2), (line, width / 2)])
    goal = geometry.goal_half_width
    pairs += _segments([(hl, -goal), (hl + geometry.goal_depth, -goal), (hl + geometry.goal_depth, goal), (hl, goal)])
    return np.array([[to_scene(*a, Z_LINES), to_scene(*b, Z_LINES)] for a, b in pairs], dtype=np.float32)


def net_segments(geometry: PitchGeometry) -> np.ndarray:
    """A light mesh inside the goal so the net reads as a net."""
    hl, goal, depth = geometry.half_length, geometry.goal_half_width, geometry.goal_depth
    step = 0.7
    pairs = [((hl + d, -goal), (hl + d, goal)) for d in np.arange(step, depth, step)]
    pairs += [((hl, y), (hl + depth, y)) for y in np.arange(-goal + step, goal, step)]
    return np.array([[to_scene(*a, Z_LINES), to_scene(*b, Z_LINES)] for a, b in pairs], dtype=np.float32)


def cone_mesh(half_angle_deg: float, length: float) -> tuple[np.ndarray, np.ndarray]:
    """A flat fan from the player's centre spanning +-half_angle about its facing (scene frame, facing +x)."""
    half = math.radians(half_angle_deg)
    n = 24
    arc = [(length * math.cos(-half + 2 * half * i / n), length * math.sin(-half + 2 * half * i / n), 0.0)
           for i in range(n + 1)]
    vertices = np.array([(0.0, 0.0, 0.0)] + arc, dtype=np.float32)
    faces = np.array([(0, i, i + 1) for i in range(1, n + 1)], dtype=np.uint32)
    return vertices, faces


class PitchView:
    """The pitch drawn into one client's scene; `show(frame)` moves player, ball and trail."""

    def __init__(self, scene: viser.SceneApi, geometry: PitchGeometry, root: str = "/pitch"):
        self.geometry = geometry
        self.root = root
        self._draw_static(scene)
        self.player = scene.add_frame(f"{root}/player", show_axes=False, position=to_scene(0, 0, Z_BODY))
        vertices, faces = cone_mesh(geometry.view_half_angle, style.VIEW_CONE_LENGTH)
        self.cone = scene.add_mesh_simple(
            f"{root}/player/view_cone", vertices, faces, color=style.VIEW_CONE, opacity=style.VIEW_CONE_OPACITY,
            side="double", flat_shading=True, cast_shadow=False, receive_shadow=False,
            position=(0.0, 0.0, Z_CONE - Z_BODY),
        )
        scene.add_cylinder(
            f"{root}/player/body", radius=style.PLAYER_DRAW_RADIUS, height=0.3, color=style.PLAYER, cast_shadow=False,
        )
        scene.add_line_segments(
            f"{root}/player/facing", np.array([[(0, 0, 0.3), (style.PLAYER_DRAW_RADIUS * 1.9, 0, 0.3)]], np.float32),
            colors=style.PLAYER_FACING, thickness=style.LINE_THICKNESS * 1.6,
        )
        self.ball = scene.add_icosphere(
            f"{root}/ball", radius=style.BALL_DRAW_RADIUS, color=style.BALL, position=to_scene(0, 0, Z_BODY),
            cast_shadow=False,
        )
        self.trail = scene.add_line_segments(
            f"{root}/trail", np.zeros((1, 2, 3), np.float32), colors=style.BALL_TRAIL,
            thickness=style.LINE_THICKNESS * 1.2,
        )

    def _draw_static(self, scene: viser.SceneApi) -> None:
        g = self.geometry
        margin = style.PITCH_MARGIN
        length = 2 * (g.half_length + margin) + g.goal_depth
        width = 2 * (g.half_width + margin)
        centre_x = g.goal_depth / 2
        scene.add_box(
            f"{self.root}/grass", dimensions=(length, width, 0.1), color=style.GRASS,
            position=(centre_x, 0.0, Z_GRASS), cast_shadow=False, receive_shadow=False,
        )
        stripes = 12
        stripe_length = 2 * g.half_length / stripes
        for i in range(0, stripes, 2):
            x = -g.half_length + (i + 0.5) * stripe_length
            scene.add_box(
                f"{self.root}/stripe_{i}", dimensions=(stripe_length, 2 * g.half_width, 0.1), color=style.GRASS_STRIPE,
                position=(x, 0.0, Z_GRASS + 0.01), cast_shadow=False, receive_shadow=False,
            )
        scene.add_line_segments(
            f"{self.root}/lines", marking_segments(g), colors=style.LINE, thickness=style.LINE_THICKNESS
        )
        scene.add_line_segments(
            f"{self.root}/net", net_segments(g), colors=style.GOAL_NET, thickness=style.LINE_THICKNESS * 0.4
        )
        for y in (-g.goal_half_width, g.goal_half_width):
            scene.add_cylinder(
                f"{self.root}/post_{'left' if y < 0 else 'right'}", radius=0.4, height=0.5, color=style.LINE,
                position=to_scene(g.half_length, y, 0.2), cast_shadow=False,
            )

    def show(self, frame: PitchFrame) -> None:
        self.player.position = to_scene(*frame.player, Z_BODY)
        self.player.wxyz = yaw_quaternion(frame.facing)
        self.ball.position = to_scene(*frame.ball, Z_BODY)
        self.cone.color = style.BALL if frame.ball_visible else style.VIEW_CONE
        points = np.stack([frame.trail[:-1], frame.trail[1:]], axis=1) if len(frame.trail) >= 2 else np.zeros((0, 2, 2))
        # The ball jumps to the centre line after a goal: no trail segment across that jump.
        points = points[np.linalg.norm(points[:, 1] - points[:, 0], axis=1) <= self.geometry.ball_speed_max * 1.01]
        if len(points):
            scene_points = np.zeros((len(points), 2, 3), np.float32)
            scene_points[..., 0] = points[..., 0]
            scene_points[..., 1] = -points[..., 1]
            scene_points[..., 2] = Z_TRAIL
            self.trail.points = scene_points
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
