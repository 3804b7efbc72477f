"""An LQR designed in Python on hsv's linear model and flown on the full nonlinear vehicle.

The sample vehicle's short period is statically unstable (a real root near +1.8 /s): flown open
loop through the paper's elevon doublet it departs within seconds. This example takes the
trimmed flexible vehicle's linear model from ``Vehicle.linearize``, keeps its longitudinal
rigid-body states (u, w, q, θ, altitude; the structural modes are left out of the design, a
truncation, so the design model is the rigid vehicle's), solves the continuous algebraic Riccati
equation with scipy (Bryson's rule weights), and flies the nonlinear flexible partitioned
vehicle with ``Simulation.step``: full-state feedback of the rigid states at 100 Hz around the
trim, with the doublet added to the elevon command as a pilot input.

Run: ``python examples/lqr.py [--duration-s 3] [--plot lqr.png]``; prints the worst angle-of-
attack excursion with and without the controller.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from scipy.linalg import solve_continuous_are

import hsv

DESIGN_STATES = ("u_m_s", "w_m_s", "q_rad_s", "pitch_rad", "down_m")
DESIGN_INPUTS = ("symmetric_elevon_rad", "fuel_equivalence_ratio")
# Bryson's rule: the largest acceptable excursion of each state and input.
MAX_STATE = np.array([10.0, 5.0, math.radians(5.0), math.radians(5.0), 100.0])
MAX_INPUT = np.array([math.radians(5.0), 0.2])


def design(vehicle: hsv.Vehicle):
    """Gain K (inputs × design states), with the design model's index sets and trim."""
    lin = vehicle.linearize()
    xi = [lin["state_names"].index(n) for n in DESIGN_STATES]
    ui = [lin["input_names"].index(n) for n in DESIGN_INPUTS]
    a = lin["A"][np.ix_(xi, xi)]
    b = lin["B"][np.ix_(xi, ui)]
    q = np.diag(1.0 / MAX_STATE ** 2)
    r = np.diag(1.0 / MAX_INPUT ** 2)
    p = solve_continuous_are(a, b, q, r)
    k = np.linalg.solve(r, b.T @ p)
    closed = np.linalg.eigvals(a - b @ k)
    return k, lin["x0"][xi], lin["u0"][ui], np.linalg.eigvals(a), closed


def doublet_deg(t: float) -> float:
    """The paper's elevon doublet: +1° from 0.5 s to 1.5 s (ramps of 0.5 s), offsets from trim."""
    return float(np.interp(t, [0.0, 0.5, 1.0, 1.5, 2.0], [0.0, 0.0, 1.0, 1.0, 0.0]))


def rigid_state(sim: hsv.Simulation, y: np.ndarray) -> np.ndarray:
    """The design states from the simulation's outputs: u, w (m/s), q, θ (rad), down (m)."""
    g = lambda name: y[sim.index(name)]  # noqa: E731
    return np.array([g("u_m_s"), g("w_m_s"), math.radians(g("q_deg_s")),
                     math.radians(g("pitch_deg")), -g("altitude_m")])


def fly(sim: hsv.Simulation, duration_s: float, gain=None, x0=None, u0=None,
        steps_per_update: int = 10):
    """Flies ``duration_s`` with the doublet, closed loop when ``gain`` is given; the time and
    α, q histories at the controller's rate."""
    y = sim.reset()
    trim = sim.trim
    times, alphas, qs, elevons = [], [], [], []
    while sim.time_s < duration_s - 1e-12:
        elevon = trim["elevon_deg"] + doublet_deg(sim.time_s)
        phi = trim["fuel_equivalence_ratio"]
        if gain is not None:
            du = -gain @ (rigid_state(sim, y) - x0)
            elevon += math.degrees(du[0])
            phi = float(np.clip(phi + du[1], 0.0, 1.0))
        try:
            y = sim.step([elevon, 0.0, phi], n=steps_per_update)
        except hsv.HsvError:
            break  # left the models' validity: the open-loop departure
        times.append(sim.time_s)
        alphas.append(y[sim.index("alpha_deg")])
        qs.append(y[sim.index("q_deg_s")])
        elevons.append(y[sim.index("elevon_deg")])
    return np.array(times), np.array(alphas), np.array(qs), np.array(elevons)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration-s", type=float, default=3.0)
    parser.add_argument("--plot", help="write a PNG of α and q (needs matplotlib)")
    parser.add_argument("--no-heating", action="store_true")
    args = parser.parse_args(argv)

    vehicle = hsv.Vehicle()
    gain, x0, u0, open_roots, closed_roots = design(vehicle)
    print("design model roots (open):  ", np.array2string(np.sort_complex(open_roots), precision=3))
    print("design model roots (closed):", np.array2string(np.sort_complex(closed_roots), precision=3))
    print("K =", np.array2string(gain, precision=4))

    sim = hsv.Simulation(vehicle, heating=not args.no_heating)
    alpha_trim = sim.trim["alpha_deg"]
    open_loop = fly(sim, args.duration_s)
    closed_loop = fly(sim, args.duration_s, gain, x0, u0)
    result = {
        "open_max_alpha_excursion_deg": float(np.max(np.abs(open_loop[1] - alpha_trim))),
        "closed_max_alpha_excursion_deg": float(np.max(np.abs(closed_loop[1] - alpha_trim))),
        "closed_final_time_s": float(closed_loop[0][-1]),
        "closed_roots": closed_roots,
        "open_roots": open_roots,
    }
    print(f"max |α − α_trim|: open loop {result['open_max_alpha_excursion_deg']:.3f}°, "
          f"LQR {result['closed_max_alpha_excursion_deg']:.3f}°")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        for (t, a, q, _), label in ((open_loop, "open loop"), (closed_loop, "LQR")):
            ax1.plot(t, a, label=label)
            ax2.plot(t, q, label=label)
        ax1.set_ylabel("α (deg)")
        ax2.set_ylabel("q (deg/s)")
        ax2.set_xlabel("time (s)")
        ax1.legend()
        ax1.set_title("Paper's elevon doublet, Mach 6, 26 km: open loop vs LQR")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print("wrote", args.plot)
    return result


if __name__ == "__main__":
    main()
