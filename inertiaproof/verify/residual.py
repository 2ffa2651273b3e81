"""The ``residual-bound`` claim (issue 50): no physically consistent parameters fit the data better than a bound.

``data``: normal equations as written, r(Theta) = Theta^T H Theta - 2 g^T Theta + c, Theta = (Phi_1..Phi_N, x), ten
columns per body (Section 2's order), then the extra (friction) columns x. K: f(Phi_l) >= 0 (every consistent body
and their limits), tr f(Phi_l) = m_l + tr(I_l)/2 <= T_l, |x_j| <= B_j and, with ``ellipsoids``, tr(Q_l f(Phi_l)) >= 0
(the body inside its bounding ellipsoid, Wensing et al. 2017) (``bounds``). ``lower``: r >= bound on K;
``excess``: r >= (1 + bound) r(Theta_ref) on K (``reference``, a least-squares fit).

Proof (``dual``: Z_l >= 0, mu_l, nu_l >= 0, decided exactly; y; sigma): on K, tr(Z_l f_l) + mu_l (T_l - tr f_l) +
nu_l tr(Q_l f_l) >= 0, so r(Theta) >= d^T H d + 2 d^T s + D, d = Theta - y, g' = g + f^*(Z - mu I + nu Q)/2,
s = H y - g', D = y^T H y - 2 g'^T y + c - sum mu_l T_l (exact). H + sigma I > 0 (LDL^T in balls) gives
d^T H d >= -sigma |d|^2; on K |Phi_l|^2 <= 3 T_l^2 (h_i^2 <= m Sigma_ii, Sigma_ij^2 <= Sigma_ii Sigma_jj,
I = tr(Sigma) I3 - Sigma), so |d| <= R = (sum 3 T_l^2 + sum B_j^2)^(1/2) + |y| and r >= D - sigma R^2 - 2 |s| R.
Refuted only at y: y in K (exact) with r(y) below the side.
"""

import hashlib
import json
import re
from types import SimpleNamespace

from flint import arb, ctx, fmpq, fmpq_mat

from .bodies import pseudo_inertia
from .exact import fields, finite, need, rational, semidefinite, symmetric, unproved_pivot, vector
from .outcome import REPROVED, UNPROVED, Outcome, refuted

COLUMNS = 400  # the most columns of H a certificate may have
PRECISION = 320  # bits of the balls of the LDL^T of H + sigma I
UNITS = [pseudo_inertia([fmpq(int(i == k)) for i in range(10)]) for k in range(10)]  # f^*(Z)_k = <Z, f(e_k)>


def _nonnegative(xs, n, where):
    out = vector(xs, n, where)
    need(all(x >= 0 for x in out), f"{where}: numbers >= 0")
    return out


def _per_body(ms, n, where):
    need(isinstance(ms, list) and len(ms) == n, f"{where}: a symmetric 4x4 matrix per body ({n})")
    return [symmetric(m, 4, f"{where}[{l}]") for l, m in enumerate(ms)]


def parse(cert):
    """The certificate's exact numbers (a namespace), every field checked for shape."""
    fields(cert, {"schema", "claim", "data", "bounds", "dual"}, "certificate", {"reference", "provenance"})
    claim = fields(cert["claim"], {"kind", "quantity", "bound"}, "claim")
    need(claim["quantity"] in ("lower", "excess") and (claim["quantity"] == "excess") == ("reference" in cert),
         "claim.quantity: lower, or excess with a reference")
    data = fields(cert["data"], {"H", "g", "c", "rows", "bodies", "extra"}, "data", {"source"})
    names, source = (data["bodies"], data["extra"]), data.get("source", {"path": "", "sha256": "0" * 64})
    need(all(isinstance(v, list) and all(isinstance(x, str) for x in v) for v in names) and type(data["rows"]) is int
         and data["rows"] >= 0 and 0 < 10 * len(names[0]) + len(names[1]) <= COLUMNS,
         f"data: bodies and extra are lists of names (1 to {COLUMNS} columns), rows a count")
    n, p = len(names[0]), 10 * len(names[0]) + len(names[1])
    need(isinstance(fields(source, {"path", "sha256"}, "data.source")["path"], str)
         and re.fullmatch(r"[0-9a-f]{64}", str(source["sha256"])), "data.source: {path, sha256 (64 hex digits)}")
    bounds = fields(cert["bounds"], {"trace", "extra"}, "bounds", {"ellipsoids"})
    dual = fields(cert["dual"], {"Z", "mu", "theta", "sigma"}, "dual", {"nu"})
    need(("ellipsoids" in bounds) == ("nu" in dual), "bounds.ellipsoids: with dual.nu, and dual.nu with them")
    return SimpleNamespace(
        quantity=claim["quantity"], bound=rational(claim["bound"], "claim.bound"), n=n, names=names,
        H=symmetric(data["H"], p, "data.H"), g=vector(data["g"], p, "data.g"), c=rational(data["c"], "data.c"),
        T=_nonnegative(bounds["trace"], n, "bounds.trace"), B=_nonnegative(bounds["extra"], p - 10 * n, "bounds.extra"),
        Q=_per_body(bounds.get("ellipsoids", [[["0"] * 4] * 4] * n), n, "bounds.ellipsoids"),
        y=vector(dual["theta"], p, "dual.theta"), Z=_per_body(dual["Z"], n, "dual.Z"),
        mu=_nonnegative(dual["mu"], n, "dual.mu"), nu=_nonnegative(dual.get("nu", ["0"] * n), n, "dual.nu"),
        sigma=_nonnegative([dual["sigma"]], 1, "dual.sigma")[0],
        ref=vector(cert["reference"], p, "reference") if "reference" in cert else None)


def _r(q, theta):
    t = fmpq_mat([[x] for x in theta])
    return (t.transpose() * fmpq_mat(q.H) * t)[0, 0] - 2 * sum(a * b for a, b in zip(q.g, theta)) + q.c


def _inside(q, theta):
    """Whether theta lies in K, decided exactly."""
    bodies = [pseudo_inertia(theta[10 * l:10 * l + 10]) for l in range(q.n)]
    return all(semidefinite(f) and sum(f[i][i] for i in range(4)) <= t and _dot(w, f) >= 0
               for f, t, w in zip(bodies, q.T, q.Q)) and all(abs(x) <= b for x, b in zip(theta[10 * q.n:], q.B))


def _dot(a, b):
    """<A, B> = tr(A B) of symmetric matrices."""
    return sum(x * y for r, s in zip(a, b) for x, y in zip(r, s))


def dual_side(q):
    """(a ball below r on K, why) from the parsed certificate ``q``'s dual, or (None, why not)."""
    for l, z in enumerate(q.Z):
        if not semidefinite(z):
            return None, f"dual.Z of body {l + 1} ({q.names[0][l]}) is not positive semidefinite (exact)"
    gp = list(q.g)  # g' = g + f^*(Z_l - mu_l I + nu_l Q_l) / 2
    for l, (z, mu, nu, w) in enumerate(zip(q.Z, q.mu, q.nu, q.Q)):
        a = [[z[i][j] - (mu if i == j else 0) + nu * w[i][j] for j in range(4)] for i in range(4)]
        for k, e in enumerate(UNITS):
            gp[10 * l + k] += _dot(a, e) / 2
    hy = fmpq_mat(q.H) * fmpq_mat([[x] for x in q.y])
    s = [hy[i, 0] - gp[i] for i in range(len(q.y))]
    dual = sum(a * (b - c) for a, b, c in zip(q.y, s, gp)) + q.c - sum(m * t for m, t in zip(q.mu, q.T))
    with ctx.workprec(PRECISION):
        sigma = arb(q.sigma)
        k = unproved_pivot([[arb(x) + (sigma if i == j else 0) for j, x in enumerate(r)] for i, r in enumerate(q.H)])
        if k is not None:
            return None, f"H + sigma I is not proved positive definite: pivot {k + 1} of its LDL^T"
        radius = arb(sum(3 * t * t for t in q.T) + sum(b * b for b in q.B)).sqrt() + arb(sum(x * x for x in q.y)).sqrt()
        low = arb(dual) - sigma * radius * radius - 2 * arb(sum(x * x for x in s)).sqrt() * radius
        return finite(low, "the dual bound"), "D - sigma R^2 - 2 |s| R (Z_l >= 0 exact, H + sigma I > 0 in balls)"


def prove(cert):
    """The :class:`.outcome.Outcome` of the claim."""
    q = parse(cert)
    side = q.bound if q.ref is None else (1 + q.bound) * _r(q, q.ref)
    if _inside(q, q.y) and _r(q, q.y) < side:
        return refuted("dual.theta lies in K (decided exactly) and its residual is below the claimed side",
                       {"theta": "dual.theta"}, {"r(theta)": str(_r(q, q.y)), "side": str(side)})
    low, why = dual_side(q)
    if low is None:
        return Outcome(UNPROVED, why)
    words = f"{why}: {low.str(10, radius=False)} against the side {arb(side).str(10, radius=False)}"
    return Outcome(REPROVED, words) if low >= arb(side) else Outcome(UNPROVED, "below the side: " + words)


def statement(cert, decimal):
    """The claim in words (``decimal(x, up)``: the rational x rounded up or down); the set's bounds rounded down."""
    q, data = parse(cert), cert["data"]
    digest = hashlib.sha256(json.dumps([data["H"], data["g"], data["c"]]).encode()).hexdigest()[:12]
    where = f" of {data['source']['path']} (SHA-256 {data['source']['sha256'][:12]})" if "source" in data else ""
    ends = lambda xs: "[" + ", ".join(decimal(x, False) for x in xs) + "]"  # noqa: E731
    side = decimal(q.bound, False)
    if q.ref is not None:
        r = _r(q, q.ref)
        side = (f"(1 + {side}) r(Theta_ref), r(Theta_ref) in [{decimal(r, False)}, {decimal(r, True)}] for Theta_ref "
                "as written: no such Theta fits within that factor of Theta_ref")
    inside = [name for name, w in zip(q.names[0], q.Q) if any(x != 0 for row in w for x in row)]
    inside = f", tr(Q_l f(Phi_l)) >= 0 for the bounding ellipsoids Q_l as written of {', '.join(inside)}" if inside \
        else ""
    extra = f"; x of the extra columns {', '.join(q.names[1])}, |x_j| <= {ends(q.B)}" if q.B else ""
    return (f"for every Theta = (Phi_l of the {q.n} bodies {', '.join(q.names[0])} with f(Phi_l) >= 0 (physically "
            f"consistent) and m_l + tr(I_l)/2 <= T_l = {ends(q.T)}{inside}{extra}): r(Theta) = Theta^T H Theta - 2 g^T "
            f"Theta + c >= {side}, for the normal equations (H, g, c: {digest}), said to sum {data['rows']} rows"
            + where)
