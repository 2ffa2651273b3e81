"""Random serial chains: revolute and prismatic joints, n up to 7, DH rows or general axes, millimetres to tens of metres."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from hypothesis import strategies as st
from inertiaproof.counterexamples.inertias import log_uniform

from inertiaproof.dynamics.chain import Chain, Joint, origin

__all__ = ["chains", "unit_floats"]

unit_floats = st.floats(-1.0, 1.0, allow_nan=False)


@st.composite
def chains(draw, max_joints=7, scale=(1e-3, 30.0), prismatic=True):
    """A chain with its length scale; prismatic joints slide within +-2 scale."""
    n = draw(st.integers(1, max_joints))
    length = draw(log_uniform(*scale))
    kinds = "".join(draw(st.sampled_from("RRRP" if prismatic else "R")) for _ in range(n))
    limits = [None if k == "R" else (-2 * length, 2 * length) for k in kinds]
    if draw(st.booleans()):
        rows = [(length * draw(unit_floats), draw(st.sampled_from([0.0, np.pi / 2, -np.pi / 2, draw(unit_floats) * np.pi])),
                 length * draw(unit_floats), 0.0) for _ in range(n)]
        chain = Chain.from_dh(rows, convention=draw(st.sampled_from(["standard", "modified"])), kinds=kinds,
                              name=f"random DH {kinds}")
        return Chain(tuple(replace(j, limits=lim) for j, lim in zip(chain.joints, limits)), name=chain.name), length
    joints = []
    for k, kind in enumerate(kinds):
        axis = np.array([draw(unit_floats) for _ in range(3)]) + np.array([0, 0, 1e-3])
        before = origin(length * np.array([draw(unit_floats) for _ in range(3)]),
                        np.pi * np.array([draw(unit_floats) for _ in range(3)]))
        joints.append(Joint("revolute" if kind == "R" else "prismatic", tuple(axis), before=before,
                            limits=limits[k], name=f"joint{k + 1}"))
    return Chain(tuple(joints), name=f"random general-axis {kinds}"), length
