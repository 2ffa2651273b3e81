"""The ``moving-mass`` claim: bounds over all time of bodies carrying rigid loads that translate along paths.

Data: ``parameters``, the bodies' rows without the moving loads (for the rates, their rates; one or more sets, whose
hull the payloads and scalings sweep; for Psi one set), and ``loads``, each a rigid body of ``mass`` m > 0 and
``inertia_com`` I_c (3x3, about its centre, Sigma_c = tr(I_c)/2 I3 - I_c >= 0: consistent, decided exactly) on body
``body`` (from 1), its centre at c(t) = a + s(t) (b - a) (``path`` shape ``line``, ``start`` a, ``end`` b) or on a
circle of ``radius`` r about ``center`` at angle 2 pi s(t) (shape ``circle``), s(t) a ``profile`` (``shape``,
``duration`` T, ``rate`` of ``exp``). The load adds Phi_p(c) with f(Phi_p(c)) = diag(Sigma_c, 0) + m v v^T, v =
(c, 1), and Z(Phi_p(c)) = diag(0, I_c) + m W W^T, W = (I3; S(c)), |v|^2 = ||W||^2 = 1 + |c|^2 (DefMatrixZ); psi =
(m cdot, m c x cdot) (RoboticEquation). With |c| <= C, |dc/ds| <= d1 (|b - a|, 2 pi r), |d2c/ds2| <= d2 (0,
4 pi^2 r), |s'| <= R and |s''| <= A (:data:`PEAKS`, over t >= start for ``exp``), |cdot| <= d1 R and |cddot| <=
d1 A + d2 R^2, the claim ``quantity`` holds for every t:

- ``lambda_min_f`` (``lambda_min_Z``): min_l lambda_min >= bound: the loads add PSD terms, so the bodies' own rows
  decide (F - bound I >= 0, exactly, in every set);
- ``lambda_max_f`` (``lambda_max_Z``): max_l lambda_max <= bound: bound I - F(row_l) - sum_p (diag(Sigma_c, 0) (or
  diag(0, I_c)) + m (1 + C^2) I) >= 0 for each body, exactly, in every set;
- ``sigma_max_fdot``: max_l sigma_max(f(Phidot_l)) <= bound: f(Phidot_p) = m (u v^T + v u^T), u = (cdot, 0), whose
  eigenvalues are m (u.v +- |u| |v|): sigma_max(F) + sum_p m d1 R (C + (1 + C^2)^(1/2)) <= bound, F the rest's rate;
- ``sigma_max_Zdot``: Z(Phidot_p) = m (Wdot W^T + W Wdot^T), ||Wdot|| = |cdot|: the sum of 2 m d1 R (1 + C^2)^(1/2);
- ``psi`` (``psi_dot``): ||Psi|| <= sum_p ||psi_p|| <= sum_p m d1 R (1 + C^2)^(1/2) (d1 A + d2 R^2 for R), F = 0.

A matrix condition linear in the row, holding at every set, holds on their hull (the semidefinite cone is convex).
The sums are balls; sigma_max(F) + sum <= bound is (bound - r) I -+ F >= 0, decided exactly for the ball's ends r.
C^2 is an exact rational (for a circle checked exactly against (|center| + r)^2).
"""

from __future__ import annotations

from flint import arb, fmpq

from .bodies import parameter_sets, pseudo_inertia, spatial_inertia
from .exact import BadCertificate, finite, rational, rational_matrix, semidefinite
from .outcome import REPROVED, UNPROVED, Outcome

__all__ = ["prove"]

PEAKS = {  # sup |s'| and sup |s''| of the ramps s(x) on [0, 1], x = (t - start) / T (times 1/T and 1/T^2)
    "constant": (0, 0), "linear": (1, None),  # s' jumps: no acceleration bound
    "smoothstep": (fmpq(3, 2), 6),  # s' = 6 x (1 - x) peaks at x = 1/2; |s''| = |6 - 12 x| at the ends
    "smootherstep": (fmpq(15, 8), arb(10) / arb(3).sqrt()),  # 30 x^2 (1-x)^2 at 1/2; 60 x (1-x) (1-2x) at 1/2 -+ 3^.5/6
    "cosine": (arb.pi() / 2, arb.pi() ** 2 / 2),  # pi/2 sin(pi x), pi^2/2 cos(pi x)
}
QUANTITIES = ("lambda_min_f", "lambda_max_f", "lambda_min_Z", "lambda_max_Z", "sigma_max_fdot", "sigma_max_Zdot",
              "psi", "psi_dot")


def _vector(data, where):
    return rational_matrix([data], (1, 3), where)[0]


def _norm2(v):
    return sum(x * x for x in v)


def _profile(data, where):
    """(R, A): bounds of |s'| and |s''| (A None where s' jumps)."""
    shape = data.get("shape") if isinstance(data, dict) else None
    if shape == "exp":
        rate = rational(data.get("rate"), f"{where}.rate")
        if rate > 0:
            raise BadCertificate(f"{where}: a growing exponential has no bounded rate")
        return arb(-rate), arb(rate * rate)
    if shape not in PEAKS:
        raise BadCertificate(f"{where}.shape: one of {sorted(PEAKS) + ['exp']}")
    duration = rational(data.get("duration"), f"{where}.duration")
    if not duration > 0:
        raise BadCertificate(f"{where}.duration: must be > 0")
    rate, acc = PEAKS[shape]
    return arb(rate) / arb(duration), None if acc is None else arb(acc) / arb(duration) ** 2


def _path(data, where):
    """(C^2 exact, d1, d2): bounds of |c|^2, |dc/ds| and |d2c/ds2| over the path."""
    shape = data.get("shape") if isinstance(data, dict) else None
    if shape == "line":
        a, b = _vector(data.get("start"), f"{where}.start"), _vector(data.get("end"), f"{where}.end")
        return max(_norm2(a), _norm2(b)), arb(_norm2([y - x for x, y in zip(a, b)])).sqrt(), arb(0)
    if shape != "circle":
        raise BadCertificate(f"{where}.shape: 'line' or 'circle'")
    centre2, r = _norm2(_vector(data.get("center"), f"{where}.center")), rational(data.get("radius"), f"{where}.radius")
    if r < 0:
        raise BadCertificate(f"{where}.radius: must be >= 0")
    reach = _exact(((arb(centre2).sqrt() + arb(r)) ** 2).upper())
    while not (reach - centre2 - r * r >= 0 and (reach - centre2 - r * r) ** 2 >= 4 * r * r * centre2):
        reach *= 1 + fmpq(1, 2**40)  # (|center| + r)^2 <= reach, decided exactly
    return reach, 2 * arb.pi() * arb(r), 4 * arb.pi() ** 2 * arb(r)


def _exact(x):
    """An exact arb (a ball's end) as a rational."""
    man, exp = x.mid().man_exp()
    return fmpq(int(man)) * fmpq(2) ** int(exp) if exp >= 0 else fmpq(int(man), 2 ** int(-exp))


def _loads(cert, bodies):
    items = cert.get("loads")
    if not isinstance(items, list) or not items:
        raise BadCertificate("loads: a nonempty list of moving loads")
    loads = []
    for i, item in enumerate(items):
        where = f"loads[{i}]"
        if not isinstance(item, dict) or type(item.get("body")) is not int or not 1 <= item["body"] <= bodies:
            raise BadCertificate(f"{where}.body: a body from 1 to {bodies}")
        m = rational(item.get("mass"), f"{where}.mass")
        inertia = rational_matrix(item.get("inertia_com"), (3, 3), f"{where}.inertia_com")
        row = [m] + [fmpq(0)] * 3 + [inertia[i][j] for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))]
        if not m > 0 or any(inertia[i][j] != inertia[j][i] for i in range(3) for j in range(i)) \
                or not semidefinite(pseudo_inertia(row)):
            raise BadCertificate(f"{where}: not a consistent rigid body (m > 0, symmetric I_c, Sigma_c >= 0)")
        reach, d1, d2 = _path(item.get("path"), f"{where}.path")
        rate, acc = _profile(item.get("profile"), f"{where}.profile")
        loads.append({"body": item["body"] - 1, "m": m, "row": row, "reach": reach,
                      "speed": d1 * rate, "acc": None if acc is None else d1 * acc + d2 * rate * rate})
    return loads


def _extra(load, matrix):
    """diag(Sigma_c, 0) (f) or diag(0, I_c) (Z), the load's own matrix about its centre less its mass's share, plus
    m (1 + C^2) I: above the load's matrix at every time."""
    own, share = matrix(load["row"]), matrix([load["m"]] + [fmpq(0)] * 9)
    lift = load["m"] * (1 + load["reach"])
    return [[a - b + (lift if i == j else 0) for j, (a, b) in enumerate(zip(r, t))]
            for i, (r, t) in enumerate(zip(own, share))]


def _rate(load, quantity):
    lever = arb(1 + load["reach"]).sqrt()
    if quantity == "sigma_max_fdot":
        return arb(load["m"]) * load["speed"] * (arb(load["reach"]).sqrt() + lever)
    if quantity == "sigma_max_Zdot":
        return 2 * arb(load["m"]) * load["speed"] * lever
    if load["acc"] is None and quantity == "psi_dot":
        raise BadCertificate("psi_dot: a linear profile's rate jumps: no bound of Psidot")
    return arb(load["m"]) * (load["speed"] if quantity == "psi" else load["acc"]) * lever


def prove(cert):
    """The :class:`Outcome` of the claim, decided exactly (the matrices) or in ball arithmetic (the sums)."""
    claim = cert["claim"]
    quantity, bound = claim.get("quantity"), rational(claim.get("bound"), "claim.bound")
    if quantity not in QUANTITIES:
        raise BadCertificate(f"claim.quantity: one of {list(QUANTITIES)}")
    sets = parameter_sets(cert)
    if len(sets) != 1 and quantity.startswith("psi"):
        raise BadCertificate("parameters: one set, the bodies' constant rows")
    loads = _loads(cert, len(sets[0]))
    if quantity.startswith("lambda"):
        matrix = pseudo_inertia if quantity.endswith("_f") else spatial_inertia
        for v, rows in enumerate(sets):
            for l, row in enumerate(rows):
                f = matrix(row)
                if quantity.startswith("lambda_min"):
                    test = [[x - (bound if i == j else 0) for j, x in enumerate(r)] for i, r in enumerate(f)]
                else:
                    extra = [_extra(load, matrix) for load in loads if load["body"] == l]
                    test = [[(bound if i == j else 0) - x - sum(e[i][j] for e in extra) for j, x in enumerate(r)]
                            for i, r in enumerate(f)]
                if not semidefinite(test):
                    return Outcome(UNPROVED, f"body {l + 1} of set {v + 1}: the bound fails for its own row and its "
                                   "loads' bounds (exact rational arithmetic)", 0, {"quantity": quantity})
        return Outcome(REPROVED, f"{len(sets)} set(s), {len(loads)} moving load(s): decided exactly", 0)
    psi = quantity.startswith("psi")
    matrix = pseudo_inertia if quantity.endswith("fdot") else spatial_inertia
    for l in range(1 if psi else len(sets[0])):
        total = sum((_rate(load, quantity) for load in loads if psi or load["body"] == l), arb(0))
        for v, rows in enumerate(sets):
            f = [[fmpq(0)]] if psi else matrix(rows[l])
            if not _holds(_exact(finite(total, "the loads' sum").upper()), bound, f):
                return Outcome(UNPROVED, f"{'Psi' if psi else f'body {l + 1} of set {v + 1}'}: sigma_max(F) + the loads' "
                               f"{total.str(10)} is not <= {float(bound):.10g}", 0, {"quantity": quantity})
    return Outcome(REPROVED, f"{len(loads)} moving load(s) on {len(sets)} set(s): the sums decided", 0)


def _holds(r, bound, f):
    """Whether sigma_max(F) + r <= bound: (bound - r) I -+ F >= 0, decided exactly."""
    return all(semidefinite([[(bound - r if i == j else 0) + sign * x for j, x in enumerate(row)]
                             for i, row in enumerate(f)]) for sign in (-1, 1))
