"""Steps per second of SimpleSoccer as a Gymnasium vector environment (docs/research/gymnasium.md): the
batched SimpleSoccerVectorEnv (all sub-environments in one GameBatch) against Gymnasium's own
SyncVectorEnv over as many single SimpleSoccerEnv, and against the engine used directly
(GameBatch.act with the same actions, restarting finished games itself), in one run.

    python benchmarks/gym_throughput.py [--envs 100] [--steps 600] [--sync-steps 100] [--seed 0] [--repeats 5]

Every side plays the same pre-drawn random actions (skills and parameters) from the same seeds, so
it plays the same games; an agent's own cost is not timed. Games last --max-ticks (250: several
autoresets per run, and no idle ending), so restarts are part of the figure. A step is one tick of
one sub-environment. SyncVectorEnv is the slow side: it plays the first --sync-steps steps only.
Every side is warmed up first so numba compilation is not timed; the sides then take turns --repeats
times and each keeps its best round (on a busy machine one round may wait for a core).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from gymnasium.vector import SyncVectorEnv

from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import GameBatch
from soccer_lab.soccer.gym.env import NO_CONTROLLER, SimpleSoccerEnv
from soccer_lab.soccer.gym.vector import SimpleSoccerVectorEnv
from results import Figure, add_record_option, load_average, record, this_command  # benchmarks/results.py


def random_actions(envs: SimpleSoccerVectorEnv, steps: int, rng: np.random.Generator) -> list[dict]:
    space = envs.single_action_space
    box = space["parameters"]
    shape = (steps, envs.num_envs)
    skills = rng.integers(0, space["skill"].n, shape)
    parameters = rng.uniform(box.low, box.high, (*shape, box.shape[0]))
    return [{"skill": skills[t], "parameters": parameters[t]} for t in range(steps)]


def time_vector(envs, actions: list[dict], seed: int) -> float:
    envs.reset(seed=seed)
    start = time.perf_counter()
    for action in actions:
        envs.step(action)
    return time.perf_counter() - start


def time_engine(config: GameConfig, envs: SimpleSoccerVectorEnv, actions: list[dict], seed: int) -> float:
    """The engine alone: GameBatch.act, each finished game restarted from the next seed."""
    n = envs.num_envs
    batch = GameBatch([NO_CONTROLLER] * n, [seed + g for g in range(n)], config, envs.vocabulary)
    engine_actions = [envs.spaces.engine_actions(action, n) for action in actions]
    next_seed = seed + n
    start = time.perf_counter()
    for skills, values in engine_actions:
        batch.act(skills, values)
        for g in np.flatnonzero(batch.state.done):
            batch.restart(int(g), next_seed)
            next_seed += 1
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--envs", type=int, default=100)
    parser.add_argument("--steps", type=int, default=600)
    parser.add_argument("--sync-steps", type=int, default=100)
    parser.add_argument("--max-ticks", type=int, default=250)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeats", type=int, default=5, help="rounds, the sides taking turns; each side's best")
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    config = GameConfig(max_ticks=args.max_ticks, idle_ticks=args.max_ticks)
    batched = SimpleSoccerVectorEnv(args.envs, config=config)
    synced = SyncVectorEnv([lambda: SimpleSoccerEnv(config=config) for _ in range(args.envs)])
    actions = random_actions(batched, args.steps, np.random.default_rng(args.seed))
    for envs in (batched, synced):  # compile / load the numba cache
        time_vector(envs, actions[:3], args.seed)
    time_engine(config, batched, actions[:3], args.seed)

    sync_steps = min(args.sync_steps, args.steps)
    best = {"batched": np.inf, "sync": np.inf, "engine": np.inf}  # seconds; the sides take turns, best kept
    for _ in range(args.repeats):
        best["batched"] = min(best["batched"], time_vector(batched, actions, args.seed))
        best["sync"] = min(best["sync"], time_vector(synced, actions[:sync_steps], args.seed))
        best["engine"] = min(best["engine"], time_engine(config, batched, actions, args.seed))
    per_second = {"batched": args.envs * args.steps / best["batched"], "sync": args.envs * sync_steps / best["sync"],
                  "engine": args.envs * args.steps / best["engine"]}
    print(f"{args.envs} sub-environments, random actions, games of {args.max_ticks} ticks (autoreset), "
          f"load average before {load_before}")
    print(f"SimpleSoccerVectorEnv (one GameBatch): {per_second['batched']:10,.0f} steps/s")
    print(f"SyncVectorEnv over SimpleSoccerEnv:    {per_second['sync']:10,.0f} steps/s ({sync_steps} steps)")
    print(f"GameBatch.act directly:                {per_second['engine']:10,.0f} steps/s")
    print(f"batched / sync: {per_second['batched'] / per_second['sync']:.1f}x, "
          f"batched / engine: {per_second['batched'] / per_second['engine']:.2f}x")
    if args.record:
        record("gym_throughput", [
            Figure(f"Gymnasium vector env, {args.envs} SimpleSoccer games in one batch, random actions",
                   round(per_second["batched"]), "steps/s"),
            Figure("the same against SyncVectorEnv over single environments",
                   round(per_second["batched"] / per_second["sync"], 1), "× faster", target="≥ 10×"),
            Figure("the same against the engine used directly (GameBatch.act)",
                   round(per_second["batched"] / per_second["engine"], 2), "× its speed", target="≥ 0.5×"),
        ], command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
