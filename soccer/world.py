"""ONE pymunk Space holding many SimpleSoccer pitches (spec 4.1, 4.5).

Each game sits on its own pitch far from the others. Pitch origins are multiples of PITCH_SPACING
inside the binade [2**20, 2**21): every coordinate of every game then has the same floating-point
spacing, and a pitch's offset is an even multiple of it, so pymunk's arithmetic gives a game bit for
bit the same trajectory whichever slot (batch) it is played in.

Walls are boxes WALL_THICKNESS deep lying outside the lines (a ball moving 3 m per tick cannot tunnel
through them; pymunk has no continuous collision detection): along both touch lines, the own end line,
the attacked end line except the goal mouth, and the back of the 2 m deep net; posts are circles.

pymunk resolves only the contacts of the ball and the player with these static shapes (shape filter
categories); the engine resolves player-ball collisions itself, as rcssserver does. Chipmunk's solver
is Gauss-Seidel over the space's arbiter list, whose order comes from the spatial hash and so from
every shape in the space: with ball-player contacts in pymunk, a body touching two things at once
(the ball between player and post) was resolved in an order that depended on the other games.
A body's contacts with its own pitch's static shapes are found in an order fixed by that pitch alone.
"""

from __future__ import annotations

import numpy as np
import pymunk
import pymunk.batch

from soccer.config import WorldConfig

PITCH_SPACING = 256.0  # metres between pitch origins: a pitch with its walls spans less than 128 m each way
ORIGIN = float(2**20) + PITCH_SPACING / 2
PITCHES_PER_ROW = int((2**20 - PITCH_SPACING) // PITCH_SPACING)
WALL_THICKNESS = 5.0  # deeper than the fastest ball moves in one tick
WALL_ELASTICITY = 1.0  # pymunk multiplies the two shapes' elasticities: ball-wall = ball elasticity
HASH_CELL = 4.0  # spatial hash cell size (m)
HASH_CELLS_PER_GAME = 64
STATIC_CATEGORY, MOVING_CATEGORY = 0b01, 0b10
STATIC_FILTER = pymunk.ShapeFilter(categories=STATIC_CATEGORY, mask=MOVING_CATEGORY)
MOVING_FILTER = pymunk.ShapeFilter(categories=MOVING_CATEGORY, mask=STATIC_CATEGORY)  # ball and player: walls only


def pitch_offset(slot: int) -> tuple[float, float]:
    """Where pitch `slot`'s centre lies in the shared space."""
    row, column = divmod(slot, PITCHES_PER_ROW)
    return ORIGIN + column * PITCH_SPACING, ORIGIN + row * PITCH_SPACING


def _box(body: pymunk.Body, x0: float, y0: float, x1: float, y1: float) -> pymunk.Poly:
    return pymunk.Poly(body, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)])


def pitch_shapes(world: WorldConfig, body: pymunk.Body, ox: float, oy: float) -> list[pymunk.Shape]:
    """The static walls, net and posts of one pitch centred at (ox, oy)."""
    hl, hw, gw, t = world.pitch_length / 2, world.pitch_width / 2, world.goal_width / 2, WALL_THICKNESS
    back = hl + world.goal_depth
    boxes = [
        (-hl - t, hw, back + t, hw + t),  # touch line, y > 0 (the player's right when attacking)
        (-hl - t, -hw - t, back + t, -hw),  # touch line, y < 0
        (-hl - t, -hw, -hl, hw),  # own end line
        (hl, gw, back + t, hw),  # attacked end line beside the goal, and the net's side
        (hl, -hw, back + t, -gw),
        (back, -gw, back + t, gw),  # back of the net
    ]
    shapes: list[pymunk.Shape] = [_box(body, ox + x0, oy + y0, ox + x1, oy + y1) for x0, y0, x1, y1 in boxes]
    for side in (-1.0, 1.0):
        shapes.append(pymunk.Circle(body, world.post_radius, (ox + hl, oy + side * gw)))
    for shape in shapes:
        shape.elasticity = WALL_ELASTICITY
        shape.friction = 0.0
        shape.filter = STATIC_FILTER
    return shapes


def _round_body(mass: float, radius: float, elasticity: float, x: float, y: float) -> tuple[pymunk.Body, pymunk.Circle]:
    # Infinite moment: bodies never spin; the player's facing is kept by the engine, not by pymunk.
    body = pymunk.Body(mass, float("inf"))
    body.position = (x, y)
    shape = pymunk.Circle(body, radius)
    shape.elasticity = elasticity
    shape.friction = 0.0
    shape.filter = MOVING_FILTER
    return body, shape


class World:
    """The shared space: games added at their slot's offset, removed when they finish, and the
    mapping from pymunk's body order (which removal permutes) to (game, player or ball)."""

    def __init__(self, config: WorldConfig, games: int):
        self.config = config
        self.space = pymunk.Space()
        self.space.use_spatial_hash(HASH_CELL, max(HASH_CELLS_PER_GAME * games, 1024))
        self.offsets = np.array([pitch_offset(g) for g in range(games)], dtype=np.float64).reshape(games, 2)
        self._objects: list[tuple[pymunk.Body, ...]] = [()] * games
        self._static: list[list[pymunk.Shape]] = [[] for _ in range(games)]
        self._ids: dict[int, int] = {}  # body id -> 2 * game + (1 for the ball)
        self.player_slot = np.full(games, -1, dtype=np.int64)
        self.ball_slot = np.full(games, -1, dtype=np.int64)
        self._id_buffer = pymunk.batch.Buffer()

    def add_game(self, game: int, player_xy: tuple[float, float], ball_xy: tuple[float, float]) -> None:
        c = self.config
        ox, oy = self.offsets[game]
        player, player_shape = _round_body(c.player_mass, c.player_size, c.elasticity, ox + player_xy[0], oy + player_xy[1])
        ball, ball_shape = _round_body(c.ball_mass, c.ball_size, c.elasticity, ox + ball_xy[0], oy + ball_xy[1])
        static = pitch_shapes(c, self.space.static_body, ox, oy)
        self.space.add(player, player_shape, ball, ball_shape, *static)
        self._objects[game] = (player, player_shape, ball, ball_shape)
        self._static[game] = static
        self._ids[player.id] = 2 * game
        self._ids[ball.id] = 2 * game + 1

    def remove_game(self, game: int) -> None:
        if self._objects[game]:
            player, _, ball, _ = self._objects[game]
            del self._ids[player.id], self._ids[ball.id]
            self.space.remove(*self._objects[game], *self._static[game])
            self._objects[game] = ()
            self._static[game] = []
            self.player_slot[game] = self.ball_slot[game] = -1

    def objects(self, game: int) -> tuple[pymunk.Body, pymunk.Shape, pymunk.Body, pymunk.Shape]:
        """(player body, player shape, ball body, ball shape) of a game still in the space."""
        return self._objects[game]

    def index_bodies(self) -> None:
        """Refresh player_slot/ball_slot: each game's bodies' rows in pymunk's batch order."""
        self._id_buffer.clear()
        pymunk.batch.get_space_bodies(self.space, pymunk.batch.BodyFields.BODY_ID, self._id_buffer)
        for row, body_id in enumerate(np.frombuffer(self._id_buffer.int_buf(), dtype=np.uintp).tolist()):
            code = self._ids.get(body_id)  # None: the space's static body (its row is read and written unchanged)
            if code is not None:
                (self.ball_slot if code & 1 else self.player_slot)[code >> 1] = row

    @property
    def bodies(self) -> int:
        return len(self._ids)
