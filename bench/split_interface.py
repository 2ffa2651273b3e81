"""The chain split at a body (:mod:`inertiaproof.bounds.interface`) at the deep budget (20 s): the certified lower
bound of inf lambda_min(M) (Theorem 2, Panda with its 2 kg payload ramp and UR5) and of inf sigma_min(QJ)^2
(Definition 2, unit bodies) against the smallest of 50,000 sampled values, with seconds and the ladder's note.
Printed, nothing is written or asserted (the measurements quoted in :mod:`inertiaproof.bounds.interface`).

    python bench/split_interface.py
"""

from __future__ import annotations

import time

import numpy as np

from inertiaproof.bounds.domain import free_coordinates, search_box
from inertiaproof.bounds.interface import split_ladder
from inertiaproof.bounds.lengths import unit_bodies
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.scene import robots


def main():
    for scene in (robots.panda(payload=2.0), robots.ur5()):
        chain, lo_hi = scene.chain, search_box(scene.chain)
        q = np.where(free_coordinates(chain), lo_hi[0] + (lo_hi[1] - lo_hi[0]) * np.random.default_rng(0).random(
            (50000, chain.n)), 0.5 * (lo_hi[0] + lo_hi[1]))
        for name, thetas in (("Thm2", parameter_vertices(scene.trajectory)[0]), ("Def2", unit_bodies(chain))):
            observed = float(np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], thetas[None]))[..., 0].min())
            start = time.perf_counter()
            gamma, note, _ = split_ladder(chain, thetas, observed, 800)
            print(f"{scene.name} {name}: {observed / gamma:.4g}x in {time.perf_counter() - start:.1f} s; {note}")


if __name__ == "__main__":
    main()
