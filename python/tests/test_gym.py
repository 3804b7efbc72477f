"""The Gymnasium environment: Gymnasium's own API checker, reproducible resets, termination."""

from __future__ import annotations

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import hsv  # noqa: E402
import hsv.gym  # noqa: E402,F401  (registers hsv/HsvCruise-v0)


@pytest.fixture(scope="module")
def env(vehicle):
    return hsv.gym.HsvCruise(vehicle, heating=False, max_episode_s=0.5, random_steps=True)


def test_env_checker_passes(env):
    from gymnasium.utils.env_checker import check_env

    check_env(env, skip_render_check=True)


def test_registered_id_makes_the_environment():
    assert "hsv/HsvCruise-v0" in gymnasium.registry


def test_same_seed_same_episode(env):
    def episode(seed):
        obs, info = env.reset(seed=seed)
        rows = [obs]
        action = np.array([env.sim.trim["elevon_deg"] + 0.5,
                           env.sim.trim["fuel_equivalence_ratio"]])
        for _ in range(5):
            obs, reward, terminated, truncated, _ = env.step(action)
            rows.append(np.append(obs, reward))
        return info["targets"], rows

    t1, r1 = episode(7)
    t2, r2 = episode(7)
    t3, _ = episode(8)
    assert t1 == t2 and t1 != t3
    for a, b in zip(r1, r2):
        assert np.array_equal(a, b)


def test_trim_action_holds_the_trim_until_truncation(env):
    """Trim commands with no commanded steps: α stays at trim (the unstable short period
    grows from the trim's residual only) and the episode ends by truncation at 0.5 s."""
    obs, _ = env.reset(options={"altitude_step_m": 0.0, "airspeed_step_m_s": 0.0})
    action = np.array([env.sim.trim["elevon_deg"], env.sim.trim["fuel_equivalence_ratio"]])
    alpha0 = obs[2]
    terminated = truncated = False
    steps = 0
    while not (terminated or truncated):
        obs, _, terminated, truncated, _ = env.step(action)
        steps += 1
    assert truncated and not terminated and steps == 50
    assert abs(obs[2] - alpha0) < 0.05
