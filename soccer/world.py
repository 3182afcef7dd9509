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

Building a pitch's shapes in pymunk from Python cost more than a short game's ticks, so spaces and
their pitches are built once per process and reused (PitchSpace): a World borrows its spaces, each
game takes a pitch already there (moved to its slot if need be, its vertices set to exactly those a
new pitch there would get), and the World gives the spaces back when its last game has left them.
Balls and players are reused the same way (building them cost about 3% of a trial's CPU): a
finished game's bodies wait in their space, and a later game puts them at rest where it starts,
Chipmunk's bias velocity cleared (PitchSpace.take_body). Nothing a reused space remembers reaches
a game: a pitch's shapes enter the spatial hash in the same order however it came, and a taken body
is in the state a new one has (docs/design.md, "Spaces and pitches are built once per process").
"""

from __future__ import annotations

import threading
from typing import NamedTuple, Sequence

import numpy as np
import pymunk
from pymunk._chipmunk import ffi

from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.random_stream import mix64

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


class PitchOutline(NamedTuple):
    """A pitch's static shapes centred at the origin: boxes (x0, y0, x1, y1) and the posts' centres."""

    boxes: tuple[tuple[float, float, float, float], ...]
    posts: tuple[tuple[float, float], ...]
    post_radius: float

    @classmethod
    def of(cls, world: WorldConfig) -> "PitchOutline":
        hl, hw, gw, t = world.pitch_length / 2, world.pitch_width / 2, world.goal_width / 2, WALL_THICKNESS
        back = hl + world.goal_depth
        # Walls that meet overlap, each running through the corner: a body sliding along one wall into
        # a corner must find the other wall's face nearest, not the seam between two boxes, or pymunk
        # pushes it along the seam and out of the pitch.
        boxes = (
            (-hl - t, hw, back + t, hw + t),  # touch line, y > 0 (the player's right when attacking)
            (-hl - t, -hw - t, back + t, -hw),  # touch line, y < 0
            (-hl - t, -hw - t, -hl, hw + t),  # own end line
            (hl, gw, back + t, hw + t),  # attacked end line beside the goal, and the net's side
            (hl, -hw - t, back + t, -gw),
            (back, -hw - t, back + t, hw + t),  # back of the net
        )
        return cls(boxes, tuple((hl, side * gw) for side in (-1.0, 1.0)), world.post_radius)

    @classmethod
    def of_match(cls, world: WorldConfig) -> "PitchOutline":
        """A match's pitch (soccer/match.py): a goal mouth and a net at both ends, the rest as `of`."""
        hl, hw, gw, t = world.pitch_length / 2, world.pitch_width / 2, world.goal_width / 2, WALL_THICKNESS
        back = hl + world.goal_depth
        boxes = (
            (-back - t, hw, back + t, hw + t),  # touch lines, running behind both nets
            (-back - t, -hw - t, back + t, -hw),
            *((x0, gw, x1, hw + t) for x0, x1 in ((hl, back + t), (-back - t, -hl))),  # end lines beside the goals
            *((x0, -hw - t, x1, -gw) for x0, x1 in ((hl, back + t), (-back - t, -hl))),
            (back, -hw - t, back + t, hw + t),  # backs of the nets
            (-back - t, -hw - t, -back, hw + t),
        )
        posts = tuple((end * hl, side * gw) for end in (1.0, -1.0) for side in (-1.0, 1.0))
        return cls(boxes, posts, world.post_radius)


def _corners(x0: float, y0: float, x1: float, y1: float) -> list[tuple[float, float]]:
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


_IDENTITY = pymunk.Transform.identity()  # through it pymunk builds the hull as for a new Poly


class Pitch:
    """One pitch's static walls, net and posts on its space's static body, moved to a game's slot by
    `place` (then the space reindexes its shapes)."""

    def __init__(self, outline: PitchOutline, body: pymunk.Body):
        self.outline = outline
        self.boxes = [pymunk.Poly(body, _corners(*box)) for box in outline.boxes]
        self.posts = [pymunk.Circle(body, outline.post_radius, centre) for centre in outline.posts]
        self.shapes: list[pymunk.Shape] = [*self.boxes, *self.posts]
        for shape in self.shapes:
            shape.elasticity = WALL_ELASTICITY
            shape.friction = 0.0
            shape.filter = STATIC_FILTER

    def place(self, ox: float, oy: float) -> None:
        """Centre the pitch at (ox, oy): each coordinate offset + outline, as a pitch built there has."""
        for box, (x0, y0, x1, y1) in zip(self.boxes, self.outline.boxes):
            box.unsafe_set_vertices(_corners(ox + x0, oy + y0, ox + x1, oy + y1), _IDENTITY)
        for post, (x, y) in zip(self.posts, self.outline.posts):
            post.unsafe_set_offset((ox + x, oy + y))


class RoundBody(NamedTuple):
    """What a ball or a player is made of in pymunk; its bodies are built and reused by this kind."""

    mass: float
    radius: float
    elasticity: float

    def build(self) -> tuple[pymunk.Body, pymunk.Circle]:
        # Infinite moment: bodies never spin; the player's facing is kept by the engine, not by pymunk.
        body = pymunk.Body(self.mass, float("inf"))
        shape = pymunk.Circle(body, self.radius)
        shape.elasticity = self.elasticity
        shape.friction = 0.0
        shape.filter = MOVING_FILTER
        return body, shape


class PitchSpace:
    """A pymunk Space and the pitches built in it, lent to one World at a time (`borrow_spaces`). A
    pitch stays in the space when its game ends; a new game takes the idle pitch lying at its slot,
    else an idle one moved there, else a new one. Each way its shapes enter the space's spatial
    hash in the same order, so a body finds its contacts in the same order."""

    def __init__(self, outline: PitchOutline):
        self.outline = outline
        self.space = pymunk.Space()
        self.space.use_spatial_hash(HASH_CELL, HASH_CELLS)
        self._idle: dict[int, Pitch] = {}  # pitches no game plays on, by the slot they lie at
        self._idle_bodies: dict[RoundBody, list[tuple[pymunk.Body, pymunk.Circle]]] = {}  # out of the space

    def take_pitch(self, slot: int) -> Pitch:
        pitch = self._idle.pop(slot, None)
        if pitch is not None:
            return pitch
        ox, oy = pitch_offset(slot)
        if self._idle:
            pitch = self._idle.popitem()[1]
            pitch.place(ox, oy)
            for shape in pitch.shapes:
                self.space.reindex_shape(shape)
        else:
            pitch = Pitch(self.outline, self.space.static_body)
            pitch.place(ox, oy)
            self.space.add(*pitch.shapes)
        return pitch

    def give_back(self, slot: int, pitch: Pitch) -> None:
        self._idle[slot] = pitch

    def take_body(self, kind: RoundBody, x: float, y: float) -> tuple[pymunk.Body, pymunk.Circle]:
        """A body of `kind` with its shape, at rest at (x, y), not yet in the space: one a finished
        game left, else a new one. A left body differs from a new one only in Chipmunk's bias
        velocity (the last step's contact correction, added to the next step's move), which
        `update_position` with no time step clears without moving it."""
        idle = self._idle_bodies.get(kind)
        if not idle:
            body, shape = kind.build()
        else:
            body, shape = idle.pop()
            pymunk.Body.update_position(body, 0.0)
            body.velocity = (0.0, 0.0)
        body.position = (x, y)
        return body, shape

    def give_back_body(self, kind: RoundBody, body: pymunk.Body, shape: pymunk.Circle) -> None:
        """A body and its shape just removed from the space, for a later game's `take_body`."""
        self._idle_bodies.setdefault(kind, []).append((body, shape))


_idle_spaces: dict[PitchOutline, list[PitchSpace]] = {}  # this process's spaces no World holds
_idle_lock = threading.Lock()  # Worlds may be built in several threads (the app's)


def borrow_spaces(outline: PitchOutline, count: int) -> list[PitchSpace]:
    with _idle_lock:
        idle = _idle_spaces.setdefault(outline, [])
        borrowed = [idle.pop() for _ in range(min(count, len(idle)))]
    return borrowed + [PitchSpace(outline) for _ in range(count - len(borrowed))]


def give_back_spaces(spaces: list[PitchSpace]) -> None:
    """Spaces every game has left (their pitches stay, idle), for the next World."""
    with _idle_lock:
        _idle_spaces[spaces[0].outline].extend(spaces)


_PROBE = (1.25, -2.5, 3.75, -5.0)  # a position and a velocity no other field of a new body holds
_PROBE_BYTES = 128  # searched for the probe: a cpBody is larger, its position and velocity lie within these


def _find_vectors_offset() -> int:
    """Where a cpBody keeps its position and velocity (Chipmunk's p and v, side by side: x, y, vx,
    vy), found in a probe body: pymunk declares the struct opaque."""
    body = pymunk.Body(1.0, float("inf"))
    body.position, body.velocity = _PROBE[:2], _PROBE[2:]
    words = np.frombuffer(ffi.buffer(body._body, _PROBE_BYTES), dtype=np.float64)
    found = [i for i in range(len(words) - 3) if tuple(words[i:i + 4]) == _PROBE]
    if len(found) != 1:
        raise RuntimeError("cannot find a pymunk body's position and velocity in Chipmunk's memory")
    return 8 * found[0]


_VECTORS_OFFSET = _find_vectors_offset()


def vectors_address(body: pymunk.Body) -> int:
    """The address of `body`'s (x, y, vx, vy) in Chipmunk's memory, valid while the body lives.
    The engine's kernel reads and writes a game's bodies there (pymunk's own setters store the same
    values: a body with its centre of gravity at its position), sparing a copy through pymunk of
    every body each tick."""
    return int(ffi.cast("uintptr_t", body._body)) + _VECTORS_OFFSET


class Pitches(NamedTuple):
    """Where each game g is, as the engine's kernel reads it (arrays updated in place)."""

    layer: np.ndarray  # int64[n]: which space the game is in
    player: np.ndarray  # uint64[n]: the address of its player's (x, y, vx, vy) (`vectors_address`); 0: left
    ball: np.ndarray  # uint64[n]: the same for its ball
    offsets: np.ndarray  # float64[n, 2]: its pitch's centre in the shared space


class World:
    """The shared space(s): games added at their seed's slot, removed when they finish, and where
    each game's bodies keep their positions and velocities (`Pitches`). The spaces are borrowed
    (`borrow_spaces`) and given back when the last game has left them; `spaces` is then empty."""

    def __init__(self, config: WorldConfig, seeds: Sequence[int], outline: PitchOutline | None = None):
        self.config = config
        self._player_kind = RoundBody(config.player_mass, config.player_size, config.elasticity)
        self._ball_kind = RoundBody(config.ball_mass, config.ball_size, config.elasticity)
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
        self.pitches = Pitches(layer=layers, player=np.zeros(games, dtype=np.uint64),
                               ball=np.zeros(games, dtype=np.uint64), offsets=offsets)
        self._slots = slots
        self._outline = PitchOutline.of(config) if outline is None else outline
        self._pitch_spaces = borrow_spaces(self._outline, max(len(taken), 1))
        self.spaces = [pitch_space.space for pitch_space in self._pitch_spaces]
        self._slots_in_space: list[set[int]] = [set() for _ in self.spaces]  # per layer: its games' slots
        self._objects: list[tuple[pymunk.Body, ...]] = [()] * games
        self._pitch: list[Pitch | None] = [None] * games

    def add_game(self, game: int, player_xy: tuple[float, float], ball_xy: tuple[float, float]) -> None:
        ox, oy = self.pitches.offsets[game]
        layer = self.pitches.layer[game]
        pitch_space = self._pitch_spaces[layer]
        player, player_shape = pitch_space.take_body(self._player_kind, ox + player_xy[0], oy + player_xy[1])
        ball, ball_shape = pitch_space.take_body(self._ball_kind, ox + ball_xy[0], oy + ball_xy[1])
        self.spaces[layer].add(player, player_shape, ball, ball_shape)
        self._objects[game] = (player, player_shape, ball, ball_shape)
        self._pitch[game] = pitch_space.take_pitch(self._slots[game])
        self._slots_in_space[layer].add(self._slots[game])
        self.pitches.player[game] = vectors_address(player)
        self.pitches.ball[game] = vectors_address(ball)

    def remove_game(self, game: int) -> None:
        pitch = self._pitch[game]
        if pitch is None:
            return
        layer = self.pitches.layer[game]
        player, player_shape, ball, ball_shape = self._objects[game]
        self.spaces[layer].remove(player, player_shape, ball, ball_shape)
        pitch_space = self._pitch_spaces[layer]
        pitch_space.give_back(self._slots[game], pitch)
        pitch_space.give_back_body(self._player_kind, player, player_shape)
        pitch_space.give_back_body(self._ball_kind, ball, ball_shape)
        self._objects[game] = ()
        self._pitch[game] = None
        self.pitches.player[game] = self.pitches.ball[game] = 0
        self._slots_in_space[layer].discard(self._slots[game])
        if not any(self._slots_in_space):
            give_back_spaces(self._pitch_spaces)
            self._pitch_spaces, self.spaces, self._slots_in_space = [], [], []

    def restart_game(self, game: int, seed: int, player_xy: tuple[float, float], ball_xy: tuple[float, float]) -> None:
        """Game `game` (finished or not) begins again from `seed`, at that seed's slot, in the first space
        where no other game holds that slot (a space borrowed when none is free)."""
        self.remove_game(game)
        slot = pitch_slot(seed)
        held = self._slots_in_space
        layer = next((k for k, slots in enumerate(held) if slot not in slots), len(held))
        if layer == len(held):  # also when every game had left and the spaces went back
            self._pitch_spaces += borrow_spaces(self._outline, 1)
            self.spaces.append(self._pitch_spaces[-1].space)
            held.append(set())
        self._slots[game] = slot
        self.pitches.offsets[game] = pitch_offset(slot)
        self.pitches.layer[game] = layer
        self.add_game(game, player_xy, ball_xy)

    def occupied_layers(self) -> list[int]:
        """The layers whose space still holds games (only their spaces need stepping)."""
        return [layer for layer, slots in enumerate(self._slots_in_space) if slots]

    def objects(self, game: int) -> tuple[pymunk.Body, pymunk.Shape, pymunk.Body, pymunk.Shape]:
        """(player body, player shape, ball body, ball shape) of a game still in the space."""
        return self._objects[game]
