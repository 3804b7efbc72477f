"""Shared fixtures: the sample vehicle, its trimmed flights (each trim takes seconds, so they are
built once per session) and the `hsv-run` binary the results are compared with."""

from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

import hsv

ROOT = pathlib.Path(__file__).resolve().parents[2]


def hsv_run_binary() -> pathlib.Path:
    """`$HSV_RUN`, else the workspace's release or test-profile build of `hsv-run`."""
    if "HSV_RUN" in os.environ:
        return pathlib.Path(os.environ["HSV_RUN"])
    for profile in ("release", "debug"):
        candidate = ROOT / "target" / profile / "hsv-run"
        if candidate.exists():
            return candidate
    raise RuntimeError("no hsv-run binary: run `cargo build -p hsv-run` or set HSV_RUN")


@pytest.fixture(scope="session")
def cli():
    """Runs `hsv-run ARGS...` and returns its stdout; a failure shows its stderr."""
    binary = hsv_run_binary()

    def run(*args: str) -> str:
        done = subprocess.run([str(binary), *args], capture_output=True, text=True)
        if done.returncode != 0:
            raise AssertionError(f"hsv-run {' '.join(args)} exited {done.returncode}:\n"
                                 f"{done.stderr}")
        return done.stdout

    return run


@pytest.fixture(scope="session")
def vehicle():
    return hsv.Vehicle()


@pytest.fixture(scope="session")
def scheduled(vehicle):
    """The trimmed flexible partitioned flight under the `schedule` controller (the doublet)."""
    return hsv.Simulation(vehicle, controller="schedule")


@pytest.fixture(scope="session")
def external(vehicle):
    """The same flight commanded from Python."""
    return hsv.Simulation(vehicle)
