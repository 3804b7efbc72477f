"""``hsv.aero``, ``hsv.flutter`` and ``hsv.linearize_grid`` against the CLI on the same config:
the same JSON summaries, and the grid's ``.npz`` read back by numpy (an independent reader of
the format hsv-run writes) holding the arrays the package returns."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

import hsv


def _without_timing(summary: dict) -> dict:
    """A summary without what differs between two runs of the same thing (wall times)."""
    text = json.dumps(summary)
    summary = json.loads(text)
    for row in summary.get("models", []):
        row.pop("evaluation_time_s", None)
    return summary


def test_aero_equals_cli(cli):
    flags = dict(mach=6.5, alpha_deg=2.0, model=["shock-expansion", "newtonian-vector"])
    ours = _without_timing(hsv.aero(None, **flags))
    theirs = _without_timing(json.loads(cli(
        "aero", "--mach", "6.5", "--alpha-deg", "2", "--model", "shock-expansion",
        "--model", "newtonian-vector", "--json")))
    assert ours == theirs


def test_aero_flags_are_checked_as_the_cli_checks_them():
    with pytest.raises(hsv.HsvError, match="--alpha-deg must be a finite angle"):
        hsv.aero(None, alpha_deg=720)
    with pytest.raises(hsv.ConfigError, match="unexpected argument '--no-such-flag'"):
        hsv.aero(None, no_such_flag=1)


def test_flutter_equals_cli(cli, tmp_path):
    flags = ["--mach-range", "4:6", "--mach-step", "1", "--times-s", "0,1",
             "--conduction", "full-order"]
    ours = hsv.flutter(None, mach_range="4:6", mach_step=1, times_s=[0, 1],
                       conduction="full-order", out=str(tmp_path / "py"))
    theirs = json.loads(cli("flutter", *flags, "--out", str(tmp_path / "cli"), "--json"))
    for key in ("mach_grid", "times_s", "boundaries", "buckled_melting_or_failed_points",
                "flutter_mach_first_time", "divergence_mach_last_time", "models"):
        assert ours[key] == theirs[key], key
    assert (tmp_path / "py" / "summary.json").exists()


def test_linearize_grid_is_the_cli_npz(cli, tmp_path):
    grid = hsv.linearize_grid(None, [6.0], [25_000.0, 200_000.0])
    cli("linearize", "--grid", "--mach", "6", "--altitude-m", "25000,200000",
        "--out", str(tmp_path / "grid"))
    npz = np.load(tmp_path / "grid" / "linear_models.npz")
    for name in npz.files:
        if npz[name].dtype.kind == "U":
            assert list(npz[name]) == list(grid[name]), name
        else:
            np.testing.assert_array_equal(npz[name], grid[name], err_msg=name)
    nx = len(grid["state_names"])
    assert grid["A"].shape == (1, 2, nx, nx)
    assert grid["ok"].tolist() == [[True, False]]
    assert np.isnan(grid["A"][0, 1]).all()
    assert "outside the US Standard Atmosphere 1976" in grid["errors"][1]
    # The same grid as MATLAB reads it (scipy's reader standing in for MATLAB).
    from scipy.io import loadmat
    hsv.save_mat(grid, tmp_path / "grid.mat")
    mat = loadmat(tmp_path / "grid.mat")
    for name in ("A", "B", "C", "D", "x0", "u0", "mach", "altitude_m"):
        expected = np.asarray(grid[name])
        if expected.ndim == 1:  # MATLAB has no 1-D arrays: axes are columns
            expected = expected.reshape(-1, 1)
        np.testing.assert_array_equal(mat[name], expected, err_msg=name)
    assert mat["ok"].tolist() == [[1, 0]]
    assert [c[0] for c in mat["state_names"][:, 0]] == list(grid["state_names"])
    assert mat["errors"][0, 0][0].startswith("1: ")


def test_linearize_grid_point_is_linearize_and_the_call_pickles(vehicle):
    """A consistency check, not a validation (the linear model's physics is tested against
    Lanchester's phugoid and the two-state short period in hsv-run/tests/linearize.rs): the
    grid at the config's own point lands in its slot as `linearize` gives it there, and the
    function and its arguments pickle, as Dask or Ray need."""
    call = pickle.loads(pickle.dumps((hsv.linearize_grid, (None, [6.0], [26_000.0]))))
    grid = call[0](*call[1])
    alone = vehicle.linearize()
    np.testing.assert_array_equal(grid["A"][0, 0], alone["A"])
    np.testing.assert_array_equal(grid["B"][0, 0], alone["B"])
    assert list(grid["state_names"]) == list(alone["state_names"])
