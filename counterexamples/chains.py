"""Random serial chains: revolute and prismatic joints, n up to 7, DH rows or general axes, millimetres to tens of
metres, with any of the coordinate maps q -> g(q) of the chain (identity, cubic, arctan) where asked."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from hypothesis import strategies as st
from inertiaproof.counterexamples.inertias import log_uniform

from inertiaproof.dynamics.chain import Chain, Coordinate, Joint, origin

__all__ = ["chains", "chains_with_configurations", "unit_floats"]

unit_floats = st.floats(-1.0, 1.0, allow_nan=False)


@st.composite
def chains(draw, max_joints=7, scale=(1e-3, 30.0), prismatic=True, kinds="RRRP", coordinates=("identity",)):
    """A chain with its length scale; prismatic joints slide within +-2 scale (a mapped coordinate within +-1).

    ``kinds`` are the letters joint kinds are drawn from (``prismatic=False``: revolute only), ``coordinates``
    the names of :data:`~inertiaproof.dynamics.chain.COORDINATE_MAPS` a joint's map is drawn from.
    """
    n = draw(st.integers(1, max_joints))
    length = draw(log_uniform(*scale))
    kinds = "".join(draw(st.sampled_from(kinds if prismatic else "R")) for _ in range(n))
    maps = [draw(st.sampled_from(coordinates)) for _ in range(n)] if len(coordinates) > 1 else [coordinates[0]] * n
    limits = [None if k == "R" or c != "identity" else (-2 * length, 2 * length) for k, c in zip(kinds, maps)]
    if draw(st.booleans()):
        rows = [(length * draw(unit_floats), draw(st.sampled_from([0.0, np.pi / 2, -np.pi / 2, draw(unit_floats) * np.pi])),
                 length * draw(unit_floats), 0.0) for _ in range(n)]
        chain = Chain.from_dh(rows, convention=draw(st.sampled_from(["standard", "modified"])), kinds=kinds,
                              name=f"random DH {kinds}", coordinates=dict(enumerate(maps)))
        return Chain(tuple(replace(j, limits=lim) for j, lim in zip(chain.joints, limits)), name=chain.name), length
    joints = []
    for k, kind in enumerate(kinds):
        axis = np.array([draw(unit_floats) for _ in range(3)]) + np.array([0, 0, 1e-3])
        before = origin(length * np.array([draw(unit_floats) for _ in range(3)]),
                        np.pi * np.array([draw(unit_floats) for _ in range(3)]))
        joints.append(Joint("revolute" if kind == "R" else "prismatic", tuple(axis), before=before,
                            coordinate=Coordinate(maps[k]), limits=limits[k], name=f"joint{k + 1}"))
    return Chain(tuple(joints), name=f"random general-axis {kinds}"), length


@st.composite
def chains_with_configurations(draw, kinds, coordinates, samples=8, max_joints=5):
    """(chain, configurations (samples, n) uniform in its coordinate box, velocities (samples, n) in [-1, 1]) for
    joints of ``kinds`` and maps ``coordinates``."""
    chain, _ = draw(chains(max_joints=max_joints, kinds=kinds, coordinates=coordinates))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    lo, hi = chain.coordinate_box()
    return chain, lo + (hi - lo) * rng.random((samples, chain.n)), rng.uniform(-1.0, 1.0, (samples, chain.n))
