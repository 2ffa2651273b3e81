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

from .bodies import first_failure, parameter_sets, pseudo_inertia, spatial_inertia
from .exact import dyadic, finite, need, rational, semidefinite, symmetric, vector
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
    centre2 = norm2(vector(data.get("center"), 3, f"{where}.center"))
    r = rational(data.get("radius"), f"{where}.radius")
    need(r >= 0, f"{where}.radius: must be >= 0")
    reach = dyadic(((arb(centre2).sqrt() + arb(r)) ** 2).upper())
    while not (reach - centre2 - r * r >= 0 and (reach - centre2 - r * r) ** 2 >= 4 * r * r * centre2):
        reach *= 1 + fmpq(1, 2**40)  # (|center| + r)^2 <= reach, decided exactly
    return reach, 2 * arb.pi() * arb(r), 4 * arb.pi() ** 2 * arb(r)


def _loads(cert, bodies):
    """Each load's body, m, its row (0, 0, I_c) of Phi without the mass, C^2, |cdot| <= speed, |cddot| <= acc."""
    items = cert.get("loads")
    need(isinstance(items, list) and items, "loads: a nonempty list of moving loads")
    loads = []
    for i, item in enumerate(items):
        where = f"loads[{i}]"
        need(isinstance(item, dict) and type(item.get("body")) is int and 1 <= item["body"] <= bodies,
             f"{where}.body: a body from 1 to {bodies}")
        m = rational(item.get("mass"), f"{where}.mass")
        c = symmetric(item.get("inertia_com"), 3, f"{where}.inertia_com")
        inertia = [fmpq(0)] * 4 + [c[a][b] for a, b in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))]
        need(m > 0 and semidefinite(pseudo_inertia(inertia)), f"{where}: not a consistent rigid body (m > 0, "
             "Sigma_c >= 0)")
        reach, d1, d2 = _path(item.get("path"), f"{where}.path")
        rate, acc = _profile(item.get("profile"), f"{where}.profile")
        loads.append({"body": item["body"] - 1, "m": m, "inertia": inertia, "reach": reach, "speed": d1 * rate,
                      "acc": None if acc is None else d1 * acc + d2 * rate * rate})
    return loads


def _rate(load, quantity):
    """The load's term of the bound on sigma_max of the rate or on ||Psi|| (``psi_dot``: ||Psidot||), a ball."""
    lever, m = arb(1 + load["reach"]).sqrt(), arb(load["m"])
    if quantity == "sigma_max_fdot":
        return m * load["speed"] * (arb(load["reach"]).sqrt() + lever)
    if quantity == "sigma_max_Zdot":
        return 2 * m * load["speed"] * lever
    need(load["acc"] is not None or quantity != "psi_dot", "psi_dot: a linear profile's rate jumps: no bound of Psidot")
    return m * (load["speed"] if quantity == "psi" else load["acc"]) * lever


def prove(cert):
    """The :class:`Outcome` of the claim: each body's matrix condition decided exactly, the loads' sums in balls."""
    quantity, bound = cert["claim"].get("quantity"), rational(cert["claim"].get("bound"), "claim.bound")
    need(quantity in QUANTITIES, f"claim.quantity: one of {list(QUANTITIES)}")
    sets, psi = parameter_sets(cert), quantity.startswith("psi")
    need(len(sets) == 1 or not psi, "parameters: one set, the bodies' constant rows")
    loads = _loads(cert, len(sets[0]))
    matrix = pseudo_inertia if quantity.endswith(("_f", "fdot")) else spatial_inertia

    def conditions(l, row):
        mine = [load for load in loads if psi or load["body"] == l]
        if quantity.startswith("lambda_min"):
            return [("F - bound I", matrix(row), 1, -bound)]
        if quantity.startswith("lambda_max"):  # F(row + the loads' (0, 0, I_c)) + m (1 + C^2) I: F is linear
            f = matrix([x + sum(load["inertia"][i] for load in mine) for i, x in enumerate(row)])
            return [("bound I - F - the loads' bounds", f, -1, bound - sum(p["m"] * (1 + p["reach"]) for p in mine))]
        total = finite(sum((_rate(load, quantity) for load in mine), arb(0)), "the loads' sum")
        f, r, what = [[fmpq(0)]] if psi else matrix(row), dyadic(total.upper()), f"sigma_max(F) + {total.str(10)}"
        return [(f"{what} <= bound", f, -1, bound - r), (f"{what} <= bound", f, 1, bound - r)]

    fail, _ = first_failure([[None]] if psi else sets, conditions)
    if fail:
        return Outcome(UNPROVED, f"{'Psi' if psi else f'body {fail[1] + 1} of set {fail[0] + 1}'}: {fail[2]} fails "
                       "(exact rational arithmetic)", 0, {"quantity": quantity})
    return Outcome(REPROVED, f"{len(sets)} set(s), {len(loads)} moving load(s): decided exactly", 0)
