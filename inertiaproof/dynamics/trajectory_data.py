"""Parameter trajectories as plain JSON-ready data and back (for replayable counterexamples)."""

from __future__ import annotations

import dataclasses

import numpy as np

from .trajectory import MovingMass, ParameterTrajectory, Path, Payload, Profile, Scaling

__all__ = ["trajectory_from_data", "trajectory_to_data"]

_TYPES = {cls.__name__: cls for cls in (MovingMass, Path, Payload, Profile, Scaling)}


def _plain(value):
    if dataclasses.is_dataclass(value):
        return {"type": type(value).__name__,
                **{f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}}
    if isinstance(value, np.ndarray):
        return {"array": value.tolist()}
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return float(value) if np.isfinite(value) else str(float(value))
    if isinstance(value, np.integer):
        return int(value)
    return value


def _restore(value, field_name=None):
    if isinstance(value, dict) and "array" in value:
        return np.asarray(value["array"], float)
    if isinstance(value, dict) and "type" in value:
        cls = _TYPES[value["type"]]
        return cls(**{k: _restore(v, k) for k, v in value.items() if k != "type"})
    if isinstance(value, list):
        return tuple(_restore(v) for v in value)
    if isinstance(value, str) and value in ("inf", "-inf", "nan"):
        return float(value)
    return value


def trajectory_to_data(trajectory: ParameterTrajectory):
    """{"base", "loads", "span"} with arrays as lists and non-finite numbers as strings."""
    return {"base": np.asarray(trajectory.base, float).tolist(), "loads": [_plain(x) for x in trajectory.loads],
            "span": [_plain(float(x)) for x in trajectory.span]}


def trajectory_from_data(data):
    """The trajectory :func:`trajectory_to_data` wrote."""
    return ParameterTrajectory(np.asarray(data["base"], float), tuple(_restore(x) for x in data["loads"]),
                               tuple(float(x) for x in data["span"]))
