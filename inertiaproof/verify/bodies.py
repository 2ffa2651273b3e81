"""The bodies' matrices and parameter sets, and the ``body-spectrum`` claim, decided exactly.

The claim: for every body l and every Phi in the hull of body l's rows in the sets (``parameters``), with F = f(Phi)
(``matrix`` "pseudo_inertia", 4x4) or Z(Phi) ("spatial_inertia", 6x6), ``lambda_min`` F - bound I >= 0,
``lambda_max`` bound I - F >= 0, ``sigma_max`` both bound I -+ F >= 0. F is linear in Phi and the semidefinite cone
convex, so each row decides the hull. Optional ``directions`` (``lambda_min``): the hull plus any nonnegative
multiple of body l's direction D_l, when also f(D_l) >= 0. Every row is decided in exact rational arithmetic.
"""

import itertools

from flint import fmpq

from .exact import above, dyadic, need, rational, semidefinite
from .outcome import REPROVED, Outcome, refuted

QUANTITIES = {"lambda_min": ((1, -1, "F - bound I"),), "lambda_max": ((-1, 1, "bound I - F"),),
              "sigma_max": ((-1, 1, "bound I - F"), (1, 1, "bound I + F"))}  # (sign of F, sign of bound I, which)


def _inertia(phi):
    _, _, _, _, i11, i22, i33, i12, i23, i13 = phi
    return [[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]]


def pseudo_inertia(phi):
    """f(Phi) = [[Sigma, h], [h^T, m]], Sigma = tr(I)/2 I3 - I (DefTrafoInertialParameters), of exact rationals."""
    m, h, inertia = phi[0], phi[1:4], _inertia(phi)
    half = (inertia[0][0] + inertia[1][1] + inertia[2][2]) / 2
    return [[(half if i == j else fmpq(0)) - inertia[i][j] for j in range(3)] + [h[i]] for i in range(3)] + [
        list(h) + [m]]


def spatial_inertia(phi):
    """Z(Phi) = [[m I3, -S(h)], [-S(h)^T, I]] (DefMatrixZ) of exact rationals."""
    m, (h1, h2, h3), z, inertia = phi[0], phi[1:4], fmpq(0), _inertia(phi)
    return [[m, z, z, z, h3, -h2], [z, m, z, -h3, z, h1], [z, z, m, h2, -h1, z],
            [z, -h3, h2] + inertia[0], [h3, z, -h1] + inertia[1], [-h2, h1, z] + inertia[2]]


MATRICES = {"pseudo_inertia": pseudo_inertia, "spatial_inertia": spatial_inertia}


def parameter_sets(cert, bodies=None):
    """The exact rows (V lists of N rows of 10) of a certificate's ``parameters``; ``bodies`` N when known. With a
    ``formation``, the sets must be the vertices it forms (:func:`formed`), no more and no fewer."""
    rows = rows_of(cert.get("parameters"), bodies, "parameters")
    keyed = lambda sets: {tuple(tuple(row) for row in r) for r in sets}  # noqa: E731
    need("formation" not in cert or keyed(rows) == keyed(formed(cert["formation"], len(rows[0]))),
         "parameters: not the vertices the formation forms")
    return rows


def rows_of(sets, bodies, key):
    """The exact rows of the sets ``sets`` (V lists of N rows of 10; the field ``key``); ``bodies`` N when known."""
    need(isinstance(sets, list) and sets and isinstance(sets[0], list) and sets[0],
         f"{key}: a nonempty list of parameter sets, each a nonempty list of bodies")
    bodies = bodies or len(sets[0])
    for v, body_rows in enumerate(sets):
        need(isinstance(body_rows, list) and len(body_rows) == bodies,
             f"{key}[{v}]: one row of 10 parameters per body ({bodies})")
        for l, row in enumerate(body_rows):
            need(isinstance(row, list) and len(row) == 10, f"{key}[{v}][{l}]: 10 numbers")
    return [[[rational(x, f"{key}[{v}][{l}][{i}]") for i, x in enumerate(row)] for l, row in enumerate(body_rows)]
            for v, body_rows in enumerate(sets)]


def formed(formation, bodies):
    """The vertex sets of Theta(t) (or Thetadot(t), ``of`` "rate") a ``formation`` gives: the base rows, each
    scaling multiplying its body's row by s, then each payload adding s Phi, at every corner s of the loads'
    ranges (and, for the rate, ds of their rates +- r), in float64 in that order (as the prover forms them), each
    float an exact rational."""
    need(isinstance(formation, dict) and set(formation) == {"of", "base", "loads"} and formation["of"] in (
        "theta", "rate") and isinstance(formation["loads"], list), "formation: {of: theta or rate, base, loads}")
    base = [[float(x) for x in row] for row in rows_of([formation["base"]], bodies, "formation.base")[0]]
    loads = []
    for i, load in enumerate(formation["loads"]):
        where, kind = f"formation.loads[{i}]", load.get("kind") if isinstance(load, dict) else None
        need(kind in ("payload", "scaling") and type(load.get("body")) is int and 1 <= load["body"] <= bodies,
             f"{where}: {{kind: payload or scaling, body from 1 to {bodies}, ...}}")
        phi = [float(rational(x, f"{where}.phi")) for x in load.get("phi", [])] if kind == "payload" else None
        need(phi is None or len(phi) == 10, f"{where}.phi: 10 numbers")
        ends = load.get("range") if isinstance(load.get("range"), list) and len(load["range"]) == 2 else [None] * 2
        loads.append((kind, load["body"] - 1, phi, [float(rational(x, f"{where}.range")) for x in ends],
                      float(rational(load.get("rate"), f"{where}.rate"))))
    need(len(loads) <= 12, "formation.loads: at most 12 (2^12 corners)")
    rates = itertools.product(*[(-r, r) for *_, r in loads]) if formation["of"] == "rate" else [None]
    out = [_corner(base, loads, s, ds) for ds in rates for s in itertools.product(*[ends for *_, ends, _ in loads])]
    return [[[dyadic(x) for x in row] for row in rows] for rows in out]


def _corner(base, loads, s, ds):
    theta, dot = [list(row) for row in base], [[0.0] * 10 for _ in base]
    for k, ((kind, body, _, _, _), si) in enumerate(zip(loads, s)):
        if kind == "scaling":
            d, row = 0.0 if ds is None else ds[k], theta[body]
            theta[body], dot[body] = [si * x for x in row], [d * x + si * y for x, y in zip(row, dot[body])]
    for k, ((kind, body, phi, _, _), si) in enumerate(zip(loads, s)):
        if kind == "payload":
            theta[body] = [x + si * p for x, p in zip(theta[body], phi)]
            dot[body] = [x + (0.0 if ds is None else ds[k]) * p for x, p in zip(dot[body], phi)]
    return theta if ds is None else dot


def prove(cert):
    """The :class:`Outcome` of the claim: every (parameter set, body) decided exactly."""
    claim = cert["claim"]
    matrix, quantity = claim.get("matrix"), claim.get("quantity")
    need(matrix in MATRICES, f"claim.matrix: one of {sorted(MATRICES)}, not {matrix!r}")
    need(quantity in QUANTITIES, f"claim.quantity: one of {sorted(QUANTITIES)}")
    build, bound, sets, tested = MATRICES[matrix], rational(claim.get("bound"), "claim.bound"), parameter_sets(cert), 0
    need("directions" not in cert or quantity == "lambda_min", "directions: only for a lambda_min claim")
    for l, row in enumerate(rows_of([cert["directions"]], len(sets[0]), "directions")[0] if "directions" in cert
                            else []):
        tested += 1
        if not semidefinite(build(row)):
            return refuted(f"direction of body {l + 1}: {matrix}(D) is not positive semidefinite, so lambda_min "
                           "falls without bound along it (exact rational arithmetic)", {"direction": l + 1},
                           {matrix + "(D)": "indefinite"}, tested)
    for v, body_rows in enumerate(sets):
        for l, row in enumerate(body_rows):
            for sign, shift, what in QUANTITIES[quantity]:
                tested += 1
                if not above(build(row), sign, shift * bound):
                    return refuted(f"parameter set {v}, body {l + 1}: {what} is not positive semidefinite for F = "
                                   f"{matrix}(Phi) (exact rational arithmetic)", {"parameter_set": v, "body": l + 1},
                                   {what: "not positive semidefinite", "bound": str(bound)}, tested)
    return Outcome(REPROVED, f"{len(sets)} parameter set(s) x {len(sets[0])} bodies: every {matrix}(Phi) decided "
                   "exactly", tested)
