"""One adaptive run as plain data (:class:`Recipe`): what a hunt draws, a counterexample stores and a replay rebuilds.

A recipe names a scene (built in, :data:`inertiaproof.scene.robots.BUILTIN`, or a scene file) and changes what a
run may change: the gains of its ``[adaptive]`` table, the reference, the loads (a payload of its own, or every
load's profile moved to another start and duration), the law, the plant and the horizon. Equal recipes share
their scene, trajectory and law objects, so that a batch of runs evaluates each trajectory once.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Payload, Profile
from inertiaproof.errors import read_text
from inertiaproof.model import solids
from inertiaproof.scene import robots
from inertiaproof.scene.format import load_scene, parse_scene

from .adaptive import make_law
from .tracking import scene_specs

__all__ = ["Recipe", "scene_of"]

PAYLOAD_RADIUS = 0.05  # m: a drawn payload is a uniform sphere about the last body's frame origin


@lru_cache(maxsize=64)
def scene_of(key, text=None):
    """The scene a recipe names: a built-in one, else the scene file ``key`` (its ``text`` where given)."""
    if key in robots.BUILTIN:
        return robots.BUILTIN[key]()
    return load_scene(key) if text is None else parse_scene(text, key)


def _timed(load, start, duration):
    if isinstance(load, MovingMass):
        return dataclasses.replace(load, path=dataclasses.replace(
            load.path, profile=dataclasses.replace(load.path.profile, start=start, duration=duration)))
    return dataclasses.replace(load, profile=dataclasses.replace(load.profile, start=start, duration=duration))


@lru_cache(maxsize=256)
def _trajectory(key, text, payload, timing):
    trajectory = scene_of(key, text).trajectory
    loads = trajectory.loads
    if payload is not None:
        mass, start, ramp = payload
        loads = () if mass == 0 else (Payload(trajectory.bodies - 1, solids.solid("sphere", mass, (PAYLOAD_RADIUS,)),
                                              Profile("smootherstep", start, ramp)),)
    if timing is not None:
        loads = tuple(_timed(load, *timing) for load in loads)
    return ParameterTrajectory(trajectory.base, loads, trajectory.span)


@lru_cache(maxsize=256)
def _law(name, gain):
    return make_law(name, gain)


@dataclass(frozen=True)
class Recipe:
    scene: str  # a key of robots.BUILTIN or a scene file
    law: str
    plant: str = "gre"
    horizon: float | None = None  # None: the scene's
    lam: float | None = None  # None: the scene's [adaptive] value (likewise kd, gamma, estimate)
    kd: float | None = None
    gamma: float | None = None
    estimate: tuple | None = None  # one factor, or one per body
    amplitude: float | None = None  # None: the scene's [control] reference (likewise frequency, home)
    frequency: float | None = None
    home: tuple | None = None
    payload: tuple | None = None  # (mass kg, start s, ramp s): replaces the scene's loads (mass 0: none)
    timing: tuple | None = None  # (start s, duration s) of every load's profile (a ramp, a trolley's traverse)
    scene_text: str | None = None  # a scene file's text, as a saved recipe carries it (None: read the file)

    def scene_object(self):
        """The scene with the recipe's reference and gains."""
        scene = scene_of(self.scene, self.scene_text)
        control = dataclasses.replace(scene.control, **{k: v for k, v in (
            ("amplitude", self.amplitude), ("frequency", self.frequency), ("home", self.home)) if v is not None})
        gamma = dict(scene.adaptive.gamma)
        if self.gamma is not None:
            gamma[self.law] = self.gamma
        adaptive = dataclasses.replace(scene.adaptive, gamma=tuple(sorted(gamma.items())), **{k: v for k, v in (
            ("lam", self.lam), ("kd", self.kd), ("estimate", self.estimate)) if v is not None})
        return dataclasses.replace(scene, control=control, adaptive=adaptive)

    def spec(self):
        scene = self.scene_object()
        spec = scene_specs(scene, [self.law], [self.plant],
                           trajectory=_trajectory(self.scene, self.scene_text, self.payload, self.timing))[0]
        return dataclasses.replace(spec, law=_law(self.law, scene.adaptive.gain(self.law)))

    def run_horizon(self):
        return self.horizon if self.horizon is not None else scene_of(self.scene, self.scene_text).horizon()

    def chain(self):
        return scene_of(self.scene, self.scene_text).chain

    def to_data(self):
        """Plain data; a scene file's text goes with it, so that the data replays without the file."""
        text = self.scene_text
        if text is None and self.scene not in robots.BUILTIN:
            text = read_text(self.scene, "scene file")
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in dataclasses.asdict(self).items()
                if v is not None} | ({"scene_text": text} if text is not None else {})

    @classmethod
    def from_data(cls, data):
        known = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: (tuple(np.asarray(v, float).tolist()) if isinstance(v, list) else v)
                      for k, v in data.items() if k in known})
