"""Throughput of physical_consistency on 10^6 rows, against NumPy's batched Cholesky on the same bodies.

Writes bench/results/consistency_throughput.json: per variant the median,
minimum and maximum of ``--repeats`` timed runs in this process
(time.perf_counter, the variants interleaved round by round), rows per
second, and the median per-round ratio to Cholesky. Timings are measured,
never asserted; on a shared machine quote medians.

Variants (all on the same array of consistent bodies, since NumPy's batched
Cholesky raises for the whole batch when one matrix is not positive definite):

- ``verdicts_with_margins``: physical_consistency(phi)
- ``verdicts_only``: physical_consistency(phi, margins=False)
- ``cholesky``: np.linalg.cholesky(f) on the prebuilt f(Phi)
- ``pseudo_inertia_and_cholesky``: f(Phi) built from Phi, then Cholesky

and ``mixed_with_margins``: physical_consistency on bodies of which a tenth
violate a triangle inequality and a hundredth lie on the boundary (point,
line and planar masses), which Cholesky cannot classify at all.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from inertiaproof.model.consistency import physical_consistency
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse


def bodies(rng, n):
    """Consistent robot-link-like bodies in SI units: 10 g to 10 kg, 1 cm to 50 cm, principal radii from a sixteenth
    to all of the size, random axes, the centre of mass about one size from the link frame.

    Their lambda_min(f)/||f||_F spreads like that of the example-robot-data links (about 2 % below 1e-6).
    """
    q, _ = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    m = 10.0 ** rng.uniform(-2, 1, size=n)
    size = 10.0 ** rng.uniform(np.log10(0.01), np.log10(0.5), size=(n, 1))
    radii = size * 10.0 ** rng.uniform(-1.2, 0, size=(n, 3))
    sigma_c = np.einsum("nij,nj,nkj->nik", q, m[:, None] * radii**2, q)
    com = size * rng.normal(size=(n, 3))
    f = np.zeros((n, 4, 4))
    f[:, :3, :3] = sigma_c + m[:, None, None] * com[:, :, None] * com[:, None, :]
    f[:, :3, 3] = f[:, 3, :3] = m[:, None] * com
    f[:, 3, 3] = m
    return pseudo_inertia_inverse(f)


def mixed(rng, n):
    phi = bodies(rng, n)
    bad = rng.random(n) < 0.1
    phi[bad, 6] += 2 * (phi[bad, 4] + phi[bad, 5])  # I33 beyond I11 + I22 (+ the shift's share): inconsistent
    edge = np.flatnonzero(rng.random(n) < 0.01)
    points = rng.integers(-5, 6, size=(edge.size, 3)).astype(float)
    x = np.concatenate([points, np.ones((edge.size, 1))], 1)
    phi[edge] = pseudo_inertia_inverse(x[:, :, None] * x[:, None, :])
    return phi


def timed(variants, repeats):
    """Seconds per run of each variant, the variants interleaved round by round (drift hits all alike)."""
    for fn in variants.values():
        fn()  # warm-up
    seconds = {name: [] for name in variants}
    for _ in range(repeats):
        for name, fn in variants.items():
            start = time.perf_counter()
            fn()
            seconds[name].append(time.perf_counter() - start)
    return seconds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=10**6)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--only", choices=["setup", "verdicts_with_margins", "verdicts_only", "cholesky",
                                           "pseudo_inertia_and_cholesky", "mixed_with_margins"],
                        help="run one variant once and write nothing (for whole-process timing; 'setup' only builds "
                             "the arrays, the baseline to subtract)")
    parser.add_argument("--out", default=str(Path(__file__).parent / "results" / "consistency_throughput.json"))
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    phi = bodies(rng, args.rows)
    f = pseudo_inertia(phi)
    mix = mixed(rng, args.rows) if args.only in (None, "mixed_with_margins") else None
    variants = {
        "verdicts_with_margins": lambda: physical_consistency(phi),
        "verdicts_only": lambda: physical_consistency(phi, margins=False),
        "cholesky": lambda: np.linalg.cholesky(f),
        "pseudo_inertia_and_cholesky": lambda: np.linalg.cholesky(pseudo_inertia(phi)),
        "mixed_with_margins": lambda: physical_consistency(mix),
    }
    if args.only:
        if args.only != "setup":
            variants[args.only]()
        return 0
    assert (physical_consistency(phi, margins=False).verdict == 0).all()
    seconds = timed(variants, args.repeats)
    results = {}
    for name, runs in seconds.items():
        results[name] = {"median_s": statistics.median(runs), "min_s": min(runs), "max_s": max(runs), "runs": runs,
                         "rows_per_s": args.rows / statistics.median(runs)}
        print(f"{name:<30} median {results[name]['median_s']:.3f} s  (min {min(runs):.3f}, max {max(runs):.3f})")
    ratios = {name: statistics.median(a / b for a, b in zip(runs, seconds["cholesky"]))
              for name, runs in seconds.items() if name != "cholesky"}
    document = {
        "rows": args.rows, "repeats": args.repeats, "seed": args.seed,
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__,
                    "note": "shared machine: other jobs ran at the same time; quote medians"},
        "results": results,
        "ratio_to_cholesky": ratios,
        "ratio_note": "median over rounds of (variant seconds / Cholesky seconds in the same round)",
        "mixed_verdicts": {k: int(v) for k, v in zip(*np.unique(physical_consistency(mix, margins=False).labels,
                                                                 return_counts=True))},
    }
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(document, indent=1))
    print("ratios to Cholesky: " + ", ".join(f"{k} {v:.2f}" for k, v in ratios.items()))
    print(f"written: {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
