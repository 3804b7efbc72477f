"""hsv from Python: the partitioned aerothermoelastic hypersonic vehicle of Klock & Cesnik.

The native module ``hsv._hsv`` is the Rust simulator itself (the ``hsv-run`` library); this
package turns its JSON into dicts and its tables into numpy arrays.

>>> import hsv
>>> v = hsv.Vehicle()                      # the embedded sample vehicle
>>> v.trim(rigid=True)["trim"]["alpha_deg"]
>>> lin = v.linearize()                    # A, B, C, D as numpy arrays, with names
>>> sim = hsv.Simulation(v)                # trimmed; commands from sim.step(u)
>>> y = sim.step([elevon_deg, 0.0, phi], n=10)

Units are SI with angles in degrees at the interface, as in the CLI; every name carries its
unit (``altitude_m``, ``q_deg_s``). Errors are ``hsv.HsvError``; a refused config is its
subclass ``hsv.ConfigError``, whose message names the file, the key path and what is allowed.
"""

from __future__ import annotations

import json
import os
from typing import Any, Callable, Mapping, Optional, Union

import numpy as np

from . import _hsv
from ._hsv import ConfigError, HsvError

__all__ = [
    "ConfigError",
    "HsvError",
    "Simulation",
    "Vehicle",
    "aero",
    "flutter",
    "linearize_grid",
    "save_mat",
    "models",
    "sample_config",
]


def models() -> list:
    """Every registered model: dicts of name, family, role, fidelity, summary, origin."""
    return json.loads(_hsv.models_json())


def sample_config() -> dict:
    """The embedded sample vehicle's config as a dict, to edit and pass to ``Vehicle``."""
    return json.loads(_hsv.sample_config_json())


def _plain(value: Any) -> Any:
    """numpy scalars and arrays as plain numbers and lists for JSON."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"a value of type {type(value).__name__} is no config value")


def _flags(options: Mapping[str, Any], repeated: tuple = ()) -> list:
    """Keyword options as a command's flags: ``mach_range="4:8"`` is ``--mach-range 4:8``,
    ``True`` a bare flag, ``False`` and ``None`` none, a list comma separated (or the flag
    repeated for the names in ``repeated``)."""
    def text(value: Any) -> str:
        return str(value.item() if isinstance(value, np.generic) else value)

    flags = []
    for key, value in options.items():
        flag = "--" + key.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            flags.append(flag)
        elif isinstance(value, (list, tuple, np.ndarray)):
            items = [text(v) for v in value]
            if key in repeated:
                for item in items:
                    flags += [flag, item]
            else:
                flags += [flag, ",".join(items)]
        else:
            flags += [flag, text(value)]
    return flags


class Vehicle:
    """A vehicle config, checked as the CLI checks it.

    ``config``: None for the embedded sample vehicle, a path to a TOML file, or a dict of the
    same tables (``sample_config()`` gives the sample's to start from).
    """

    def __init__(self, config: Union[None, str, os.PathLike, Mapping[str, Any]] = None):
        if config is None:
            self._native = _hsv.Vehicle()
        elif isinstance(config, Mapping):
            try:
                text = json.dumps(config, allow_nan=False, default=_plain)
            except (TypeError, ValueError) as e:
                raise ConfigError(f"<dict>: not a config: {e}") from None
            self._native = _hsv.Vehicle(json_text=text, name="<dict>")
        elif isinstance(config, (str, os.PathLike)):
            self._native = _hsv.Vehicle(path=os.fspath(config))
        else:
            raise ConfigError(
                f"config must be None, a path or a dict, got {type(config).__name__}")

    @property
    def file(self) -> str:
        """The file (or ``<dict>``) the config came from."""
        return self._native.file

    @property
    def flight_condition(self) -> tuple:
        """The config's flight condition: (Mach, altitude m)."""
        return self._native.flight_condition

    def config_toml(self) -> str:
        """The config as TOML text."""
        return self._native.config_toml()

    def trim(self, rigid: bool = False, mach: Optional[float] = None,
             altitude_m: Optional[float] = None) -> dict:
        """Steady level flight (paper Eq. 2): the dict ``hsv-run trim --json`` prints."""
        return json.loads(self._native.trim_json(rigid=rigid, mach=mach, altitude_m=altitude_m))

    def linearize(self, relative: Optional[float] = None,
                  absolute: Optional[float] = None) -> dict:
        """The trimmed flexible vehicle's linear model x' = A x + B u, y = C x + D u.

        Returns a dict: ``A``, ``B``, ``C``, ``D``, ``x0``, ``u0`` (numpy arrays; deviations
        from x0, u0), ``state_names``, ``input_names``, ``output_names`` and ``modes`` (named
        eigenvalues: short period, phugoid, structural modes, ...).
        """
        lin = self._native.linearize(relative=relative, absolute=absolute)
        lin["modes"] = json.loads(lin.pop("modes_json"))
        return lin


    def aero(self, **options) -> dict:
        """``hsv-run aero --json`` on this vehicle: forces, moments and coefficients per aero
        model. Options are the command's flags as keywords (``mach=6``, ``alpha_deg=2``,
        ``model=["shock-expansion", "newtonian-vector"]``, ``all=True``, ``friction=True``)."""
        return json.loads(self._native.aero_json(_flags(options, repeated=("model",))))

    def flutter(self, **options) -> dict:
        """``hsv-run flutter --json`` on this vehicle: the flutter and divergence Mach of the
        heated lifting surface versus time in the flow, its run folder written as the command
        writes it (``out="dir"``). Options are the command's flags as keywords
        (``mach_range="4:8"``, ``times_s=[0, 10]``, ``conduction="full-order"``)."""
        return json.loads(self._native.flutter_json(_flags(options)))

    def linearize_grid(self, machs, altitudes_m, relative: Optional[float] = None,
                       absolute: Optional[float] = None) -> dict:
        """Linear models at every Mach × altitude point (``hsv-run linearize --grid``), side by
        side in Rust: a dict of numpy arrays ``A`` (Mach, altitude, states, states), ``B``,
        ``C``, ``D``, ``x0``, ``u0``, ``trim_alpha_deg``, ``trim_elevon_deg``,
        ``trim_fuel_equivalence_ratio``, ``ok`` (NaN and False where a point does not trim),
        the axes ``mach`` and ``altitude_m``, the names, and ``errors`` by flat point index."""
        return self._native.linearize_grid(
            [float(m) for m in np.atleast_1d(machs)],
            [float(h) for h in np.atleast_1d(altitudes_m)],
            relative=relative, absolute=absolute)


def aero(config: Union[None, str, os.PathLike, Mapping[str, Any]] = None, **options) -> dict:
    """``Vehicle(config).aero(**options)``: picklable arguments in, a dict out."""
    return Vehicle(config).aero(**options)


def flutter(config: Union[None, str, os.PathLike, Mapping[str, Any]] = None, **options) -> dict:
    """``Vehicle(config).flutter(**options)``: picklable arguments in, a dict out."""
    return Vehicle(config).flutter(**options)


def linearize_grid(config: Union[None, str, os.PathLike, Mapping[str, Any]], machs, altitudes_m,
                   relative: Optional[float] = None, absolute: Optional[float] = None) -> dict:
    """``Vehicle(config).linearize_grid(...)`` as a plain function of picklable arguments, for
    Dask, Ray or submitit to map over chunks of a grid (the GIL is released while Rust runs)."""
    return Vehicle(config).linearize_grid(machs, altitudes_m, relative=relative,
                                          absolute=absolute)


def save_mat(grid: Mapping[str, Any], path: Union[str, os.PathLike]) -> None:
    """Writes a ``linearize_grid`` result to a MATLAB ``.mat`` file (``scipy.io.savemat``,
    format 5, compressed) for MATLAB and Simulink gain-scheduling users: the arrays as they are
    (``A`` of shape (Mach, altitude, states, states), ...; ``ok`` as 0/1), the names as cell
    arrays of strings, and ``errors`` as a cell array of ``"<flat point index>: <message>"``.
    Needs scipy."""
    from scipy.io import savemat

    contents = {}
    for key, value in grid.items():
        if key == "errors":
            contents[key] = np.array([f"{i}: {m}" for i, m in sorted(value.items())],
                                     dtype=object).reshape(-1, 1)
        elif isinstance(value, (list, tuple)) or np.asarray(value).dtype.kind == "U":
            contents[key] = np.array([str(v) for v in value], dtype=object).reshape(-1, 1)
        elif np.asarray(value).dtype == bool:
            contents[key] = np.asarray(value, dtype=np.uint8)
        else:
            contents[key] = np.asarray(value)
    savemat(os.fspath(path), contents, do_compression=True, oned_as="column")


class Simulation:
    """The trimmed vehicle in flight, one aeroelastic step at a time (``hsv-run simulate``).

    ``controller``: None to command the vehicle yourself with ``step(u)`` (held from the trim
    commands), or a registered controller's name (``"schedule"``: the config's
    ``[simulation.inputs]``, default the paper's doublet; ``"lqr"``, ``"tracking"``). ``dt_s``
    is the aeroelastic step (paper Table 3: 1 ms). ``disturbances``: a ``[disturbances]`` table
    as a dict (``{"dryden": {"severity": "severe", "seed": 3}, "gusts": [...]}``) in place of
    the config's. Construction trims the vehicle (seconds).
    """

    def __init__(self, vehicle: Vehicle, dt_s: float = 0.001, controller: Optional[str] = None,
                 heating: bool = True, monolithic: bool = False,
                 lumped_surface_mass: bool = False,
                 disturbances: Optional[Mapping[str, Any]] = None):
        self._native = _hsv.Simulation(
            vehicle._native, dt_s=dt_s, controller=controller, heating=heating,
            monolithic=monolithic, lumped_surface_mass=lumped_surface_mass,
            disturbances_json=None if disturbances is None else json.dumps(dict(disturbances)))
        self.output_names = list(self._native.output_names)
        self.input_names = list(self._native.input_names)
        self._index = {name: i for i, name in enumerate(self.output_names)}

    @property
    def time_s(self) -> float:
        """Flight time, s."""
        return self._native.time_s

    @property
    def dt_s(self) -> float:
        """Aeroelastic step, s."""
        return self._native.dt_s

    @property
    def controller(self) -> str:
        """The controller flying the vehicle (``external``: your ``step(u)`` commands)."""
        return self._native.controller

    @property
    def trim(self) -> dict:
        """The trim the flight started from (a vehicle without an engine glides: φ 0 and a
        negative flight-path angle)."""
        alpha, elevon, phi, gamma = self._native.trim
        return {"alpha_deg": alpha, "elevon_deg": elevon, "fuel_equivalence_ratio": phi,
                "flight_path_angle_deg": gamma}

    @property
    def state(self) -> np.ndarray:
        """The vehicle state vector (names in ``state_names``)."""
        return self._native.state

    def state_dict(self) -> dict:
        """The vehicle state as plain data: the ``state`` of ``restart.json`` (rigid body, body
        and surface modal coordinates), exact to the last bit."""
        return json.loads(self._native.state_json())

    @property
    def state_names(self) -> list:
        return list(self._native.state_names)

    def index(self, name: str) -> int:
        """The position of output ``name`` in the arrays ``step`` and ``run`` return."""
        try:
            return self._index[name]
        except KeyError:
            raise KeyError(f"no output `{name}`; outputs are {', '.join(self.output_names)}")

    def outputs(self) -> np.ndarray:
        """The outputs now (names in ``output_names``)."""
        return self._native.outputs()

    def reset(self) -> np.ndarray:
        """Back to the trimmed flight at t = 0 (no new trim); the outputs there."""
        return self._native.reset()

    def snapshot(self) -> str:
        """Everything the next step depends on, as a JSON string: the steps taken, the vehicle
        state, its coupling guesses, thermal states and load histories, the control loop. Keep
        it to branch a flight (Monte Carlo from a common start, a learning agent's episodes)."""
        return self._native.run_state_json()

    def restore(self, snapshot: str) -> np.ndarray:
        """Back to a ``snapshot()`` of this flight (or of one built alike): the steps after it
        repeat those after it was taken, bit for bit. The outputs there."""
        return self._native.restore_json(str(snapshot))

    def step(self, u=None, n: int = 1) -> np.ndarray:
        """``n`` steps with commands ``u`` = (elevon deg, differential elevon deg, φ), absolute
        and held from now on (None keeps the last); the outputs at the end."""
        if u is not None:
            u = [float(x) for x in np.asarray(u, dtype=float).reshape(3)]
        if n < 0:
            raise HsvError(f"n must be >= 0, got {n}")
        return self._native.step(u, int(n))

    def run(self, duration_s: float, record_every: int = 1,
            inputs: Optional[Callable[[float, np.ndarray], Any]] = None) -> dict:
        """Flies ``duration_s`` under the flight's controller: a dict of numpy arrays, one per
        output (``history.csv``'s columns), sampled every ``record_every`` steps and at the
        start and end.

        ``inputs(t_s, outputs)``, for a flight you command (``controller=None``), returns the
        commands ``u`` of ``step`` for the next step (absolute, held over it): your control law
        in the loop at the aeroelastic rate, the whole run in one call. Without it the last
        commands are held and Rust runs the whole flight with the GIL released."""
        if inputs is None:
            rows = self._native.run(float(duration_s), int(record_every))
            return {name: rows[:, i].copy() for i, name in enumerate(self.output_names)}
        if self.controller != "external":
            raise HsvError(f"inputs command only a flight built with controller=None; this one "
                           f"is flown by `{self.controller}`")
        steps = round(float(duration_s) / self.dt_s)
        if steps < 0 or abs(steps * self.dt_s - float(duration_s)) > 1e-9 * self.dt_s:
            raise HsvError(f"duration_s {duration_s} is not a whole number of steps of "
                           f"{self.dt_s} s")
        every = max(int(record_every), 1)
        y = self.outputs()
        rows = [y]
        for k in range(steps):
            y = self.step(inputs(self.time_s, y), n=1)
            if (k + 1) % every == 0 or k + 1 == steps:
                rows.append(y)
        table = np.array(rows)
        return {name: table[:, i].copy() for i, name in enumerate(self.output_names)}
