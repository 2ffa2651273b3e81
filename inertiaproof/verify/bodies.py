"""The bodies' matrices and parameter sets, and the ``body-spectrum`` claim, decided exactly.

The claim: for every body l and every Phi in the hull of body l's rows in the sets (``parameters``), with F = f(Phi)
(``matrix`` "pseudo_inertia", 4x4) or Z(Phi) ("spatial_inertia", 6x6), ``lambda_min`` F - bound I >= 0,
``lambda_max`` bound I - F >= 0, ``sigma_max`` both bound I -+ F >= 0. F is linear in Phi and the semidefinite cone
convex, so each row decides the hull. Optional ``directions`` (``lambda_min``): the hull plus any nonnegative
multiple of body l's direction D_l, when also F(D_l) >= 0. Every row is decided in exact rational arithmetic.
"""

import itertools

from flint import fmpq

from .exact import dyadic, need, rational, rationals, semidefinite, vector
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
    sets = cert.get("parameters")
    need(isinstance(sets, list) and sets and isinstance(sets[0], list) and sets[0],
         "parameters: a nonempty list of parameter sets, each a nonempty list of bodies")
    rows = rationals(sets, (len(sets), bodies or len(sets[0]), 10), "parameters")
    keyed = lambda sets: {tuple(tuple(row) for row in r) for r in sets}  # noqa: E731
    need("formation" not in cert or keyed(rows) == keyed(formed(cert["formation"], len(rows[0]))),
         "parameters: not the vertices the formation forms")
    return rows


def formed(formation, bodies):
    """The vertex sets of Theta(t) (or Thetadot(t), ``of`` "rate") a ``formation`` gives: the base rows, each
    scaling multiplying its body's row by s, then each payload adding s Phi, at every corner s of the loads'
    ranges (and, for the rate, ds of their rates +- r), in float64 in that order (as the prover forms them), each
    float an exact rational."""
    need(isinstance(formation, dict) and set(formation) == {"of", "base", "loads"} and formation["of"] in (
        "theta", "rate") and isinstance(formation["loads"], list) and len(formation["loads"]) <= 12,
         "formation: {of: theta or rate, base, loads (at most 12: 2^12 corners)}")
    rates, floats = formation["of"] == "rate", lambda xs, n, at: [float(x) for x in vector(xs, n, at)]  # noqa: E731
    base, loads = [[float(x) for x in row] for row in rationals(formation["base"], (bodies, 10), "formation.base")], []
    for i, load in enumerate(formation["loads"]):
        where, kind = f"formation.loads[{i}]", load.get("kind") if isinstance(load, dict) else None
        need(kind in ("payload", "scaling") and type(load.get("body")) is int and 1 <= load["body"] <= bodies,
             f"{where}: {{kind: payload or scaling, body from 1 to {bodies}, ...}}")
        rate = float(rational(load.get("rate"), f"{where}.rate"))
        corners = [(s, ds) for s in floats(load.get("range"), 2, f"{where}.range")
                   for ds in ((-rate, rate) if rates else (0.0,))]
        loads.append((kind, load["body"] - 1, floats(load.get("phi"), 10, f"{where}.phi") if kind == "payload"
                      else None, corners))
    loads.sort(key=lambda load: load[0] == "payload")  # every scaling, then every payload, each in the list's order
    vertices = [_corner(base, loads, corner)[rates]
                for corner in itertools.product(*[corners for *_, corners in loads])]
    return [[[dyadic(x) for x in row] for row in rows] for rows in vertices]


def _corner(base, loads, corner):
    """(Theta, Thetadot) at one corner, a pair (s, ds) per load."""
    theta, dot = [list(row) for row in base], [[0.0] * 10 for _ in base]
    for (kind, l, phi, _), (s, ds) in zip(loads, corner):
        if kind == "scaling":
            theta[l], dot[l] = [s * x for x in theta[l]], [ds * x + s * y for x, y in zip(theta[l], dot[l])]
        else:
            theta[l], dot[l] = [x + s * p for x, p in zip(theta[l], phi)], [y + ds * p for y, p in zip(dot[l], phi)]
    return theta, dot


def first_failure(sets, conditions):
    """The first (set v, body l, what) at which sign F + shift I >= 0 fails, decided exactly for every one of the
    ``conditions(l, row)`` (tuples (what, F, sign, shift)) of every row of the sets; or None. And how many were
    decided."""
    tested = 0
    for v, rows in enumerate(sets):
        for l, row in enumerate(rows):
            for what, f, sign, shift in conditions(l, row):
                tested += 1
                if not semidefinite(f, sign, shift):
                    return (v, l, what), tested
    return None, tested


def prove(cert):
    """The :class:`Outcome` of the claim: the directions, then every (parameter set, body), decided exactly."""
    claim = cert["claim"]
    matrix, quantity = claim.get("matrix"), claim.get("quantity")
    need(matrix in MATRICES, f"claim.matrix: one of {sorted(MATRICES)}, not {matrix!r}")
    need(quantity in QUANTITIES, f"claim.quantity: one of {sorted(QUANTITIES)}")
    need("directions" not in cert or quantity == "lambda_min", "directions: only for a lambda_min claim")
    build, bound, sets = MATRICES[matrix], rational(claim.get("bound"), "claim.bound"), parameter_sets(cert)
    directions = rationals(cert["directions"], (len(sets[0]), 10), "directions") if "directions" in cert else []
    for l, row in enumerate(directions):
        if not semidefinite(build(row)):
            return refuted(f"direction of body {l + 1}: {matrix}(D) is not positive semidefinite, so lambda_min falls "
                           "without bound along it (exact rational arithmetic)", {"direction": l + 1},
                           {f"{matrix}(D)": "indefinite"}, l + 1)
    fail, tested = first_failure(sets, lambda l, row: [(what, build(row), sign, shift * bound)
                                                       for sign, shift, what in QUANTITIES[quantity]])
    if fail:
        v, l, what = fail
        return refuted(f"parameter set {v}, body {l + 1}: {what} is not positive semidefinite for F = {matrix}(Phi) "
                       "(exact rational arithmetic)", {"parameter_set": v, "body": l + 1},
                       {what: "not positive semidefinite", "bound": str(bound)}, tested + len(directions))
    return Outcome(REPROVED, f"{len(sets)} parameter set(s) x {len(sets[0])} bodies: every {matrix}(Phi) decided "
                   "exactly", tested + len(directions))
