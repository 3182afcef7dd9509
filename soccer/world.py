"""The pymunk Space holding many SimpleSoccer pitches.

Each game sits on its own pitch far from the others, at a slot drawn from the game's seed, so a game
has the same coordinates, and pymunk does the same arithmetic for it, whichever batch it is played in
(contact geometry, e.g. Chipmunk's GJK interpolating support points, is not translation invariant:
one ulp apart at tick 387 became a missed goal). All slots lie in the binade [2**20, 2**21), so
every game has the same floating-point resolution. Two games of one batch that draw the same slot
(rare) go to separate spaces ("layers"), stepped one after the other.

Walls are boxes WALL_THICKNESS deep lying outside the lines (a ball moving 3 m per tick cannot tunnel
through them; pymunk has no continuous collision detection): along both touch lines, the own end line,
the attacked end line except the goal mouth, and the back of the 2 m deep net; posts are circles.

pymunk resolves only the contacts of the ball and the player with these static shapes (shape filter
categories); the engine resolves player-ball collisions itself, as rcssserver does. Chipmunk's solver
is Gauss-Seidel over the space's arbiter list, whose order comes from the spatial hash and so from
every shape in the space: with ball-player contacts in pymunk, a body touching two things at once
(the ball between player and post) was resolved in an order that depended on the other games. A
body's contacts with its own pitch's static shapes are found in an order fixed by its slot and the
hash table size, which is therefore a constant, not scaled with the batch.
"""

from __future__ import annotations

from typing import NamedTuple, Sequence

import numpy as np
import pymunk
import pymunk.batch

from soccer.config import WorldConfig
from soccer.random_stream import mix64

PITCH_SPACING = 256.0  # metres between pitch origins: a pitch with its walls spans less than 128 m each way
ORIGIN = float(2**20) + PITCH_SPACING / 2
PITCHES_PER_ROW = int((2**20 - PITCH_SPACING) // PITCH_SPACING)
WALL_THICKNESS = 5.0  # deeper than the fastest ball moves in one tick
WALL_ELASTICITY = 1.0  # pymunk multiplies the two shapes' elasticities: ball-wall = ball elasticity
HASH_CELL = 16.0  # spatial hash cell size (m): a ball or player overlaps one or two cells
HASH_CELLS = 4096  # fixed whatever the batch size (see above); measured fastest for 200-1000 games
SLOTS = PITCHES_PER_ROW * PITCHES_PER_ROW
STATIC_CATEGORY, MOVING_CATEGORY = 0b01, 0b10
STATIC_FILTER = pymunk.ShapeFilter(categories=STATIC_CATEGORY, mask=MOVING_CATEGORY)
MOVING_FILTER = pymunk.ShapeFilter(categories=MOVING_CATEGORY, mask=STATIC_CATEGORY)  # ball and player: walls only


def pitch_offset(slot: int) -> tuple[float, float]:
    """Where pitch `slot`'s centre lies in the shared space."""
    row, column = divmod(slot, PITCHES_PER_ROW)
    return ORIGIN + column * PITCH_SPACING, ORIGIN + row * PITCH_SPACING


def pitch_slot(seed: int) -> int:
    """The slot of the game played from `seed`: a 64-bit hash of the seed, so nearby seeds land far
    apart and two games of a batch rarely share a slot."""
    return mix64(seed) % SLOTS


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


def _new_space() -> pymunk.Space:
    space = pymunk.Space()
    space.use_spatial_hash(HASH_CELL, HASH_CELLS)
    return space


class Pitches(NamedTuple):
    """Where each game g is, as the engine's kernel reads it (arrays updated in place)."""

    layer: np.ndarray  # int64[n]: which space the game is in
    player_slot: np.ndarray  # int64[n]: row of its player in its space's batch order (-1: left the space)
    ball_slot: np.ndarray  # int64[n]
    offsets: np.ndarray  # float64[n, 2]: its pitch's centre in the shared space


class World:
    """The shared space(s): games added at their seed's slot, removed when they finish, and the
    mapping from pymunk's body order (which removal permutes) to (game, player or ball)."""

    def __init__(self, config: WorldConfig, seeds: Sequence[int]):
        self.config = config
        games = len(seeds)
        slots = [pitch_slot(seed) for seed in seeds]
        offsets = np.array([pitch_offset(s) for s in slots], dtype=np.float64).reshape(games, 2)
        layers = np.zeros(games, dtype=np.int64)
        taken: list[set[int]] = []
        for g, slot in enumerate(slots):
            layer = next((k for k, used in enumerate(taken) if slot not in used), len(taken))
            if layer == len(taken):
                taken.append(set())
            taken[layer].add(slot)
            layers[g] = layer
        unplaced = np.full(games, -1, dtype=np.int64)  # index_bodies fills the slots in
        self.pitches = Pitches(layer=layers, player_slot=unplaced.copy(), ball_slot=unplaced.copy(), offsets=offsets)
        self.spaces = [_new_space() for _ in range(max(len(taken), 1))]
        self._objects: list[tuple[pymunk.Body, ...]] = [()] * games
        self._static: list[list[pymunk.Shape]] = [[] for _ in range(games)]
        self._body_ids = np.zeros(2 * games, dtype=np.uintp)  # pymunk body id of game g's player [g], ball [games + g]
        self._id_order: np.ndarray | None = None  # argsort of _body_ids, refreshed after games are added
        self._id_buffer = pymunk.batch.Buffer()

    def add_game(self, game: int, player_xy: tuple[float, float], ball_xy: tuple[float, float]) -> None:
        c = self.config
        ox, oy = self.pitches.offsets[game]
        space = self.spaces[self.pitches.layer[game]]
        player, player_shape = _round_body(c.player_mass, c.player_size, c.elasticity, ox + player_xy[0], oy + player_xy[1])
        ball, ball_shape = _round_body(c.ball_mass, c.ball_size, c.elasticity, ox + ball_xy[0], oy + ball_xy[1])
        static = pitch_shapes(c, space.static_body, ox, oy)
        space.add(player, player_shape, ball, ball_shape, *static)
        self._objects[game] = (player, player_shape, ball, ball_shape)
        self._static[game] = static
        self._body_ids[game] = player.id
        self._body_ids[len(self._objects) + game] = ball.id
        self._id_order = None

    def remove_game(self, game: int) -> None:
        if self._objects[game]:
            self.spaces[self.pitches.layer[game]].remove(*self._objects[game], *self._static[game])
            self._objects[game] = ()
            self._static[game] = []
            self.pitches.player_slot[game] = self.pitches.ball_slot[game] = -1

    def objects(self, game: int) -> tuple[pymunk.Body, pymunk.Shape, pymunk.Body, pymunk.Shape]:
        """(player body, player shape, ball body, ball shape) of a game still in the space."""
        return self._objects[game]

    def index_bodies(self) -> None:
        """Refresh pitches.player_slot/ball_slot: each game's bodies' rows in its space's batch order."""
        games = len(self._objects)
        if games == 0:
            return
        if self._id_order is None:
            self._id_order = np.argsort(self._body_ids)
        known = self._body_ids[self._id_order]
        for space in self.spaces:
            self._id_buffer.clear()
            pymunk.batch.get_space_bodies(space, pymunk.batch.BodyFields.BODY_ID, self._id_buffer)
            ids = np.frombuffer(self._id_buffer.int_buf(), dtype=np.uintp)
            where = np.minimum(np.searchsorted(known, ids), len(known) - 1)
            rows = np.flatnonzero(known[where] == ids)  # all but the space's static body
            which = self._id_order[where[rows]]
            player = which < games
            self.pitches.player_slot[which[player]] = rows[player]
            self.pitches.ball_slot[which[~player] - games] = rows[~player]
