"""The two equivalences of Section 2, symbolically and on random input (EQ-schur, EQ-triangle).

Each side of an equivalence is decided on its own: in floats where the
margin exceeds the resolution (64 eps relative to the matrix), otherwise in
rational arithmetic on the exact values. A disagreement is a counterexample.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from hypothesis import strategies as st
from inertiaproof.checks.identities import all_of, identity_result
from inertiaproof.counterexamples.boundary import boundary_phi, near_boundary_phi, principal_inertia, shifted_com_phi
from inertiaproof.counterexamples.inertias import any_phi, consistent_phi, pseudo_inertia_pd
from inertiaproof.symbolic import identities

from inertiaproof.errors import InputError, numbers
from inertiaproof.model import exact
from inertiaproof.model.consistency import CONSISTENT, decide_exactly, physical_consistency
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse, sigma_com, unpack
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "definiteness", "EPS", "eq_schur", "eq_triangle", "exact_pseudo_inertia", "phi_strategy",
    "pseudo_inertia_side", "replay_equivalence", "RESOLUTION", "schur_margin", "schur_numeric", "schur_side",
    "schur_sweep", "strict_triangle", "triangle_decisions", "triangle_margin", "triangle_numeric",
]

EPS = np.finfo(float).eps
RESOLUTION = 64 * EPS


def definiteness(q):
    """'pd', 'psd' or 'indefinite' of a symmetric matrix of Fractions, exactly."""
    return exact.definiteness(exact.integer_matrix(q))[0]


def exact_pseudo_inertia(phi):
    """f(Phi) in Fractions for the exact values of the float row Phi."""
    m, h1, h2, h3, i11, i22, i33, i12, i23, i13 = (Fraction(float(x)) for x in phi)
    inertia = np.array([[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]], dtype=object)
    f = np.empty((4, 4), dtype=object)
    f[:3, :3] = (i11 + i22 + i33) / 2 * np.eye(3, dtype=int) - inertia
    f[:3, 3] = f[3, :3] = (h1, h2, h3)
    f[3, 3] = m
    return f


def pseudo_inertia_side(phi):
    """(f(Phi) > 0, decided exactly?, lambda_min(f)/||f||_F)."""
    f = pseudo_inertia(phi)
    lam = np.linalg.eigvalsh(f)[0]
    norm = np.linalg.norm(f)
    margin = lam / norm if norm > 0 else 0.0
    if abs(lam) > RESOLUTION * norm:
        return bool(lam > 0), False, margin
    return definiteness(exact_pseudo_inertia(phi)) == "pd", True, margin


def schur_side(phi, schur_complement=sigma_com):
    """(m > 0 and Sigma_CoM > 0, decided exactly?)."""
    m, h, inertia = unpack(phi)
    if not m > 0:
        return False, False
    with np.errstate(over="ignore", invalid="ignore"):
        s = schur_complement(phi)
        lam = np.linalg.eigvalsh(s)[0] if np.all(np.isfinite(s)) else np.nan
        scale = np.linalg.norm(s) + np.linalg.norm(inertia) + h @ h / m
    if np.isfinite(scale) and abs(lam) > RESOLUTION * scale:
        return bool(lam > 0), False
    return decide_exactly(phi)[0] == CONSISTENT, True


def schur_margin(phi, rhs=schur_side, record=None):
    """|lambda_min(f)|/||f||_F where both sides agree, -1 where they do not."""
    lhs, lhs_exact, margin = pseudo_inertia_side(phi)
    right, right_exact = rhs(phi)
    if record is not None:
        record["exact"] += lhs_exact or right_exact
    return abs(margin) if lhs == right else -1.0


def phi_strategy():
    return st.one_of(any_phi, consistent_phi(), shifted_com_phi(), boundary_phi(), near_boundary_phi(),
                     pseudo_inertia_pd().map(pseudo_inertia_inverse))


def schur_sweep(rng, ordinary=4000, boundary=400):
    """Batched: eigvalsh(f) against physical_consistency (the Schur route) on random and boundary rows.

    ``ordinary`` random f > 0 and as many arbitrary Phi; ``boundary`` sums of
    up to three integer point masses (exactly singular f) and as many of them
    moved by one ulp in I11.
    """
    consistent = pseudo_inertia_inverse(_random_pd(rng, ordinary))
    arbitrary = rng.normal(size=(ordinary, 10)) * 10.0 ** rng.uniform(-3, 3, size=(ordinary, 1))
    points = rng.integers(-6, 7, size=(2 * boundary, 3, 3)).astype(float)
    masses = rng.integers(0, 6, size=(2 * boundary, 3)).astype(float)
    masses[:, 0] += 1
    singular = pseudo_inertia_inverse(np.einsum("np,npij->nij", masses, _homogeneous_outer(points)))
    singular[boundary:, 4] = np.nextafter(singular[boundary:, 4],
                                          np.where(rng.random(boundary) < 0.5, -np.inf, np.inf))
    phi = np.concatenate([consistent, arbitrary, singular])
    f = pseudo_inertia(phi)
    lam = np.linalg.eigvalsh(f)[:, 0]
    norm = np.linalg.norm(f, axis=(1, 2))
    lhs = lam > 0
    unresolved = np.flatnonzero(np.abs(lam) <= RESOLUTION * norm)
    for i in unresolved:
        lhs[i] = definiteness(exact_pseudo_inertia(phi[i])) == "pd"
    rhs = physical_consistency(phi, margins=False)
    disagree = np.flatnonzero(lhs != (rhs.verdict == CONSISTENT))
    return phi, disagree, unresolved.size, int(rhs.decided_exactly.sum())


def _random_pd(rng, n):
    q, _ = np.linalg.qr(rng.normal(size=(n, 4, 4)))
    lam = 10.0 ** rng.uniform(-12, 0, size=(n, 4))
    return 10.0 ** rng.uniform(-3, 3, size=(n, 1, 1)) * (q * lam[:, None, :]) @ np.swapaxes(q, 1, 2)


def _homogeneous_outer(points):
    x = np.concatenate([points, np.ones(points.shape[:-1] + (1,))], -1)
    return x[..., :, None] * x[..., None, :]


def schur_numeric(ctx, rhs=schur_side, strategy=None):
    """Hypothesis hunt and a batched sweep for disagreements of f > 0 and (m > 0, Sigma_CoM > 0)."""
    record = {"exact": 0}
    ctx.progress("hunting Phi where f > 0 and (m > 0, Sigma_CoM > 0) disagree")
    h = hunt(phi_strategy() if strategy is None else strategy, lambda phi: schur_margin(phi, rhs, record), ctx,
             label="EQ-schur")
    evidence = {"hunt": {**h.summary(), "margins": h.margins},
                "hunt_exact_decisions": quantity(record["exact"], "count",
                                                 "examples with a side below float resolution, decided in rational arithmetic"),
                "margin_meaning": "|lambda_min(f)|/||f||_F where both sides agree (0: exactly singular); -1 where they disagree",
                "resolution": quantity(RESOLUTION, "tolerance", "64 eps relative to the matrix: below it a side is decided exactly")}
    if h.violation is not None:
        phi = np.asarray(h.violation, dtype=float)
        return Result("EQ-schur", Verdict.VIOLATED, f"f > 0 and (m > 0, Sigma_CoM > 0) disagree at Phi = {phi.tolist()}",
                      evidence, counterexample={"kind": "equivalence", "data": {"id": "EQ-schur", "phi": phi.tolist()}})
    if rhs is schur_side:
        phi, disagree, lhs_exact, rhs_exact = schur_sweep(ctx.rng("EQ-schur"), 2 * ctx.profile.samples,
                                                          ctx.profile.samples // 5)
        evidence["sweep"] = {
            "rows": quantity(len(phi), "count", "batched: random f > 0, arbitrary Phi, point masses and their 1-ulp moves"),
            "disagreements": quantity(disagree.size, "count", "rows where eigvalsh(f) and physical_consistency disagree"),
            "exact_decisions": quantity(lhs_exact + rhs_exact, "count", "row sides below float resolution, decided exactly"),
        }
        if disagree.size:
            bad = phi[disagree[0]]
            return Result("EQ-schur", Verdict.VIOLATED, f"sweep: f > 0 and physical_consistency disagree at {bad.tolist()}",
                          evidence, counterexample={"kind": "equivalence", "data": {"id": "EQ-schur", "phi": bad.tolist()}})
    return Result("EQ-schur", Verdict.HOLDS, f"f > 0 iff m > 0 and Sigma_CoM > 0 on {h.examples} hunted Phi"
                  + (f" and {len(phi)} swept rows" if "sweep" in evidence else ""), evidence)


@check("EQ-schur")
def eq_schur(ctx):
    return all_of("EQ-schur", [
        ("symbolic", identity_result("EQ-schur", *identities.schur_factorisation(),
                                     "f = L diag(Sigma_CoM, m) L^T with L = [[I3, h/m], [0, 1]] (Sylvester: same inertia)")),
        ("numeric", schur_numeric(ctx)),
    ], "f(Phi) > 0 iff m > 0 and Sigma_CoM > 0")


def strict_triangle(lam):
    a, b, c = lam
    return a < b + c and b < a + c and c < a + b


def triangle_decisions(lam, rot, sigma_map=None, triangle=strict_triangle):
    """(Sigma_CoM > 0, strict triangle inequalities, I_CoM > 0, decided exactly?) for I_CoM = R diag(lambda) R^T."""
    i_com = rot @ np.diag(np.array(lam, dtype=object)) @ rot.T
    sigma = (np.trace(i_com) / 2 * np.eye(3, dtype=int) - i_com) if sigma_map is None else sigma_map(i_com)
    approx = np.array(sigma, dtype=float)
    low = np.linalg.eigvalsh(approx)[0]
    resolved = abs(low) > RESOLUTION * (np.linalg.norm(approx) + float(sum(abs(x) for x in lam)))
    sigma_pd = bool(low > 0) if resolved else definiteness(sigma) == "pd"
    return sigma_pd, triangle(lam), definiteness(i_com) == "pd", not resolved


def triangle_margin(example, sigma_map=None, triangle=strict_triangle, record=None):
    """|smallest triangle slack| / sum |lambda| where all agree; -1 on a disagreement or a failed footnote."""
    lam, rot = example
    sigma_pd, strict, i_pd, exactly = triangle_decisions(lam, rot, sigma_map, triangle)
    slack = min(lam[1] + lam[2] - lam[0], lam[0] + lam[2] - lam[1], lam[0] + lam[1] - lam[2])
    if record is not None:
        record["exact"] += exactly
        record["equalities"] += slack == 0
    if sigma_pd != strict or (strict and not i_pd):
        return -1.0
    total = sum(abs(x) for x in lam)
    return float(abs(slack) / total) if total else 0.0


def triangle_numeric(ctx, sigma_map=None, triangle=strict_triangle):
    record = {"exact": 0, "equalities": 0}
    ctx.progress("hunting I_CoM where Sigma_CoM > 0 and the strict triangle inequalities disagree")
    h = hunt(principal_inertia(), lambda e: triangle_margin(e, sigma_map, triangle, record), ctx, label="EQ-triangle")
    evidence = {"hunt": {**h.summary(), "margins": h.margins},
                "equality_cases": quantity(record["equalities"], "count",
                                           "examples with a triangle inequality holding with equality (Sigma_CoM singular)"),
                "exact_decisions": quantity(record["exact"], "count", "examples decided in rational arithmetic"),
                "construction": "I_CoM = R diag(lambda) R^T, dyadic lambda, R rational from an integer quaternion: "
                                "the triangle inequalities are decided exactly on lambda, definiteness by exact minors",
                "margin_meaning": "|smallest triangle slack| / sum |lambda| where all agree (0: on the boundary); -1 otherwise"}
    if h.violation is not None:
        lam, rot = h.violation
        data = {"id": "EQ-triangle", "lambda": [str(x) for x in lam], "rotation": [[str(x) for x in row] for row in rot]}
        return Result("EQ-triangle", Verdict.VIOLATED, f"Sigma_CoM > 0, strict triangle inequalities and I_CoM > 0 "
                      f"disagree at principal moments {data['lambda']}", evidence,
                      counterexample={"kind": "equivalence", "data": data})
    return Result("EQ-triangle", Verdict.HOLDS, f"Sigma_CoM > 0 iff strict triangle inequalities, and these give "
                  f"I_CoM > 0, on {h.examples} examples ({record['equalities']} on the boundary)", evidence)


@check("EQ-triangle")
def eq_triangle(ctx):
    return all_of("EQ-triangle", [
        ("spectrum of Sigma_CoM", identity_result("EQ-triangle", *identities.spectrum_of_sigma(),
                                                  "det(t I - Sigma(J)) = -det((tr(J)/2 - t) I - J)")),
        ("spectrum of I_CoM", identity_result("EQ-triangle", *identities.spectrum_of_inertia(),
                                              "det(t I - I(S)) = -det((tr(S) - t) I - S)")),
        ("numeric", triangle_numeric(ctx)),
    ], "Sigma_CoM > 0 iff I_CoM satisfies the strict triangle inequalities, which imply I_CoM > 0")


def _fractions(values, where, count):
    if not isinstance(values, list) or len(values) != count:
        raise InputError(f"{where}: needs {count} numbers")
    try:
        return [Fraction(str(x)) for x in values]
    except (ValueError, ZeroDivisionError):
        raise InputError(f"{where}: not exact numbers: {values!r}") from None


@replayer("equivalence")
def replay_equivalence(data, ctx):
    """Decide both sides of the equivalence again on the saved example."""
    if data.get("id") == "EQ-schur":
        phi = numbers(data.get("phi"), "counterexample data: field 'phi'", (10,))
        lhs, _, margin = pseudo_inertia_side(phi)
        rhs, _ = schur_side(phi)
        verdict = Verdict.HOLDS if lhs == rhs else Verdict.VIOLATED
        return Result("EQ-schur", verdict, f"f > 0: {lhs}; m > 0 and Sigma_CoM > 0: {rhs} (lambda_min(f)/||f|| = {margin:.3e})")
    if data.get("id") != "EQ-triangle":
        raise InputError(f"counterexample data: field 'id' must be EQ-schur or EQ-triangle, got {data.get('id')!r}")
    lam = _fractions(data.get("lambda"), "counterexample data: field 'lambda'", 3)
    rows = data.get("rotation")
    rot = np.array([_fractions(r, "counterexample data: field 'rotation'", 3) for r in rows]
                   if isinstance(rows, list) and len(rows) == 3 else _fractions(rows, "counterexample data: field 'rotation'", 9),
                   dtype=object)
    if not (rot @ rot.T == np.eye(3, dtype=int)).all():
        raise InputError("counterexample data: field 'rotation' is not exactly orthogonal")
    sigma_pd, strict, i_pd, _ = triangle_decisions(lam, rot)
    verdict = Verdict.HOLDS if sigma_pd == strict and (i_pd or not strict) else Verdict.VIOLATED
    return Result("EQ-triangle", verdict, f"Sigma_CoM > 0: {sigma_pd}; strict triangle inequalities: {strict}; I_CoM > 0: {i_pd}")
