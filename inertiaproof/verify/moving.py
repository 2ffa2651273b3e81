"""The ``moving-mass`` claim: bounds over all time of bodies carrying rigid loads that translate along paths.

Data: ``parameters``, the bodies' rows without the moving loads (for the rates, their rates; for Psi one set), and
``loads``, each of ``mass`` m > 0 and ``inertia_com`` I_c (Sigma_c = tr(I_c)/2 I3 - I_c >= 0, decided exactly) on
``body`` (from 1), its centre c(t) = a + s(t) (b - a) (``path`` ``line`` from ``start`` a to ``end`` b) or on a
``circle`` of ``radius`` r about ``center`` at angle 2 pi s(t), s(t) a ``profile`` (``shape``, ``duration`` T,
``rate`` of ``exp``). f(Phi_p(c)) = diag(Sigma_c, 0) + m v v^T, v = (c, 1); Z(Phi_p(c)) = diag(0, I_c) + m W W^T,
W = (I3; S(c)), |v|^2 = ||W||^2 = 1 + |c|^2 (DefMatrixZ); psi = (m cdot, m c x cdot) (RoboticEquation). With
|c|^2 <= C^2 (exact), |dc/ds| <= d1, |d2c/ds2| <= d2, |s'| <= R, |s''| <= A (:data:`PEAKS`): |cdot| <= d1 R,
|cddot| <= d1 A + d2 R^2, and the ``quantity`` holds for every t:

- ``lambda_min_f`` (``_Z``): the loads add PSD terms: F - bound I >= 0 for the bodies' own rows;
- ``lambda_max_f`` (``_Z``): bound I - F(row_l) - sum_p (diag(Sigma_c, 0) (diag(0, I_c)) + m (1 + C^2) I) >= 0;
- ``sigma_max_fdot``: f(Phidot_p) = m (u v^T + v u^T), u = (cdot, 0), eigenvalues m (u.v +- |u| |v|):
  sigma_max(F) + sum_p m d1 R (C + (1 + C^2)^(1/2)) <= bound, F the rest's rate; ``sigma_max_Zdot``:
  ||Z(Phidot_p)|| <= 2 m d1 R (1 + C^2)^(1/2); ``psi`` (``psi_dot``): ||Psi|| <= sum_p m d1 R (1 + C^2)^(1/2)
  (d1 A + d2 R^2 for R), F = 0.

A matrix condition linear in the row, holding at every set, holds on their hull; sigma_max(F) + r <= bound is
(bound - r) I -+ F >= 0, decided exactly for the upper end r of the sum's ball.
"""

from flint import arb, fmpq

from .bodies import parameter_sets, pseudo_inertia, spatial_inertia
from .exact import above, dyadic, finite, need, rational, rational_matrix, vector
from .outcome import REPROVED, UNPROVED, Outcome

PEAKS = {  # sup |s'| and sup |s''| of the ramps s(x) on [0, 1], x = (t - start) / T (times 1/T and 1/T^2)
    "constant": (0, 0), "linear": (1, None),  # s' jumps: no acceleration bound
    "smoothstep": (fmpq(3, 2), 6),  # s' = 6 x (1 - x) peaks at x = 1/2; |s''| = |6 - 12 x| at the ends
    "smootherstep": (fmpq(15, 8), arb(10) / arb(3).sqrt()),  # 30 x^2 (1-x)^2 at 1/2; 60 x (1-x) (1-2x) at 1/2 -+ 3^.5/6
    "cosine": (arb.pi() / 2, arb.pi() ** 2 / 2),  # pi/2 sin(pi x), pi^2/2 cos(pi x)
}
QUANTITIES = ("lambda_min_f", "lambda_max_f", "lambda_min_Z", "lambda_max_Z", "sigma_max_fdot", "sigma_max_Zdot",
              "psi", "psi_dot")


def _profile(data, where):
    """(R, A): bounds of |s'| and |s''| (A None where s' jumps)."""
    shape = data.get("shape") if isinstance(data, dict) else None
    if shape == "exp":
        rate = rational(data.get("rate"), f"{where}.rate")
        need(rate <= 0, f"{where}: a growing exponential has no bounded rate")
        return arb(-rate), arb(rate * rate)
    need(shape in PEAKS, f"{where}.shape: one of {sorted(PEAKS) + ['exp']}")
    duration = rational(data.get("duration"), f"{where}.duration")
    need(duration > 0, f"{where}.duration: must be > 0")
    rate, acc = PEAKS[shape]
    return arb(rate) / arb(duration), None if acc is None else arb(acc) / arb(duration) ** 2


def _path(data, where):
    """(C^2 exact, d1, d2): bounds of |c|^2, |dc/ds| and |d2c/ds2| over the path."""
    shape = data.get("shape") if isinstance(data, dict) else None
    norm2 = lambda v: sum(x * x for x in v)  # noqa: E731
    if shape == "line":
        a, b = vector(data.get("start"), 3, f"{where}.start"), vector(data.get("end"), 3, f"{where}.end")
        return max(norm2(a), norm2(b)), arb(norm2([y - x for x, y in zip(a, b)])).sqrt(), arb(0)
    need(shape == "circle", f"{where}.shape: 'line' or 'circle'")
    centre2, r = norm2(vector(data.get("center"), 3, f"{where}.center")), rational(data.get("radius"), f"{where}.radius")
    need(r >= 0, f"{where}.radius: must be >= 0")
    reach = dyadic(((arb(centre2).sqrt() + arb(r)) ** 2).upper())
    while not (reach - centre2 - r * r >= 0 and (reach - centre2 - r * r) ** 2 >= 4 * r * r * centre2):
        reach *= 1 + fmpq(1, 2**40)  # (|center| + r)^2 <= reach, decided exactly
    return reach, 2 * arb.pi() * arb(r), 4 * arb.pi() ** 2 * arb(r)


def _loads(cert, bodies):
    items = cert.get("loads")
    need(isinstance(items, list) and items, "loads: a nonempty list of moving loads")
    loads = []
    for i, item in enumerate(items):
        where = f"loads[{i}]"
        need(isinstance(item, dict) and type(item.get("body")) is int and 1 <= item["body"] <= bodies,
             f"{where}.body: a body from 1 to {bodies}")
        m = rational(item.get("mass"), f"{where}.mass")
        inertia = rational_matrix(item.get("inertia_com"), (3, 3), f"{where}.inertia_com")
        row = [m] + [fmpq(0)] * 3 + [inertia[i][j] for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))]
        need(m > 0 and all(inertia[i][j] == inertia[j][i] for i in range(3) for j in range(i))
             and above(pseudo_inertia(row), 1, 0), f"{where}: not a consistent rigid body (m > 0, symmetric I_c, "
             "Sigma_c >= 0)")
        reach, d1, d2 = _path(item.get("path"), f"{where}.path")
        rate, acc = _profile(item.get("profile"), f"{where}.profile")
        loads.append({"body": item["body"] - 1, "m": m, "row": row, "reach": reach,
                      "speed": d1 * rate, "acc": None if acc is None else d1 * acc + d2 * rate * rate})
    return loads


def _extra(load, matrix):
    """diag(Sigma_c, 0) (f) or diag(0, I_c) (Z), the load's own matrix about its centre less its mass's share, plus
    m (1 + C^2) I: above the load's matrix at every time."""
    own, share, lift = matrix(load["row"]), matrix([load["m"]] + [fmpq(0)] * 9), load["m"] * (1 + load["reach"])
    return [[a - b + (lift if i == j else 0) for j, (a, b) in enumerate(zip(r, t))]
            for i, (r, t) in enumerate(zip(own, share))]


def _rate(load, quantity):
    lever, m = arb(1 + load["reach"]).sqrt(), arb(load["m"])
    if quantity == "sigma_max_fdot":
        return m * load["speed"] * (arb(load["reach"]).sqrt() + lever)
    if quantity == "sigma_max_Zdot":
        return 2 * m * load["speed"] * lever
    need(load["acc"] is not None or quantity != "psi_dot", "psi_dot: a linear profile's rate jumps: no bound of Psidot")
    return m * (load["speed"] if quantity == "psi" else load["acc"]) * lever


def prove(cert):
    """The :class:`Outcome` of the claim, decided exactly (the matrices) or in ball arithmetic (the sums)."""
    quantity, bound = cert["claim"].get("quantity"), rational(cert["claim"].get("bound"), "claim.bound")
    need(quantity in QUANTITIES, f"claim.quantity: one of {list(QUANTITIES)}")
    sets = parameter_sets(cert)
    psi = quantity.startswith("psi")
    need(len(sets) == 1 or not psi, "parameters: one set, the bodies' constant rows")
    loads = _loads(cert, len(sets[0]))
    matrix = pseudo_inertia if quantity.endswith(("_f", "fdot")) else spatial_inertia
    if quantity.startswith("lambda"):
        for v, rows in enumerate(sets):
            for l, row in enumerate(rows):
                f, lower = matrix(row), quantity.startswith("lambda_min")
                extra = [_extra(load, matrix) for load in loads if load["body"] == l and not lower]
                if not above([[x + sum(e[i][j] for e in extra) for j, x in enumerate(r)] for i, r in enumerate(f)],
                             1 if lower else -1, -bound if lower else bound):
                    return Outcome(UNPROVED, f"body {l + 1} of set {v + 1}: the bound fails for its own row and its "
                                   "loads' bounds (exact rational arithmetic)", 0, {"quantity": quantity})
        return Outcome(REPROVED, f"{len(sets)} set(s), {len(loads)} moving load(s): decided exactly", 0)
    for l in range(1 if psi else len(sets[0])):
        total = sum((_rate(load, quantity) for load in loads if psi or load["body"] == l), arb(0))
        r = dyadic(finite(total, "the loads' sum").upper())
        for v, rows in enumerate(sets):
            f = [[fmpq(0)]] if psi else matrix(rows[l])
            if not (above(f, -1, bound - r) and above(f, 1, bound - r)):
                return Outcome(UNPROVED, f"{'Psi' if psi else f'body {l + 1} of set {v + 1}'}: sigma_max(F) + the "
                               f"loads' {total.str(10)} is not <= {float(bound):.10g}", 0, {"quantity": quantity})
    return Outcome(REPROVED, f"{len(loads)} moving load(s) on {len(sets)} set(s): the sums decided", 0)
