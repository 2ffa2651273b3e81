"""The ``body-spectrum`` claim, decided exactly: a spectral bound of each body's matrix over the hull of its rows.

It says: for every body l and every Phi in the convex hull of the rows of body l in the parameter sets
(``parameters``), with F = f(Phi) (``matrix`` "pseudo_inertia", 4x4) or Z(Phi) ("spatial_inertia", 6x6),

- ``lambda_min``: lambda_min(F) >= bound, proved as F - bound I >= 0;
- ``lambda_max``: lambda_max(F) <= bound, proved as bound I - F >= 0;
- ``sigma_max``: max |eigenvalue of F| <= bound, proved as bound I - F >= 0 and bound I + F >= 0.

F is linear in Phi, so each condition holds on the hull when it holds at every row (the semidefinite cone is
convex). Optional ``directions`` (``lambda_min`` only; one row per body): the claim holds on the hull plus any
nonnegative multiple of body l's direction D_l (a scaling that grows without bound) when also f(D_l) >= 0, as adding
a semidefinite term only raises lambda_min. Every row is decided in exact rational arithmetic
(:func:`.exact.semidefinite`): no rounding, no boxes.
"""

from __future__ import annotations

import itertools
from fractions import Fraction

from flint import fmpq

from .exact import BadCertificate, rational, semidefinite
from .outcome import REPROVED, refuted, Outcome

__all__ = ["formed", "parameter_sets", "prove", "pseudo_inertia", "rows_of", "spatial_inertia"]

QUANTITIES = {"lambda_min": ((1, -1, "F - bound I"),), "lambda_max": ((-1, 1, "bound I - F"),),
              "sigma_max": ((-1, 1, "bound I - F"), (1, 1, "bound I + F"))}  # (sign of F, sign of bound I, which)


def _inertia(phi):
    _, _, _, _, i11, i22, i33, i12, i23, i13 = phi
    return [[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]]


def pseudo_inertia(phi):
    """f(Phi) = [[Sigma, h], [h^T, m]], Sigma = tr(I)/2 I3 - I (DefTrafoInertialParameters), of exact rationals."""
    m, h = phi[0], phi[1:4]
    inertia = _inertia(phi)
    half = (inertia[0][0] + inertia[1][1] + inertia[2][2]) / 2
    rows = [[(half if i == j else fmpq(0)) - inertia[i][j] for j in range(3)] + [h[i]] for i in range(3)]
    return rows + [list(h) + [m]]


def spatial_inertia(phi):
    """Z(Phi) = [[m I3, -S(h)], [-S(h)^T, I]] (DefMatrixZ) of exact rationals."""
    m, (h1, h2, h3), z = phi[0], phi[1:4], fmpq(0)
    inertia = _inertia(phi)
    return [[m, z, z, z, h3, -h2], [z, m, z, -h3, z, h1], [z, z, m, h2, -h1, z],
            [z, -h3, h2] + inertia[0], [h3, z, -h1] + inertia[1], [-h2, h1, z] + inertia[2]]


MATRICES = {"pseudo_inertia": pseudo_inertia, "spatial_inertia": spatial_inertia}


def parameter_sets(cert, bodies=None):
    """The exact rows (V lists of N rows of 10) of a certificate's ``parameters``; ``bodies`` N when known. With a
    ``formation``, the sets must be the vertices it forms (:func:`formed`), no more and no fewer."""
    rows = rows_of(cert.get("parameters"), bodies, "parameters")
    if "formation" in cert and _keyed(rows) != _keyed(formed(cert["formation"], len(rows[0]))):
        raise BadCertificate("parameters: not the vertices the formation forms")
    return rows


def rows_of(sets, bodies, key):
    """The exact rows of the sets ``sets`` (V lists of N rows of 10; the field ``key``); ``bodies`` N when known."""
    if not isinstance(sets, list) or not sets or not isinstance(sets[0], list) or not sets[0]:
        raise BadCertificate(f"{key}: a nonempty list of parameter sets, each a nonempty list of bodies")
    bodies, rows = bodies or len(sets[0]), []
    for v, body_rows in enumerate(sets):
        if not isinstance(body_rows, list) or len(body_rows) != bodies:
            raise BadCertificate(f"{key}[{v}]: one row of 10 parameters per body ({bodies})")
        for l, row in enumerate(body_rows):
            if not isinstance(row, list) or len(row) != 10:
                raise BadCertificate(f"{key}[{v}][{l}]: 10 numbers")
        rows.append([[rational(x, f"{key}[{v}][{l}][{i}]") for i, x in enumerate(row)]
                     for l, row in enumerate(body_rows)])
    return rows


def _keyed(sets):
    return {tuple(tuple(row) for row in rows) for rows in sets}


def formed(formation, bodies):
    """The vertex sets of Theta(t) (or Thetadot(t), ``of`` "rate") a ``formation`` gives: the base rows, each
    scaling multiplying its body's row by s, then each payload adding s Phi, at every corner s of the loads'
    ranges (and, for the rate, ds of their rates +- r), computed in float64 in that order (as the prover forms
    them), each float an exact rational."""
    if not isinstance(formation, dict) or set(formation) != {"of", "base", "loads"} \
            or formation["of"] not in ("theta", "rate") or not isinstance(formation["loads"], list):
        raise BadCertificate("formation: {of: theta or rate, base, loads}")
    base = [[float(x) for x in row] for row in rows_of([formation["base"]], bodies, "formation.base")[0]]
    loads = []
    for i, load in enumerate(formation["loads"]):
        kind = load.get("kind") if isinstance(load, dict) else None
        if kind not in ("payload", "scaling") or type(load.get("body")) is not int or not 1 <= load["body"] <= bodies:
            raise BadCertificate(f"formation.loads[{i}]: {{kind: payload or scaling, body from 1 to {bodies}, ...}}")
        phi = [float(rational(x, f"formation.loads[{i}].phi")) for x in load.get("phi", [])] if kind == "payload" \
            else None
        if phi is not None and len(phi) != 10:
            raise BadCertificate(f"formation.loads[{i}].phi: 10 numbers")
        ends = load.get("range") if isinstance(load.get("range"), list) and len(load["range"]) == 2 else [None] * 2
        loads.append((kind, load["body"] - 1, phi, [float(rational(x, f"formation.loads[{i}].range")) for x in ends],
                      float(rational(load.get("rate"), f"formation.loads[{i}].rate"))))
    if len(loads) > 12:
        raise BadCertificate("formation.loads: at most 12 (2^12 corners)")
    rates = itertools.product(*[(-r, r) for *_, r in loads]) if formation["of"] == "rate" else [None]
    out = [_corner(base, loads, s, ds) for ds in rates for s in itertools.product(*[ends for *_, ends, _ in loads])]
    return [[[_exact(x) for x in row] for row in rows] for rows in out]


def _corner(base, loads, s, ds):
    theta, dot = [list(row) for row in base], [[0.0] * 10 for _ in base]
    for k, ((kind, body, _, _, _), si) in enumerate(zip(loads, s)):
        if kind == "scaling":
            d = 0.0 if ds is None else ds[k]
            row = theta[body]
            theta[body], dot[body] = [si * x for x in row], [d * x + si * y for x, y in zip(row, dot[body])]
    for k, ((kind, body, phi, _, _), si) in enumerate(zip(loads, s)):
        if kind == "payload":
            theta[body] = [x + si * p for x, p in zip(theta[body], phi)]
            dot[body] = [x + (0.0 if ds is None else ds[k]) * p for x, p in zip(dot[body], phi)]
    return theta if ds is None else dot


def _exact(x):
    value = Fraction(x)
    return fmpq(value.numerator, value.denominator)


def _parse(cert):
    claim = cert["claim"]
    if claim.get("matrix") not in MATRICES:
        raise BadCertificate(f"claim.matrix: one of {sorted(MATRICES)}, not {claim.get('matrix')!r}")
    if claim.get("quantity") not in QUANTITIES:
        raise BadCertificate(f"claim.quantity: one of {sorted(QUANTITIES)}")
    bound = rational(claim.get("bound"), "claim.bound")
    return MATRICES[claim["matrix"]], claim["matrix"], claim["quantity"], bound, parameter_sets(cert)


def prove(cert):
    """The :class:`Outcome` of the claim: every (parameter set, body) decided exactly."""
    build, matrix, quantity, bound, sets = _parse(cert)
    tested = 0
    if "directions" in cert:
        if quantity != "lambda_min":
            raise BadCertificate("directions: only for a lambda_min claim")
        for l, row in enumerate(rows_of([cert["directions"]], len(sets[0]), "directions")[0]):
            tested += 1
            if not semidefinite(build(row)):
                return refuted(f"direction of body {l + 1}: {matrix}(D) is not positive semidefinite, so lambda_min "
                               "falls without bound along it (exact rational arithmetic)", {"direction": l + 1},
                               {matrix + "(D)": "indefinite"}, tested)
    for v, body_rows in enumerate(sets):
        for l, row in enumerate(body_rows):
            f = build(row)
            for sign, shift, what in QUANTITIES[quantity]:
                tested += 1
                if not semidefinite([[sign * x + (shift * bound if i == j else 0) for j, x in enumerate(r)]
                                     for i, r in enumerate(f)]):
                    return refuted(f"parameter set {v}, body {l + 1}: {what} is not positive semidefinite for F = "
                                   f"{matrix}(Phi) (exact rational arithmetic)", {"parameter_set": v, "body": l + 1},
                                   {what: "not positive semidefinite", "bound": str(bound)}, tested)
    return Outcome(REPROVED, f"{len(sets)} parameter set(s) x {len(sets[0])} bodies: every {matrix}(Phi) decided "
                   "exactly", tested)
