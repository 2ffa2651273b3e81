"""Certificates of the certified sides of the mass-matrix brackets, for the independent checker.

A certificate (schema ``inertiaproof.certificate/2``, documented in the README) is self-contained: the claim,
the chain as its source writes it (each fixed transform as origins {xyz, rpy}, from which the checker builds a
rigid transform itself), the parameter sets and how they were formed, and the configuration box, every other
number an exact rational ("p/q") equal to the float64 the prover used. A claim carries no statement: the checker
writes it. ``inertiaproof verify`` (:mod:`inertiaproof.verify`, which shares no code with this package)
re-proves it; :meth:`inertiaproof.bounds.extremes.Bracket.evidence` cites the certificate of its certified side;
the runner writes it under ``OUT/certificates/``.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from inertiaproof.dynamics.trajectory import MovingMass
from inertiaproof.model.exact import definiteness, integer_matrix

from .domain import certification_obstacle, search_box
from .written import chain_data, distinct, domain_data, exact, exact_rows

__all__ = ["PayloadClaim", "SCHEMA", "SpectrumClaim", "body_spectrum_certificate", "distinct", "exact",
           "key_step_certificate",
           "moving_mass_certificate", "payload_f_certificate", "product_certificate", "pseudo_exact",
           "skew_certificate", "SkewClaim", "spatial_exact", "spatial_psd", "spectrum_certificate", "sum_certificate",
           "ZERO_FLOOR"]

SCHEMA = "inertiaproof.certificate/2"
@dataclass(frozen=True)
class PivotProof:
    """What a pivot ladder hands to its certificate: the partition that proved its rung as a tree
    (:func:`partition_tree`; None where its boxes do not tile the domain, which the checker rejects) and the body
    matrices proved on, ``forms`` (V, N, 6, 6): lower forms Y_l <= Z(Phi_l) of a
    lower claim, or None where they are the parameter sets' own."""

    tree: str
    forms: np.ndarray | None = None
    metric: tuple = ("shift", 0.1)  # the turns' loss metric (kind, ridge) the ladder calibrated: the checker's hint


@dataclass(frozen=True)
class SplitProof:
    """What the chain split (:mod:`inertiaproof.bounds.interface`) hands to its certificate: the body k it splits
    at, the interface inertias L (V, 6, 6), one per parameter set, and the trees of the tail's partition (joints
    k+1.., A_k(q) >= L) and of the head's (joints ..k with body k's inertia L)."""

    body: int
    interfaces: np.ndarray
    tail: str | None
    head: str | None
    metric: tuple = ("abs", 1e-3)


def partition_tree(centres, radii, lo, hi):
    """The prefix code (:mod:`inertiaproof.verify.tree`) of a partition of the box [lo, hi] into boxes (centres, radii)
    (K, n) made by halving (a coordinate of radius 0 is left whole); None when the boxes are not such a partition.
    A box is cut along a coordinate whose middle no box straddles (any such cut is one the halving made or could
    have made: every box lies in one half)."""
    centres, radii = np.asarray(centres, float), np.asarray(radii, float)
    moving = radii.max(0) > 0
    tokens, stack = [], [(np.arange(len(centres)), np.asarray(lo, float), np.asarray(hi, float))]
    while stack:
        rows, a, b = stack.pop()
        middle, tol = 0.5 * (a + b), 1e-9 * (b - a)
        if len(rows) == 1:
            c, r = centres[rows[0]], radii[rows[0]]
            if np.any(moving & ((np.abs(c - middle) > tol) | (np.abs(r - 0.5 * (b - a)) > tol))):
                return None
            tokens.append(".")
            continue
        low = centres[rows] + radii[rows] <= middle + tol
        high = centres[rows] - radii[rows] >= middle - tol
        cuts = np.flatnonzero(moving & (low | high).all(0) & low.any(0) & high.any(0))
        if not len(rows) or not len(cuts):
            return None
        k = int(cuts[0])
        tokens.append(str(k))
        upper_a, lower_b = a.copy(), b.copy()
        upper_a[k] = lower_b[k] = middle[k]
        stack.append((rows[high[:, k]], upper_a, b))
        stack.append((rows[low[:, k]], a, lower_b))
    return " ".join(tokens)


def _proof_fields(proof):
    """The certificate's fields of a proof: its tree (None where the prover's boxes were no partition, which the
    checker rejects), or the split's."""
    if proof is None:
        return {"tree": ".", "metric": {"kind": "shift", "ridge": "1/10"}}
    metric = {"metric": {"kind": proof.metric[0], "ridge": exact(proof.metric[1])}}
    if isinstance(proof, SplitProof):
        return {"tree": ".", "split": {"body": proof.body, "interfaces": [exact_rows(m) for m in proof.interfaces],
                                       "tail": proof.tail, "head": proof.head}, **metric}
    return {"tree": proof.tree, **metric}


def spectrum_certificate(chain, thetas, quantity, bound, provenance="", witness=None, proof=None, formation=None):
    """The certificate of "for all q in the chain's search box and Theta in the convex hull of ``thetas`` (V, N, 10),
    lambda_min(M(q, Theta)) >= bound" (``quantity`` "lambda_min"; "lambda_max": <= bound); None where the checker
    has no claim of this kind for the chain (a coordinate map other than the identity, an unbounded slide). The
    ``witness``, a configuration where the prover saw the extreme, is where the checker looks first; ``proof`` (a
    :class:`PivotProof`) gives the partition it starts from and, for a lower claim, the forms it proves on;
    ``formation`` (:func:`inertiaproof.bounds.time.formation`) how the parameter sets were formed."""
    written = chain_data(chain)
    if certification_obstacle(chain) is not None or not np.isfinite(float(bound)) or written is None:
        return None
    lo, hi = search_box(chain)
    thetas = np.asarray(thetas, float)
    forms = proof.forms if isinstance(proof, PivotProof) and quantity == "lambda_min" else None
    if isinstance(proof, SplitProof) or forms is not None and len(forms) == len(thetas) > 1:  # paired: keep the order
        sets = thetas
    else:
        sets = distinct(thetas)
    return {"schema": SCHEMA,
            "claim": {"kind": "mass-matrix-spectrum", "quantity": quantity, "bound": exact(bound)},
            "chain": written,
            "domain": domain_data(chain, written["joints"]),
            "parameters": [exact_rows(s) for s in sets],
            **({} if formation is None else {"formation": formation}),
            **_proof_fields(proof),
            **({"forms": [[exact_rows(y) for y in form] for form in forms]} if forms is not None else {}),
            **({"witness": [exact(x) for x in np.clip(witness, lo, hi)]} if witness is not None else {}),
            "provenance": provenance}


@dataclass(frozen=True)
class SpectrumClaim:
    """bound -> the certificate of a bracket's certified side (``square``: the bracket is of a square root, so the
    claim is of bound^2, exactly); plain data, so a Bracket that carries it can be pickled."""

    chain: object
    thetas: np.ndarray
    quantity: str
    square: bool = False
    formation: dict | None = None  # how the parameter sets were formed (bounds.time.formation)

    def __call__(self, bound, note="", witness=None, proof=None):
        if self.quantity == "lambda_min" and float(bound) == 0.0 and spatial_psd(self.thetas):
            return body_spectrum_certificate(self.thetas, "lmin_Z", 0.0, ZERO_FLOOR + note, formation=self.formation)
        bound = Fraction(float(bound)) ** 2 if self.square else bound
        return spectrum_certificate(self.chain, self.thetas, self.quantity, bound, note, witness, proof,
                                    self.formation)


ZERO_FLOOR = ("lambda_min(M(q, Theta)) >= 0 for every q as M = (QJ)^T blockdiag(Z(Phi_l)) QJ (MassMatrix, "
              "DefBlockmatrixZ), so it is Z(Phi_l) >= 0 on the hull that is claimed: ")


def spatial_exact(row):
    """Z(Phi) (DefMatrixZ) of a row of floats, in exact Fractions."""
    m, h1, h2, h3, i11, i22, i33, i12, i23, i13 = (Fraction(float(x)) for x in row)
    zero = Fraction(0)
    return [[m, zero, zero, zero, h3, -h2], [zero, m, zero, -h3, zero, h1], [zero, zero, m, h2, -h1, zero],
            [zero, -h3, h2, i11, i12, i13], [h3, zero, -h1, i12, i22, i23], [-h2, h1, zero, i13, i23, i33]]


def spatial_psd(thetas):
    """Whether Z(Phi_l) >= 0 for every row of ``thetas`` (..., 10), decided exactly (so on their convex hull: Z is
    linear in Phi); False where a row is not finite."""
    rows = distinct(np.asarray(thetas, float).reshape(-1, 10))
    return bool(np.all(np.isfinite(rows))) and all(
        definiteness(integer_matrix(spatial_exact(row)))[0] in ("pd", "psd")
        for row in rows)


@dataclass(frozen=True)
class PayloadClaim:
    """bound -> the certificate (kind ``payload-envelope``) of a bracket's certified side over a payload set: the
    spectrum claim ``inner`` proved (parameter sets ``arm`` with, for "lambda_max", Phi_U of Young's ``eps`` at the
    payload's body: :func:`inertiaproof.bounds.payload.covering_parameters`), restated for the arm ``arm`` (V, N,
    10) carrying any payload of the set ``payloads``; the checker adds Phi_U itself."""

    inner: object
    arm: np.ndarray
    payloads: object
    quantity: str
    eps: float | None = None

    def __call__(self, bound, note="", witness=None, proof=None):
        cert = self.inner(bound, note, witness, proof) if self.inner else None
        if cert is None or "parameters" not in cert:
            return None
        sets = distinct(self.arm)
        if len(cert["parameters"]) != len(sets):
            return None
        claim = {**cert["claim"], "kind": "payload-envelope"}
        return {**cert, "claim": claim, "parameters": [exact_rows(s) for s in sets], "payload": self.payloads.to_json(),
                **({"epsilon": exact(self.eps)} if self.quantity == "lambda_max" else {})}


def pseudo_exact(row):
    """f(Phi) (DefTrafoInertialParameters) of a row of floats or Fractions, in exact Fractions."""
    m, h1, h2, h3, i11, i22, i33, i12, i23, i13 = (x if isinstance(x, Fraction) else Fraction(float(x)) for x in row)
    half = (i11 + i22 + i33) / 2
    return [[half - i11, -i12, -i13, h1], [-i12, half - i22, -i23, h2], [-i13, -i23, half - i33, h3], [h1, h2, h3, m]]


def payload_f_certificate(arm, payloads, beta):
    """The certificate (kind ``payload-envelope``, quantity ``lambda_max_f``) of "for every body l, Theta in the hull
    of ``arm`` (V, N, 10) and payload Phi_p of the set ``payloads`` (at its body): lambda_max(f(Phi_l + Phi_p)) <=
    bound", bound = max_l lambda_max(f(Phi_l)) (+ ``beta`` at the payload's body), beta >= m ((|c| + a_max)^2 + 1) a
    Fraction; the bound is found in floats and confirmed (raised by 2^-40 relative until it holds) in exact
    arithmetic. None where a row is not finite."""
    arm = np.asarray(arm, float)
    if not np.all(np.isfinite(arm)):
        return None
    lifts = [Fraction(beta) if l == payloads.body else Fraction(0) for l in range(arm.shape[1])]
    pseudo = [(pseudo_exact(row), lift) for rows in arm for row, lift in zip(rows, lifts)]
    bound = Fraction(max(float(np.linalg.eigvalsh(np.array(f, float))[-1] + lift) for f, lift in pseudo))
    step = abs(bound) * Fraction(1, 2**40) + Fraction(1, 2**60)
    while not all(definiteness(integer_matrix([[(bound - lift if i == j else 0) - f[i][j] for j in range(4)]
                                               for i in range(4)]))[0] != "indefinite" for f, lift in pseudo):
        bound += step
    sets = distinct(arm)
    return {"schema": SCHEMA,
            "claim": {"kind": "payload-envelope", "quantity": "lambda_max_f", "bound": exact(bound)},
            "parameters": [exact_rows(s) for s in sets], "payload": payloads.to_json(), "beta": exact(beta)}


BODY_CLAIMS = {  # inertiaproof.bounds.time.BODY_FUNCTIONS name: (matrix, quantity)
    "lmin_f": ("pseudo_inertia", "lambda_min"), "lmax_f": ("pseudo_inertia", "lambda_max"),
    "lmin_Z": ("spatial_inertia", "lambda_min"), "lmax_Z": ("spatial_inertia", "lambda_max"),
    "smax_fdot": ("pseudo_inertia", "sigma_max"), "smax_Zdot": ("spatial_inertia", "sigma_max"),
}


def body_spectrum_certificate(stack, name, bound, provenance="", directions=None, formation=None):
    """The certificate (kind ``body-spectrum``) of the certified side ``bound`` of the time extreme ``name`` (a key
    of :data:`BODY_CLAIMS`): for every body l and Phi_l in the convex hull of the rows of body l in ``stack`` (V, N,
    10; the vertices of Theta or Thetadot), e.g. lambda_min(f(Phi_l)) >= bound; with ``directions`` (N, 10; a lower
    claim) plus any nonnegative multiple of body l's direction (an unbounded scaling); ``formation`` how the rows
    were formed. None when a row or the bound is not finite: the checker has no claim then."""
    stack = np.asarray(stack, float)
    if not (np.all(np.isfinite(stack)) and np.isfinite(float(bound))):
        return None
    matrix, quantity = BODY_CLAIMS[name]
    sets = distinct(stack)
    return {"schema": SCHEMA,
            "claim": {"kind": "body-spectrum", "matrix": matrix, "quantity": quantity, "bound": exact(bound)},
            "parameters": [exact_rows(s) for s in sets],
            **({} if formation is None else {"formation": formation}),
            **({} if directions is None else {"directions": exact_rows(directions)}),
            "provenance": provenance}


def product_certificate(relation, bound, formula, ingredients, provenance="", declared=None):
    """The certificate (kind ``product``) of "the paper's constant ``formula`` (a name of the checker's closed list,
    :data:`inertiaproof.verify.product.FORMULAS`, which fixes its factor and powers) ``relation`` bound" (">=" or
    "<="), from the ingredient certificates in the formula's order (lower claims for ">=", upper for "<=");
    ``declared`` the formula's r where it has one (a ramp's rate). None when an ingredient has no certificate, the
    bound is not finite, a lower claim's bound is negative or an upper claim's bound is (the checker proves
    neither)."""
    if any(c is None for c in ingredients) or not np.isfinite(float(bound)):
        return None
    if (relation == "<=" and bound < 0) or (relation == ">=" and any(Fraction(c["claim"]["bound"]) < 0
                                                                       for c in ingredients)):
        return None
    return {"schema": SCHEMA,
            "claim": {"kind": "product", "formula": formula, "relation": relation, "bound": exact(bound),
                      **({} if declared is None else {"declared": exact(declared)})},
            "ingredients": list(ingredients), "provenance": provenance}


def sum_certificate(relation, terms):
    """(value, certificate) of "sum_i x_i ``relation`` value" (kind ``sum``) from ``terms``, certificates of upper
    claims (``<=``) or lower ones (``>=``): value is the float nearest the exact sum of their bounds, moved outward
    when rounding went inward. (inf or nan, None) when a term has none."""
    if any(t is None for t in terms):
        return np.inf if relation == "<=" else -np.inf, None
    total = sum(Fraction(t["claim"]["bound"]) for t in terms)
    value = float(total)
    if (Fraction(value) < total) if relation == "<=" else (Fraction(value) > total):
        value = float(np.nextafter(value, np.inf if relation == "<=" else -np.inf))
    return value, {"schema": SCHEMA,
                   "claim": {"kind": "sum", "relation": relation, "bound": exact(value)},
                   "terms": terms}


MOVING_CLAIMS = {  # time_extreme's name or "psi", "psi_dot": the checker's quantity
    "lmin_f": "lambda_min_f", "lmax_f": "lambda_max_f", "lmin_Z": "lambda_min_Z", "lmax_Z": "lambda_max_Z",
    "smax_fdot": "sigma_max_fdot", "smax_Zdot": "sigma_max_Zdot", "psi": "psi", "psi_dot": "psi_dot",
}


def moving_mass_certificate(trajectory, name, bound, provenance, stack):
    """The certificate (kind ``moving-mass``) of "for every t, ``name`` (a key of :data:`MOVING_CLAIMS`) is bounded
    by ``bound``" on a trajectory with moving loads (:class:`inertiaproof.dynamics.trajectory.MovingMass`), the rest
    of Theta(t) (of Thetadot(t) for the rates) in the hull of ``stack`` (V, N, 10; for Psi, which only the moving
    loads have, one set); None when the bound is not finite."""
    if not np.isfinite(float(bound)):
        return None
    quantity = MOVING_CLAIMS[name]

    def path(p):
        if p.shape == "line":
            return {"shape": "line", "start": [exact(x) for x in p.start], "end": [exact(x) for x in p.end]}
        return {"shape": "circle", "center": [exact(x) for x in p.center], "radius": exact(p.radius)}

    loads = [{"body": load.body + 1, "mass": exact(load.mass), "inertia_com": exact_rows(load.inertia_com),
              "path": path(load.path), "profile": {"shape": load.path.profile.shape,
                                                   "duration": exact(load.path.profile.duration),
                                                   "rate": exact(load.path.profile.rate)}}
             for load in trajectory.loads if isinstance(load, MovingMass)]
    sets = distinct(stack)
    return {"schema": SCHEMA,
            "claim": {"kind": "moving-mass", "quantity": quantity, "bound": exact(bound)},
            "parameters": [exact_rows(s) for s in sets], "loads": loads, "provenance": provenance}


def key_step_certificate(choi, lower, upper):
    """The certificate (kind ``key-step``) of the key step of Theorems 2-4: L(F) = Z(f^-1(F)) is a positive map
    (``choi``: its 24x24 Choi matrix, rationals as strings) and lower I6 <= L(I4) <= upper I6."""
    return {"schema": SCHEMA,
            "claim": {"kind": "key-step", "lower": exact(lower), "upper": exact(upper)},
            "choi": [list(row) for row in choi]}


def skew_certificate(chain, quantity, bound, provenance="", witness=None, tree="."):
    """The certificate (kind ``skew-partials``) of "for all q in the chain's search box, sigma_max(Y_p(q)) <= bound
    for every row p of QJ" (``quantity`` "max_sigma") or "(sum_p sigma_max(Y_p(q))^2)^(1/2) <= bound" ("rss_sigma"),
    Y_p = dK_p/dq - (dK_p/dq)^T (DefK, Theorem 5); ``tree`` the partition the prover's branch and bound proved on
    (:func:`partition_tree`; None, written as null, where its boxes were no partition: the checker rejects it). None
    where the checker has no claim for the chain (a coordinate map other than the identity, an unbounded slide) or
    the bound is not finite."""
    written = chain_data(chain)
    if certification_obstacle(chain) is not None or not np.isfinite(float(bound)) or written is None:
        return None
    lo, hi = search_box(chain)
    return {"schema": SCHEMA,
            "claim": {"kind": "skew-partials", "quantity": quantity, "bound": exact(bound)},
            "chain": written,
            "domain": domain_data(chain, written["joints"]),
            "tree": tree,
            **({"witness": [exact(x) for x in np.clip(witness, lo, hi)]} if witness is not None else {}),
            "provenance": provenance}


@dataclass(frozen=True)
class SkewClaim:
    """bound -> the certificate (:func:`skew_certificate`) of a bracket's certified side of Theorem 5's sups
    (``quantity`` "max_sigma" or "rss_sigma"); the bracket's ``proof`` is its partition's tree. Plain data."""

    chain: object
    quantity: str

    def __call__(self, bound, note="", witness=None, proof=None):
        return skew_certificate(self.chain, self.quantity, bound, note, witness, proof)
