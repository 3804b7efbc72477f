"""``hsv.gym.HsvCruise``: hypersonic cruise of the flexible vehicle as a Gymnasium environment.

Registered as ``hsv/HsvCruise-v0`` when ``gymnasium`` is installed (``pip install ./python[gym]``).
The plant is ``hsv.Simulation`` with your commands: the trimmed flexible partitioned vehicle of
Klock & Cesnik at the config's flight condition (sample: Mach 6, 26 km), whose short period is
statically unstable (a real root near +1.8 /s), so an uncontrolled episode ends within seconds.

Action (``Box``, float64, physical units): ``[elevon_deg, fuel_equivalence_ratio]``, absolute
symmetric elevon in [-20, 20] deg (positive nose-up: trailing edge up) and fuel equivalence ratio φ in
[0, 1], held for ``steps_per_action`` aeroelastic steps of ``dt_s`` (default 10 × 1 ms: 100 Hz).

Observation (``Box``, float64): ``[altitude_error_m, airspeed_error_m_s, alpha_deg, pitch_deg,
q_deg_s, elevon_deg, fuel_equivalence_ratio]``: altitude and airspeed minus their targets (the
trim values plus the episode's commanded steps), angle of attack, pitch attitude, pitch rate and
the actuator positions.

Reward: ``-((altitude_error_m / 100)^2 + (airspeed_error_m_s / 10)^2 + (q_deg_s / 10)^2)`` per
step: track altitude and airspeed, damp the pitch rate.

Termination: the flight leaves the sample models' validity (|α| > ``max_alpha_deg``, altitude
more than ``max_altitude_error_m`` from the target) or the simulation stops on a non-finite
state. Truncation: after ``max_episode_s`` of flight.

``reset(seed=..., options={"altitude_step_m": dh, "airspeed_step_m_s": dv})`` returns to the trim
(no new trim) and sets the episode's commanded steps; with ``random_steps=True`` they are drawn
from ``np_random`` (uniform within ±``altitude_step_m``, ±``airspeed_step_m_s``), so the same seed
gives the same episode.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

import gymnasium
from gymnasium import spaces

from . import HsvError, Simulation, Vehicle

OBSERVATION_NAMES = (
    "altitude_error_m",
    "airspeed_error_m_s",
    "alpha_deg",
    "pitch_deg",
    "q_deg_s",
    "elevon_deg",
    "fuel_equivalence_ratio",
)
ACTION_NAMES = ("elevon_deg", "fuel_equivalence_ratio")


class HsvCruise(gymnasium.Env):
    """Altitude and airspeed tracking at hypersonic cruise (module docstring for the spaces)."""

    metadata = {"render_modes": []}

    def __init__(self, vehicle: Optional[Vehicle] = None, dt_s: float = 0.001,
                 steps_per_action: int = 10, max_episode_s: float = 5.0,
                 heating: bool = True, altitude_step_m: float = 100.0,
                 airspeed_step_m_s: float = 20.0, random_steps: bool = False,
                 max_alpha_deg: float = 10.0, max_altitude_error_m: float = 2000.0):
        super().__init__()
        if steps_per_action < 1:
            raise HsvError(f"steps_per_action must be >= 1, got {steps_per_action}")
        self.sim = Simulation(vehicle or Vehicle(), dt_s=dt_s, controller=None, heating=heating)
        self.steps_per_action = int(steps_per_action)
        self.max_steps = int(round(max_episode_s / (dt_s * steps_per_action)))
        self.altitude_step_m = float(altitude_step_m)
        self.airspeed_step_m_s = float(airspeed_step_m_s)
        self.random_steps = bool(random_steps)
        self.max_alpha_deg = float(max_alpha_deg)
        self.max_altitude_error_m = float(max_altitude_error_m)
        self.action_space = spaces.Box(low=np.array([-20.0, 0.0]), high=np.array([20.0, 1.0]),
                                       dtype=np.float64)
        big = np.finfo(np.float64).max
        self.observation_space = spaces.Box(low=-big, high=big, shape=(len(OBSERVATION_NAMES),),
                                            dtype=np.float64)
        self._columns = [self.sim.index(n) for n in
                         ("altitude_m", "airspeed_m_s", "alpha_deg", "pitch_deg", "q_deg_s",
                          "elevon_deg", "fuel_equivalence_ratio")]
        y0 = self.sim.outputs()
        self._trim_altitude_m = float(y0[self._columns[0]])
        self._trim_airspeed_m_s = float(y0[self._columns[1]])
        self._targets = (self._trim_altitude_m, self._trim_airspeed_m_s)
        self._steps = 0

    def _observation(self, y: np.ndarray) -> np.ndarray:
        v = y[self._columns]
        return np.array([v[0] - self._targets[0], v[1] - self._targets[1], *v[2:]],
                        dtype=np.float64)

    def reset(self, *, seed: Optional[int] = None,
              options: Optional[dict[str, Any]] = None):
        super().reset(seed=seed)
        options = options or {}
        if self.random_steps:
            dh = self.np_random.uniform(-self.altitude_step_m, self.altitude_step_m)
            dv = self.np_random.uniform(-self.airspeed_step_m_s, self.airspeed_step_m_s)
        else:
            dh, dv = self.altitude_step_m, self.airspeed_step_m_s
        dh = float(options.get("altitude_step_m", dh))
        dv = float(options.get("airspeed_step_m_s", dv))
        self._targets = (self._trim_altitude_m + dh, self._trim_airspeed_m_s + dv)
        self._steps = 0
        y = self.sim.reset()
        return self._observation(y), {"time_s": self.sim.time_s, "targets": self._targets}

    def step(self, action):
        a = np.clip(np.asarray(action, dtype=np.float64).reshape(2), self.action_space.low,
                    self.action_space.high)
        self._steps += 1
        try:
            y = self.sim.step([a[0], 0.0, a[1]], n=self.steps_per_action)
        except HsvError as e:
            obs = np.zeros(len(OBSERVATION_NAMES))
            return obs, -1e3, True, False, {"time_s": self.sim.time_s, "error": str(e)}
        obs = self._observation(y)
        reward = -float((obs[0] / 100.0) ** 2 + (obs[1] / 10.0) ** 2 + (obs[4] / 10.0) ** 2)
        terminated = bool(abs(obs[2]) > self.max_alpha_deg
                          or abs(obs[0]) > self.max_altitude_error_m
                          or not np.all(np.isfinite(obs)))
        truncated = self._steps >= self.max_steps
        return obs, reward, terminated, truncated, {"time_s": self.sim.time_s}


gymnasium.register(id="hsv/HsvCruise-v0", entry_point="hsv.gym:HsvCruise")
