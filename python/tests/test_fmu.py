"""The FMI 3.0 co-simulation FMU that `hsv-run fmu` packages, checked with fmpy 0.3.32: its
model description validates, its outputs are history.csv's flight-state columns, stepping it through the
paper's elevon doublet gives `hsv-run simulate`'s history, and host inputs fly it as
`Simulation.step` does."""

from __future__ import annotations

import csv
import os
import pathlib

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import read_model_description, simulate_fmu  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

# The paper's doublet (Fig. 10) ends at 2 s; its ramp starts at 0.5 s and peaks at 1 s.
DOUBLET_S = 2.0


def _history(path) -> dict:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}, header


def _flight_columns(history) -> list[str]:
    """history.csv's columns the FMU outputs: all but time (FMI's own) and the body's modal
    coordinates (as many as the config has modes)."""
    _, header = history
    return [n for n in header[1:] if not n.startswith("body_mode_")]


@pytest.fixture(scope="module")
def fmu(cli, tmp_path_factory) -> pathlib.Path:
    library = os.environ.get("HSV_FMU_LIBRARY")
    if not library:
        raise RuntimeError("set HSV_FMU_LIBRARY to the hsv_fmu library (python/run-tests does)")
    path = tmp_path_factory.mktemp("fmu") / "hsv.fmu"
    cli("fmu", "--library", library, "--out", str(path))
    return path


@pytest.fixture(scope="module")
def cli_doublet(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("doublet")
    cli("simulate", "--duration-s", str(DOUBLET_S), "--record-every", "10",
        "--vtk-interval-s", "0", "--quiet", "--out", str(out))
    return _history(out / "history.csv")


def test_model_description_validates(fmu):
    assert validate_fmu(str(fmu)) == []


def test_variables_are_the_trim_and_history_columns(fmu, cli_doublet, vehicle):
    description = read_model_description(str(fmu))
    assert description.fmiVersion == "3.0"
    assert description.coSimulation.modelIdentifier == "hsv_fmu"
    by_causality: dict[str, list] = {}
    for v in description.modelVariables:
        by_causality.setdefault(v.causality, []).append(v)
    assert [v.name for v in by_causality["output"]] == [
        "trim_alpha_deg", "trim_elevon_deg", "trim_fuel_equivalence_ratio",
        *_flight_columns(cli_doublet)]
    assert [v.name for v in by_causality["input"]] == [
        "elevon_offset_deg", "differential_elevon_command_deg", "fuel_equivalence_ratio_offset"]
    start = {v.name: v.start for v in by_causality["parameter"]}
    mach, altitude_m = vehicle.flight_condition
    assert float(start["trim_mach"]) == mach
    assert float(start["trim_altitude_m"]) == altitude_m
    assert start["controller"] == "external"


def test_doublet_through_the_fmu_is_simulate(fmu, cli_doublet):
    """The FMU's `schedule` controller flies the config's [simulation.inputs] (the paper's
    doublet) as `hsv-run simulate` does: every recorded quantity to 1e-9 relative (history.csv
    prints ten significant digits), communication steps of ten aeroelastic steps."""
    theirs, _ = cli_doublet
    names = _flight_columns(cli_doublet)
    ours = simulate_fmu(str(fmu), stop_time=DOUBLET_S, step_size=0.01, output_interval=0.01,
                        start_values={"controller": "schedule"}, output=names)
    np.testing.assert_allclose(ours["time"], theirs["time_s"], rtol=0, atol=1e-12)
    for name in names:
        np.testing.assert_allclose(ours[name], theirs[name], rtol=1e-9, atol=1e-300,
                                   err_msg=name)
    # The doublet is in there: the elevon went 1 degree above trim and came back.
    command = theirs["command_elevon_deg"]
    assert command.max() - command[0] == pytest.approx(1.0, abs=1e-9)


def test_host_inputs_fly_it_as_step_does(fmu, external):
    """Inputs are offsets from the trim commands, held over each communication step: a constant
    +0.5 degree elevon offset is `Simulation.step` with the trim elevon + 0.5 degrees."""
    duration_s, offset_deg = 0.05, 0.5
    signal = np.array([(0.0, offset_deg), (duration_s, offset_deg)],
                      dtype=[("time", float), ("elevon_offset_deg", float)])
    names = [n for n in external.output_names[1:] if not n.startswith("body_mode_")]
    ours = simulate_fmu(str(fmu), stop_time=duration_s, step_size=0.001,
                        output_interval=duration_s, input=signal, output=names)
    external.reset()
    trim = external.trim
    theirs = dict(zip(external.output_names,
                      external.step([trim["elevon_deg"] + offset_deg, 0.0,
                                     trim["fuel_equivalence_ratio"]], n=50)))
    for name in names:
        # The FMU and the wheel are separate builds of the same code: equal to rounding (a
        # lateral velocity of 3e-16 m/s is rounding itself).
        assert ours[name][-1] == pytest.approx(theirs[name], rel=1e-12, abs=1e-12), name
    assert ours["command_elevon_deg"][-1] == pytest.approx(trim["elevon_deg"] + offset_deg,
                                                           rel=1e-12)


def test_a_bad_step_or_controller_stops_with_the_reason(fmu, capfd):
    with pytest.raises(Exception):
        simulate_fmu(str(fmu), stop_time=0.003, step_size=0.0015, output_interval=0.0015)
    assert "not a whole number of aeroelastic steps" in capfd.readouterr().err
    with pytest.raises(Exception):
        simulate_fmu(str(fmu), stop_time=0.001, step_size=0.001,
                     start_values={"controller": "nonesuch"})
    assert "nonesuch" in capfd.readouterr().err
