"""SimpleSoccer as a Gymnasium environment (soccer/gym/): the environment checker, the fuzzy controller
acting through the environment plays exactly the games `soccer-lab play` plays (single and vector),
NEXT_STEP autoreset, bad actions, rewards, rendering, and soccer/ importing without Gymnasium."""

import subprocess
import sys
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import soccer_lab.soccer.gym
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.engine import GameBatch, play_game, play_games
from soccer_lab.soccer.examples import example
from soccer_lab.soccer.gym.env import NO_CONTROLLER, SimpleSoccerEnv
from soccer_lab.soccer.gym.policy import FuzzyPolicy
from soccer_lab.soccer.gym.render import BALL, PLAYER, PIXELS_PER_METRE, MARGIN
from soccer_lab.soccer.gym.vector import SimpleSoccerVectorEnv

ENV_ID = soccer_lab.soccer.gym.ENV_ID
SHORT = GameConfig(max_ticks=300)
IDLE_SOON = GameConfig(max_ticks=300, idle_ticks=20)  # a random player that stands still ends the game early
GOAL_CAP = GameConfig(goal_cap=1, skills="assisted")  # the demo scores within 1000 ticks: ends by the cap
NOISY = GameConfig(max_ticks=300, noise=True, count_touches=True)  # every random draw, every kick counted


def rulebases():
    """The demo, the other examples and two random rulebases: players that score, dribble, stand still."""
    rng = np.random.default_rng(38)
    return {**{name: example(name).rulebase(SOCCER_VOCABULARY) for name in ("demo", "striker", "hunter")},
            **{f"random-{i}": random_rulebase(rng, SOCCER_VOCABULARY, rules=8) for i in range(2)}}


RULEBASES = rulebases()


def play_through_env(env, policy, seed):
    """One episode with the policy; what play_game's trace holds, from the env's info, and the end."""
    observation, info = env.reset(seed=seed)
    rows = []
    while True:
        rows.append((info["player"], info["facing"], info["ball"], info["goals"]))
        observation, reward, terminated, truncated, info = env.step(policy(observation))
        if terminated or truncated:
            return rows, info, terminated, truncated


def trace_rows(trace):
    return [((x, y), f, (bx, by), g) for x, y, f, bx, by, g in
            zip(trace.player_x, trace.player_y, trace.facing, trace.ball_x, trace.ball_y, trace.goals)]


@pytest.mark.parametrize("config", [SHORT, IDLE_SOON, GOAL_CAP, NOISY], ids=["time-up", "idle", "goal-cap", "noise"])
@pytest.mark.parametrize("name", list(RULEBASES))
def test_fuzzy_policy_through_env_plays_the_game_play_plays(name, config):
    rulebase = RULEBASES[name]
    env = gymnasium.make(ENV_ID, config=config)
    policy = FuzzyPolicy(rulebase)
    for seed in (0, 7):
        rows, info, terminated, truncated = play_through_env(env, policy, seed)
        result, trace = play_game(rulebase, seed, config)
        assert info["result"] == result  # goals, kicks, ticks, closest approach, fitness, end reason
        assert rows == trace_rows(trace)  # every tick's positions and facing, bit for bit
        assert truncated == (result.end_reason == "max-ticks")
        assert terminated == (result.end_reason in ("goal-cap", "idle"))


def test_the_three_end_reasons_are_all_played():
    """The parametrised equality above covers every way a game ends (else it proves less than it says)."""
    reasons = {play_game(RULEBASES[name], seed, config, trace=False)[0].end_reason
               for name in RULEBASES for seed in (0, 7) for config in (SHORT, IDLE_SOON, GOAL_CAP)}
    assert reasons == {"max-ticks", "idle", "goal-cap"}


def test_vector_env_plays_each_sub_environment_as_play_games_across_autoresets():
    names = list(RULEBASES)
    players = [RULEBASES[n] for n in names]
    envs = SimpleSoccerVectorEnv(len(players), config=IDLE_SOON)
    policy = FuzzyPolicy(players)
    observations, infos = envs.reset(seed=100)
    seeds = [[s] for s in infos["seed"]]
    assert [s[0] for s in seeds] == [100 + i for i in range(len(players))]
    results = [[] for _ in players]
    traced = [[] for _ in players]  # each first game's positions, tick by tick
    while min(len(r) for r in results) < 2:
        for g in range(len(players)):
            if not results[g]:
                seen = envs.batch.observation
                traced[g].append((seen.player_x[g], seen.player_y[g], seen.ball_x[g], seen.ball_y[g]))
        observations, rewards, terminated, truncated, infos = envs.step(policy(observations))
        for g in np.flatnonzero(infos.get("_result", [])):
            results[g].append(infos["result"][g])
        for g in np.flatnonzero(infos.get("_seed", [])):
            seeds[g].append(infos["seed"][g])
    assert [r[0] for r in results] == play_games(players, [s[0] for s in seeds], IDLE_SOON)
    for g, player in enumerate(players):
        result, trace = play_game(player, seeds[g][1], IDLE_SOON)
        assert results[g][1] == result  # the autoreset game too: a game does not depend on its batch
        _, first = play_game(player, seeds[g][0], IDLE_SOON)
        assert traced[g] == list(zip(first.player_x, first.player_y, first.ball_x, first.ball_y))


def test_vector_env_sub_environments_sharing_a_seed_play_the_same_game():
    """Games of one seed share a pitch slot: they play in separate spaces, and restarts find one free."""
    player = RULEBASES["demo"]
    envs = gymnasium.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point", config=IDLE_SOON)
    policy = FuzzyPolicy(player)
    observations, _ = envs.reset(seed=[5, 5, 5])
    ended = np.zeros(3, dtype=bool)
    while not ended.all():
        observations, _, terminated, truncated, infos = envs.step(policy(observations))
        ended |= terminated | truncated
        if "_result" in infos:
            assert len({infos["result"][g] for g in np.flatnonzero(infos["_result"])}) == 1
    assert isinstance(envs.unwrapped, SimpleSoccerVectorEnv)


def test_vector_env_next_step_autoreset_returns_the_new_games_first_observation():
    envs = SimpleSoccerVectorEnv(2, config=GameConfig(max_ticks=3))
    observations, _ = envs.reset(seed=1)
    hunt = {"skill": np.full(2, envs.spaces.hunt), "parameters": np.zeros((2, 2))}
    for _ in range(3):
        observations, rewards, terminated, truncated, infos = envs.step(hunt)
    assert truncated.all() and not terminated.any() and infos["_result"].all()
    observations, rewards, terminated, truncated, infos = envs.step(hunt)  # the actions are ignored
    assert not (terminated | truncated).any() and (rewards == 0).all() and "result" not in infos
    single = SimpleSoccerEnv()
    for g in range(2):
        first, _ = single.reset(seed=infos["seed"][g])
        assert np.array_equal(first["inputs"], observations["inputs"][g])
        assert np.array_equal(first["visible"], observations["visible"][g])


ADVICE_ONLY = ("symmetric and normalized space",  # its advice to normalise the Box: the skills' own units
               "not having a spec")  # the env built directly: render modes are checked through make's above


def test_environment_checker_passes_with_no_warning_but_its_advice():
    """The checker reports much only as warnings (an observation outside its space, a wrong dtype, a reset
    that ignores its seed): all of them fail here but its advice about the Box's range."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(gymnasium.make(ENV_ID, render_mode="rgb_array").unwrapped)
        check_env(SimpleSoccerEnv(config=GameConfig(max_ticks=20, skills="assisted"), reward="fitness"))
    assert not [str(w.message) for w in caught if not any(advice in str(w.message) for advice in ADVICE_ONLY)]


def test_observations_hide_what_the_player_does_not_see():
    env = SimpleSoccerEnv(config=SHORT)
    observation, _ = env.reset(seed=3)
    turn = {"skill": SOCCER_VOCABULARY.action_names.index("TURN"), "parameters": np.array([60.0, 0.0])}
    unseen_inputs = 0
    for _ in range(20):  # turning on the spot: ball and goal come into and out of view
        seen = env.batch.observation
        visible = seen.visible[0]
        assert np.array_equal(observation["visible"], visible.astype(np.int8))
        for i, o in enumerate(env.spaces.input_object):
            assert observation["inputs"][i] == (seen.inputs[0, i] if visible[o] else 0.0)
            unseen_inputs += not visible[o]
        assert env.observation_space.contains(observation)
        observation, *_ = env.step(turn)
    assert unseen_inputs > 0


def test_bad_actions_raise_a_value_error_and_leave_the_game_untouched():
    env = SimpleSoccerEnv(config=SHORT)
    env.reset(seed=2)
    for bad in ({"skill": env.spaces.hunt + 1, "parameters": np.zeros(2)},
                {"skill": -1, "parameters": np.zeros(2)},
                {"skill": 0, "parameters": np.array([np.nan, 50.0])},
                {"skill": 0, "parameters": np.zeros(3)}):
        with pytest.raises(ValueError):
            env.step(bad)
    assert env.batch.state.ticks[0] == 0


def test_parameters_beyond_their_universe_act_as_its_bound():
    dash = SOCCER_VOCABULARY.action_names.index("DASH")
    power = SOCCER_VOCABULARY.output_names.index("power")
    high = SimpleSoccerEnv(config=SHORT).action_space["parameters"].high
    infos = []
    for parameters in (high * 10, np.full(2, np.inf), high):
        env = SimpleSoccerEnv(config=SHORT)
        env.reset(seed=4)
        infos.append(env.step({"skill": dash, "parameters": parameters})[4])
    assert infos[0]["player"] == infos[1]["player"] == infos[2]["player"] and high[power] > 0


def test_step_after_the_game_ended_asks_for_reset():
    env = SimpleSoccerEnv(config=GameConfig(max_ticks=1))
    env.reset(seed=0)
    assert env.step({"skill": 0, "parameters": np.zeros(2)})[3]
    with pytest.raises(RuntimeError, match="reset"):
        env.step({"skill": 0, "parameters": np.zeros(2)})


def test_rewards_sum_to_the_games_goals_or_end_with_its_fitness():
    player = RULEBASES["demo"]
    for reward in ("goals", "fitness"):
        env = SimpleSoccerEnv(config=SHORT, reward=reward)
        policy = FuzzyPolicy(player)
        observation, _ = env.reset(seed=0)
        rewards, done = [], False
        while not done:
            observation, r, terminated, truncated, info = env.step(policy(observation))
            rewards.append(r)
            done = terminated or truncated
        result = info["result"]
        if reward == "goals":
            assert sum(rewards) == result.goals > 0
        else:
            assert rewards[-1] == 1.0 - result.fitness and not any(rewards[:-1])


def test_one_seed_fixes_every_later_unseeded_episode():
    def seeds(env):
        env.reset(seed=9)
        return [env.reset()[1]["seed"] for _ in range(3)]
    assert seeds(SimpleSoccerEnv()) == seeds(SimpleSoccerEnv())
    assert len(set(seeds(SimpleSoccerEnv()))) == 3


def test_rgb_array_draws_the_player_and_the_ball_where_they_are():
    env = gymnasium.make(ENV_ID, render_mode="rgb_array", config=SHORT)
    _, info = env.reset(seed=6)
    for _ in range(5):
        _, _, _, _, info = env.step({"skill": env.unwrapped.spaces.hunt, "parameters": np.zeros(2)})
    image = env.render()
    world = SHORT.world

    def pixel(xy):
        column = int((xy[0] + MARGIN + world.pitch_length / 2) * PIXELS_PER_METRE)
        row = int((xy[1] + MARGIN + world.pitch_width / 2) * PIXELS_PER_METRE)
        return tuple(image[row, column])
    assert image.dtype == np.uint8 and image.shape[2] == 3
    assert pixel(info["player"]) == PLAYER
    assert pixel(info["ball"]) == BALL
    vector = SimpleSoccerVectorEnv(2, render_mode="rgb_array")
    vector.reset(seed=1)
    pictures = vector.render()
    assert len(pictures) == 2 and not np.array_equal(*pictures)


def test_a_batch_is_played_by_its_controllers_or_by_given_actions_not_both():
    batch = GameBatch([NO_CONTROLLER], [0], SHORT, SOCCER_VOCABULARY)
    batch.act(np.array([-1]), np.zeros((1, 2)))
    with pytest.raises(RuntimeError, match="not both"):
        batch.step()


def test_soccer_imports_without_gymnasium():
    """Gymnasium is an optional extra: only soccer_lab.soccer.gym needs it."""
    code = ("import sys, pkgutil, importlib; sys.modules['gymnasium'] = None\n"
            "import soccer_lab.soccer as soccer\n"
            "names = [m.name for m in pkgutil.walk_packages(soccer.__path__, 'soccer_lab.soccer.') "
            "if not m.name.startswith('soccer_lab.soccer.gym')]\n"
            "[importlib.import_module(n) for n in names]\n"
            "print(len(names))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert int(done.stdout) > 10


def test_make_with_the_module_prefix_needs_no_import_first():
    """Gymnasium 1.x loads no plugins: "soccer_lab.soccer.gym:<id>" makes gymnasium import the package that registers it."""
    code = ("import gymnasium\n"
            f"env = gymnasium.make('soccer_lab.soccer.gym:{ENV_ID}')\n"
            "observation, info = env.reset(seed=0)\n"
            "print(sorted(observation))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "['inputs', 'visible']"


def test_the_gymnasium_page_examples_print_what_it_shows(capsys):
    """docs/research/gymnasium.md: each ```python block, run in turn, prints the ```text block after it."""
    import re
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "docs" / "research" / "gymnasium.md").read_text(encoding="utf-8")
    examples = re.findall(r"^```python\n(.*?)^```\n\n```text\n(.*?)^```", page, re.MULTILINE | re.DOTALL)
    assert len(examples) == 2
    for code, shown in examples:
        exec(compile(code, "docs/research/gymnasium.md", "exec"), {})
        assert capsys.readouterr().out == shown


def test_evolved_players_through_the_vector_env_play_the_games_play_games_plays(evolved_rulebases):
    """What evolution produces (long messy antecedents), a population at once through the vector env."""
    players = evolved_rulebases
    envs = SimpleSoccerVectorEnv(len(players), config=SHORT)
    policy = FuzzyPolicy(players)
    observations, infos = envs.reset(seed=[1000 + 7 * g for g in range(len(players))])
    results = [None] * len(players)
    while any(r is None for r in results):
        observations, _, _, _, infos = envs.step(policy(observations))
        for g in np.flatnonzero(infos.get("_result", [])):
            results[g] = results[g] or infos["result"][g]
    assert results == play_games(players, [1000 + 7 * g for g in range(len(players))], SHORT)


def test_vector_env_steps_as_sync_vector_env_over_single_envs_does():
    """The same API as Gymnasium's own vectorisation: the same batched observations, rewards and ends."""
    from gymnasium.vector import SyncVectorEnv

    config = GameConfig(max_ticks=20, skills="assisted")
    batched = SimpleSoccerVectorEnv(3, config=config)
    synced = SyncVectorEnv([lambda: SimpleSoccerEnv(config=config) for _ in range(3)])
    batched.action_space.seed(4)
    actions = [batched.action_space.sample() for _ in range(20)]
    steps = [[envs.reset(seed=30)[0]] + [envs.step(action)[:4] for action in actions] for envs in (batched, synced)]
    for ours, theirs in zip(*steps):
        for a, b in zip(ours, theirs):
            if isinstance(a, dict):
                assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)
            else:
                assert np.array_equal(a, b)
    assert steps[0][-1][3].all()  # the last step truncated every game
