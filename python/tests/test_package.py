"""The Python package against the CLI on the same config: the same registry, the same config
errors, the same trim and the same flight (the package and the CLI are two front ends of one
library, so they must agree to the last bit where the CLI prints bits, and to its CSV's ten
significant digits where it prints those)."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

import hsv


def test_models_are_the_cli_catalog(cli):
    assert hsv.models() == json.loads(cli("models", "--json"))


def test_unknown_key_is_a_config_error_naming_the_key_path():
    config = hsv.sample_config()
    config["flight"]["mach_number"] = 6.0
    with pytest.raises(hsv.ConfigError) as raised:
        hsv.Vehicle(config)
    assert "flight.mach_number" in str(raised.value) or "mach_number" in str(raised.value)
    assert "<dict>" in str(raised.value)


def test_missing_file_is_a_config_error_naming_the_file(tmp_path):
    missing = tmp_path / "absent.toml"
    with pytest.raises(hsv.ConfigError, match="absent.toml"):
        hsv.Vehicle(missing)


def test_non_finite_value_is_refused():
    config = hsv.sample_config()
    config["flight"]["mach"] = math.nan
    with pytest.raises(hsv.ConfigError):
        hsv.Vehicle(config)


def test_sample_config_round_trips(tmp_path, vehicle):
    path = tmp_path / "sample.toml"
    path.write_text(vehicle.config_toml())
    assert hsv.Vehicle(path).flight_condition == vehicle.flight_condition == (6.0, 26000.0)


def _close(a: float, b: float, rel: float) -> bool:
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


@pytest.mark.parametrize("rigid", [True, False])
def test_trim_equals_cli(cli, vehicle, rigid):
    ours = vehicle.trim(rigid=rigid)["trim"]
    theirs = json.loads(cli("trim", "--rigid" if rigid else "--flexible", "--json"))["trim"]
    for key in ("alpha_deg", "elevon_deg", "fuel_equivalence_ratio", "thrust_n", "drag_n"):
        assert _close(ours[key], theirs[key], 1e-12), (key, ours[key], theirs[key])


def _history(path) -> dict:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}


def test_run_equals_cli_history_and_restart_state(cli, tmp_path, scheduled):
    scheduled.reset()
    ours = scheduled.run(0.2, record_every=1)
    final_state = scheduled.state_dict()
    out = tmp_path / "run"
    cli("simulate", "--duration-s", "0.2", "--record-every", "1", "--vtk-interval-s", "0",
        "--quiet", "--out", str(out))
    # The flight's trim (the vehicle built for flight: body loads at the [simulation] rates).
    summary = json.loads((out / "summary.json").read_text())
    for key, value in scheduled.trim.items():
        assert _close(value, summary["trim"][key], 1e-12), (key, value, summary["trim"][key])
    theirs = _history(out / "history.csv")
    assert set(theirs) == set(ours)
    for name, column in theirs.items():
        # history.csv prints ten significant digits ({:.9e}): half a unit in the last place.
        np.testing.assert_allclose(ours[name], column, rtol=6e-10, atol=1e-300, err_msg=name)
    # restart.json carries the final state bit for bit (serde_json's float round trip).
    restart = json.loads((out / "restart.json").read_text())
    assert restart["step"] == 200
    assert final_state == restart["state"]


def test_reset_reproduces_the_flight_bit_for_bit(scheduled):
    scheduled.reset()
    first = scheduled.run(0.05, record_every=5)
    scheduled.reset()
    second = scheduled.run(0.05, record_every=5)
    for name in first:
        assert np.array_equal(first[name], second[name]), name
    assert scheduled.time_s == pytest.approx(0.05, abs=1e-15)


def test_a_snapshot_restores_the_flight_bit_for_bit(scheduled):
    scheduled.reset()
    scheduled.step(None, n=20)
    snap = scheduled.snapshot()
    first = scheduled.step(None, n=30)
    scheduled.reset()
    scheduled.restore(snap)
    assert scheduled.time_s == pytest.approx(0.02, abs=1e-15)
    second = scheduled.step(None, n=30)
    assert np.array_equal(first, second)
    with pytest.raises(hsv.HsvError):
        scheduled.restore("{}")


def test_commands_held_at_trim_fly_the_schedule_before_its_doublet(scheduled, external):
    """The paper's doublet starts at 0.5 s: until then the schedule commands the trim, so a
    host holding the trim commands flies the same flight, bit for bit."""
    scheduled.reset()
    external.reset()
    trim = external.trim
    u = [trim["elevon_deg"], 0.0, trim["fuel_equivalence_ratio"]]
    ours = external.step(u, n=100)
    theirs = scheduled.step(None, n=100)
    assert np.array_equal(ours, theirs)


def test_step_refuses_non_finite_commands(external):
    external.reset()
    with pytest.raises(hsv.HsvError):
        external.step([math.nan, 0.0, 0.5])


def test_linearize_gives_named_arrays(vehicle):
    lin = vehicle.linearize()
    n, m = len(lin["state_names"]), len(lin["input_names"])
    p = len(lin["output_names"])
    assert lin["A"].shape == (n, n) and lin["B"].shape == (n, m)
    assert lin["C"].shape == (p, n) and lin["D"].shape == (p, m)
    # Every named mode is an eigenvalue of A (both come from the same Jacobian; this checks
    # that the arrays handed to numpy are A, not its transpose or a copy in the wrong order).
    eig = np.linalg.eigvals(lin["A"])
    assert lin["modes"]
    # Roots slower than 0.1 rad/s (phugoid, spiral, the near-zero position roots) are
    # ill-conditioned in a 40-state Jacobian with finite-difference noise: two eigensolvers
    # (hsv's and LAPACK's) differ there by ~1e-4 /s, so only the faster ones are compared.
    fast = [m for m in lin["modes"] if m["natural_frequency_rad_s"] > 0.1]
    assert fast
    for mode in fast:
        s = complex(mode["real_per_s"], mode["imaginary_rad_s"])
        assert np.min(np.abs(eig - s)) <= 1e-6 * abs(s), mode
    assert lin["x0"].shape == (n,) and lin["u0"].shape == (m,)


def test_run_with_inputs_is_the_same_steps_taken_one_by_one(external):
    """`run(inputs=law)` asks the law once per aeroelastic step, at the step's start, and flies
    exactly what `step` flies with those commands."""
    external.reset()
    trim = external.trim
    u = [trim["elevon_deg"] + 0.5, 0.0, trim["fuel_equivalence_ratio"]]
    asked = []

    def law(t_s, outputs):
        asked.append(t_s)
        return u

    history = external.run(0.01, record_every=5, inputs=law)
    external.reset()
    last = external.step(u, n=10)
    assert np.array_equal([history[name][-1] for name in external.output_names], last)
    assert len(history["time_s"]) == 3
    assert asked == pytest.approx([k * 1e-3 for k in range(10)], abs=1e-15)


def test_inputs_command_only_a_flight_you_command(scheduled):
    with pytest.raises(hsv.HsvError, match="controller=None"):
        scheduled.run(0.001, inputs=lambda t_s, outputs: None)


def test_turbulence_from_python_is_the_cli_run(cli, tmp_path, vehicle):
    """`disturbances=` is `[disturbances]`: severe Dryden turbulence with seed 3 flies as
    `hsv-run simulate --turbulence severe --turbulence-seed 3` (ten significant digits)."""
    sim = hsv.Simulation(vehicle, controller="schedule",
                         disturbances={"dryden": {"severity": "severe", "seed": 3}})
    ours = sim.run(0.05, record_every=1)
    out = tmp_path / "turbulence"
    cli("simulate", "--duration-s", "0.05", "--record-every", "1", "--vtk-interval-s", "0",
        "--turbulence", "severe", "--turbulence-seed", "3", "--quiet", "--out", str(out))
    theirs = _history(out / "history.csv")
    assert np.abs(theirs["gust_w_m_s"]).max() > 0.0
    for name, column in theirs.items():
        np.testing.assert_allclose(ours[name], column, rtol=6e-10, atol=1e-300, err_msg=name)


def test_bad_disturbances_name_their_key(vehicle):
    with pytest.raises(hsv.HsvError, match="disturbances.dryden"):
        hsv.Simulation(vehicle, disturbances={"dryden": {"severity": "severe", "sigma_m_s": 1.0}})
    with pytest.raises(hsv.HsvError, match="wind"):
        hsv.Simulation(vehicle, disturbances={"wind": 3})


def test_regions_are_added_and_removed_by_configuration_alone():
    """Issue 25 item 5 from Python: a dict config without `[regions.propulsion]` trims for a
    glide, and one with the fin's two tables has a stable Dutch roll where the sample's yaw
    diverges (the CLI's closed-form checks are in hsv-run/tests/vertical_fin.rs)."""
    glide = hsv.sample_config()
    del glide["regions"]["propulsion"]
    trim = hsv.Vehicle(glide).trim(rigid=True)["trim"]
    assert trim["flight_path_angle_deg"] < -1.0, trim

    fin = hsv.sample_config()
    fin["vertical_fin"] = {
        "root_chord_m": 4.0, "tip_chord_m": 1.6, "height_m": 3.0,
        "leading_edge_sweep_deg": 38.66, "thickness_to_chord": 0.028,
        "max_thickness_chord_fraction": 0.5, "root_leading_edge_aft_of_nose_m": 25.0,
        "root_z_m": -1.415, "panels_chordwise": 10, "panels_spanwise": 8,
    }
    fin["regions"]["vertical_fin"] = {"aero": "shock-expansion-piston"}

    def lateral(vehicle):
        return [m for m in vehicle.linearize()["modes"] if m["content"]["lateral"] > 0.5]

    assert any(m["real_per_s"] > 0.5 for m in lateral(hsv.Vehicle()))
    with_fin = lateral(hsv.Vehicle(fin))
    assert all(m["real_per_s"] < 0.0 for m in with_fin), with_fin
    assert any(m["imaginary_rad_s"] > 0.1 for m in with_fin), with_fin
