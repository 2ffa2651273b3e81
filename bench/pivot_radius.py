"""The articulated-body pivot bound of lambda_min(M) on one box against the box's radius (issue 12): Panda with its
2 kg payload ramp, a box about the sampled minimiser of branch and bound (``mass_inf`` at 12 rounds) with
the same radius in every joint but the first; bound and value at the centre are printed, nothing is written or
asserted (the measurements quoted in :mod:`inertiaproof.bounds.pivots`).

    python bench/pivot_radius.py
"""

from __future__ import annotations

import numpy as np

from inertiaproof.bounds.configuration import mass_inf
from inertiaproof.bounds.pivots import PivotFamily, pivot_bounds
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.scene import robots


def main():
    scene = robots.panda(payload=2.0)
    chain, stack = scene.chain, parameter_vertices(scene.trajectory)[0]
    witness = mass_inf(chain, stack, samples=2000, rounds=12, rng=np.random.default_rng(0)).witness
    start = np.linalg.eigvalsh(composite.mass_matrix(chain, witness[None, None], stack[None]))[..., 0]
    lo, hi = chain.coordinate_box()
    for radius in (0.0, 0.01, 0.03, 0.1):
        r = np.minimum(radius, 0.5 * (hi - lo))[None]
        r[0, 0] = 0.0
        print(radius, float(pivot_bounds(PivotFamily(chain, stack), "lmin", witness[None], r, start)[0][0]))


if __name__ == "__main__":
    main()
