"""Every SimpleSoccer constant in one place: the world (rcssserver 19 defaults plus the
few decisions that are ours) and the game rules. Both are frozen, validated pydantic models, so the
REST API and the UI publish them with `.model_dump()` and a changed value reaches every kernel."""

from __future__ import annotations

from typing import Literal, NamedTuple, get_args

from pydantic import BaseModel, ConfigDict, Field, PositiveFloat, PositiveInt, model_validator

from soccer_lab.fuzzy.vocabulary import Vocabulary

# The vocabulary SimpleSoccer's player is written in (fuzzy/data/soccer_vocabulary.json). The soccer
# package's entry points (play_games, play_game, SoccerEnv, SimpleSoccerEvaluator) play in it unless
# given another; GameBatch, the engine itself, always takes its vocabulary explicitly.
SOCCER_VOCABULARY = Vocabulary.default()

# Upper bounds of the evaluation rules (docs/reference/limits.md): every game or trial, and so every request
# and run, has a bounded cost. Ten times the chapter's trial length; a cap or idle limit past the game's
# length never ends it; a mean over more games than this adds nothing the GA can use.
MAX_TICKS = 10_000
MAX_GAMES_PER_EVALUATION = 100

FitnessName = Literal["simple-composite", "goals-only", "robocup-composite"]
FITNESS_NAMES: tuple[str, ...] = get_args(FitnessName)
SkillSet = Literal["strict", "assisted", "sighted"]  # soccer/skills.py says what each does
SKILL_SET_NAMES: tuple[str, ...] = get_args(SkillSet)


class WorldConstants(NamedTuple):
    """WorldConfig as a flat tuple of floats: the form numba kernels take (attribute access compiles)."""

    half_length: float
    half_width: float
    goal_half_width: float
    goal_depth: float
    post_radius: float
    ball_size: float
    ball_decay: float
    ball_speed_max: float
    ball_accel_max: float
    ball_rand: float
    player_size: float
    player_decay: float
    player_speed_max: float
    player_accel_max: float
    player_rand: float
    inertia_moment: float
    dash_power_rate: float
    kick_power_rate: float
    kickable_margin: float
    max_power: float
    max_moment: float
    view_half_angle: float
    tick_seconds: float
    collision_rebound: float
    turn_threshold: float
    dribble_power_fraction: float
    hunt_turn: float


class WorldConfig(BaseModel):
    """rcssserver's defaults (server.conf, player type 0) so behaviour carries over to the real server.
    Distances in metres, speeds and accelerations per tick, angles in degrees."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    # pitch (centre origin; the player attacks the goal at x = +pitch_length/2)
    pitch_length: PositiveFloat = 105.0
    pitch_width: PositiveFloat = 68.0
    goal_width: PositiveFloat = 14.02
    goal_depth: PositiveFloat = 2.0  # our decision: the net behind the goal mouth
    post_radius: PositiveFloat = 0.06
    # ball
    ball_size: PositiveFloat = 0.085
    ball_decay: float = Field(0.94, gt=0.0, le=1.0)
    ball_speed_max: PositiveFloat = 3.0
    ball_accel_max: PositiveFloat = 2.7
    ball_rand: float = Field(0.05, ge=0.0, lt=1.0)
    # player
    player_size: PositiveFloat = 0.3
    player_decay: float = Field(0.4, gt=0.0, le=1.0)
    player_speed_max: PositiveFloat = 1.05
    player_accel_max: PositiveFloat = 1.0
    player_rand: float = Field(0.1, ge=0.0, lt=1.0)
    inertia_moment: float = Field(5.0, ge=0.0)
    dash_power_rate: PositiveFloat = 0.006
    kick_power_rate: PositiveFloat = 0.027
    kickable_margin: PositiveFloat = 0.7
    max_power: PositiveFloat = 100.0
    max_moment: PositiveFloat = 180.0
    view_width: float = Field(90.0, gt=0.0, le=360.0)  # normal view: +-45 degrees
    tick_seconds: PositiveFloat = 0.1
    # Player-ball collisions follow rcssserver (Stadium::collisions), not pymunk: after the move, an
    # overlapping player and ball are pushed apart along the line of their centres, each half the
    # way from their midpoint, and both velocities are multiplied by collision_rebound. pymunk only
    # resolves contacts of a body with its own pitch's walls, net and posts: a body's contacts then
    # never depend on the other games in the space, so results do not depend on the batch (soccer/world.py).
    collision_rebound: float = Field(-0.1, ge=-1.0, le=1.0)
    # pymunk contact model with walls, net and posts (ours: rcssserver has no elastic collisions)
    elasticity: float = Field(0.5, ge=0.0, le=1.0)
    ball_mass: PositiveFloat = 0.45
    player_mass: PositiveFloat = 70.0
    # mid-level skills and the hunt (soccer/skills.py)
    turn_threshold: float = Field(10.0, ge=0.0, le=180.0)  # turn instead of dash when further off than this
    dribble_power_fraction: float = Field(0.3, gt=0.0, le=1.0)
    hunt_turn: float = Field(45.0, gt=0.0, le=180.0)

    @model_validator(mode="after")
    def _goal_fits(self) -> "WorldConfig":
        if self.goal_width >= self.pitch_width:
            raise ValueError("goal_width must be smaller than pitch_width")
        return self

    @property
    def kickable_distance(self) -> float:
        """Largest centre-to-centre distance at which the ball can be kicked."""
        return self.player_size + self.ball_size + self.kickable_margin

    def constants(self) -> WorldConstants:
        return WorldConstants(
            half_length=self.pitch_length / 2,
            half_width=self.pitch_width / 2,
            goal_half_width=self.goal_width / 2,
            goal_depth=self.goal_depth,
            post_radius=self.post_radius,
            ball_size=self.ball_size,
            ball_decay=self.ball_decay,
            ball_speed_max=self.ball_speed_max,
            ball_accel_max=self.ball_accel_max,
            ball_rand=self.ball_rand,
            player_size=self.player_size,
            player_decay=self.player_decay,
            player_speed_max=self.player_speed_max,
            player_accel_max=self.player_accel_max,
            player_rand=self.player_rand,
            inertia_moment=self.inertia_moment,
            dash_power_rate=self.dash_power_rate,
            kick_power_rate=self.kick_power_rate,
            kickable_margin=self.kickable_margin,
            max_power=self.max_power,
            max_moment=self.max_moment,
            view_half_angle=self.view_width / 2,
            tick_seconds=self.tick_seconds,
            collision_rebound=self.collision_rebound,
            turn_threshold=self.turn_threshold,
            dribble_power_fraction=self.dribble_power_fraction,
            hunt_turn=self.hunt_turn,
        )


class EvaluationRules(BaseModel):
    """How one evaluation ends, its fitness (the chapter, 5.1 and 5.2) and the player's skill set: the rules
    SimpleSoccer games (GameConfig) and rcssserver trials (soccer_lab.soccer.rcss.trial.TrialConfig) share."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    max_ticks: int = Field(1000, ge=1, le=MAX_TICKS)
    goal_cap: int = Field(10, ge=1, le=MAX_TICKS)
    idle_ticks: int = Field(100, ge=1, le=MAX_TICKS)  # consecutive ticks without moving more than idle_distance nor kicking
    idle_distance: float = Field(0.01, ge=0.0)
    fitness: FitnessName = "simple-composite"
    # What the kicking skills do with the ball out of reach, and what the player knows of the goal
    # (soccer/skills.py). `sighted` by calibration (docs/research/calibration.md): with `assisted` the GA
    # reaches the 10-goal cap within a few generations; with `strict` goal scorers spread further and
    # the trials' plateaus spread three times as wide as the chapter's "tightly clustered" curves.
    skills: SkillSet = "sighted"


class GameConfig(EvaluationRules):
    """The rules of one SimpleSoccer game, and its world."""

    games_per_evaluation: int = Field(1, ge=1, le=MAX_GAMES_PER_EVALUATION)
    noise: bool = False  # rcssserver-like velocity and turn noise
    # What the fitness counts as a kick: the kicks that reached the ball (default), or also every tick the
    # player's body pushes the ball (docs/research/calibration.md: the chapter's 5.2.3 reads fitness 1.0 as "no ball
    # movement", and a player that shoves the ball along moves it). SimpleSoccer only: on rcssserver the
    # server counts the kicks.
    count_touches: bool = False
    world: WorldConfig = WorldConfig()
