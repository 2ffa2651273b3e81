"""The chain split's deep certificates and the independent checker's time on them: ``python
bench/split_certificates.py ur5|panda`` proves inf lambda_min of the unit bodies (Definition 2) and of the real
bodies (Theorem 2) with :func:`inertiaproof.bounds.interface.split_ladder` at a deep budget, writes the
certificate of each, and re-proves it with :func:`inertiaproof.verify.cli.check`, printing both times and
writing them to ``bench/results/split_certificates-<chain>.json``."""

import json
import sys
import time
from pathlib import Path

import numpy as np

from inertiaproof.bounds.completion import complete
from inertiaproof.bounds.certificate import spectrum_certificate
from inertiaproof.bounds.configuration import mass_spectra
from inertiaproof.bounds.domain import search_box
from inertiaproof.bounds.interface import split_ladder
from inertiaproof.bounds.lengths import unit_bodies
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.scene import robots
from inertiaproof.verify.cli import check

scene = robots.ur5() if sys.argv[1:] == ["ur5"] else robots.panda(2.0)
chain = scene.chain
rows = []
for label, thetas in (("unit bodies", unit_bodies(chain)), ("real bodies", parameter_vertices(scene.trajectory)[0])):
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(0).random((20000, chain.n))
    values = mass_spectra(chain, thetas, q, "lmin").min(1)
    start = time.perf_counter()
    gamma, note, proof = split_ladder(chain, thetas, float(values.min()), 800)
    row = {"bodies": label, "observed": float(values.min()), "certified": gamma, "prover": note,
           "prover_seconds": round(time.perf_counter() - start, 1)}
    print(f"{chain.name}, {label}: {note} ({row['prover_seconds']} s)")
    if proof is not None:
        cert = spectrum_certificate(chain, thetas, "lambda_min", gamma, proof=proof, witness=q[np.argmin(values)])
        start = time.perf_counter()
        out = check(complete(cert, 100_000))  # the prover completes the tree; the checker walks it once
        row.update(checker=f"{out['status']}: {out['why']}", checker_seconds=round(time.perf_counter() - start, 1))
        print(f"  the checker: {row['checker']} ({row['checker_seconds']} s)")
    rows.append(row)
out = Path(__file__).parent / "results" / f"split_certificates-{chain.name}.json"
out.write_text(json.dumps(rows, indent=1) + "\n")
print(f"written: {out}")
