"""Physical consistency of inertial parameters (Definition 1, Theorem 1).

``physical_consistency(phi)`` classifies every row of a batch:

- ``consistent``: f(Phi) > 0, realisable by a nonnegative Lebesgue density;
- ``degenerate``: f(Phi) >= 0 and singular, realisable only by a point, line
  or planar mass (Thm1-boundary);
- ``inconsistent``: no nonnegative mass distribution has these moments;
- ``invalid``: the row holds a non-finite number.

The decision uses the Schur complement (fPosDef_IFF_PosMassPosDefSigmaCoM):
f > 0 iff m > 0 and Sigma_CoM > 0, and the eigenvalues s1 <= s2 <= s3 of
Sigma_CoM are half the slacks of the triangle inequalities of I_CoM
(SigmaCoMPosDef_IFF_StricTriangleCoM). They come from a closed form over
whole columns, on each row scaled exactly by powers of two to unit mass and
unit size (Phi -> (2^-a m, 2^-(a+b) h, 2^-(a+2b) I) turns f into
2^-a D f D with D = diag(2^-b, 2^-b, 2^-b, 1): the same signs at every finite
magnitude). Where |s1| is below the rounding resolution of the inputs, or
the scaled row left the range of floats, the row is decided again exactly in
rational arithmetic: on the numbers as written when they are given
(``written``: the decimal text a file holds, ``0.1`` meaning 1/10), else on
the float values. Where the written numbers and their float64 values fall in
different classes the reason says both: an engine that reads doubles sees
the float64 class.
"""

from __future__ import annotations

import math
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from fractions import Fraction

import mpmath
import numpy as np

from inertiaproof.budget import available_cores

from . import exact
from .inertia import PHI_FIELDS

__all__ = [
    "CHUNK", "Consistency", "CONSISTENT", "decide_exactly", "DEGENERATE", "DEGENERATE_KIND", "EPS", "INCONSISTENT",
    "INVALID", "LABELS", "physical_consistency", "RESOLUTION",
]

CONSISTENT, DEGENERATE, INCONSISTENT, INVALID = 0, 1, 2, 3
LABELS = ("consistent", "degenerate", "inconsistent", "invalid")
DEGENERATE_KIND = {0: "point mass", 1: "line mass", 2: "planar mass"}

# |s1| below RESOLUTION * eps * scale cannot be signed reliably in floats.
RESOLUTION = 64.0
CHUNK = 50_000  # rows from which a batch is split over threads
EPS = np.finfo(float).eps


def _power_of_two_scale(columns):
    """Per row, the exponent k with 2^(k-1) <= max |entry| < 2^k (0 for a zero row): dividing by 2^k is exact."""
    return np.frexp(np.max(np.abs(columns), axis=0))[1]


def _sym3_eigenvalues(a, b, c, d, e, f):
    """Ascending eigenvalues of [[a, d, f], [d, b, e], [f, e, c]], column-wise.

    Trigonometric closed form on the entries scaled by a power of two to at
    most 1 (squares neither overflow nor underflow); it loses half the digits
    where two eigenvalues nearly coincide (|r| -> 1), so those rows are
    recomputed with LAPACK.
    """
    k = _power_of_two_scale(np.stack([a, b, c, d, e, f]))
    a, b, c, d, e, f = (np.ldexp(x, -k) for x in (a, b, c, d, e, f))
    q = (a + b + c) / 3.0
    p1 = d * d + e * e + f * f
    p = np.sqrt(((a - q) ** 2 + (b - q) ** 2 + (c - q) ** 2 + 2.0 * p1) / 6.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ip = np.where(p > 0, 1.0 / p, 0.0)
    ba, bb, bc, bd, be, bf = (a - q) * ip, (b - q) * ip, (c - q) * ip, d * ip, e * ip, f * ip
    r = np.clip(0.5 * (ba * (bb * bc - be * be) - bd * (bd * bc - be * bf) + bf * (bd * be - bb * bf)), -1.0, 1.0)
    phi = np.arccos(r) / 3.0
    e_max = q + 2.0 * p * np.cos(phi)
    e_min = q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0)
    eig = np.stack([e_min, 3.0 * q - e_max - e_min, e_max], -1)
    close = np.flatnonzero(np.abs(r) > 1.0 - 1e-2)
    if close.size:
        rows = np.stack([a, d, f, d, b, e, f, e, c], -1)[close].reshape(-1, 3, 3)
        eig[close] = np.linalg.eigvalsh(rows)
    return np.ldexp(eig, k[:, None])


def _pseudo_inertia_lambda_min(m, h, s):
    """lambda_min of f = [[Sigma, h], [h^T, m]] from columns, and ||f||_F.

    Laguerre's method on the characteristic polynomial, started at the
    Gershgorin lower bound, converges monotonically and cubically to the
    smallest root (the polynomial is real-rooted). The root is kept where an
    a-posteriori bound shows it accurate: every coefficient c_k is a sum of
    products of k entries, so its rounding error is below 64 eps e_k(r), e_k
    the elementary symmetric polynomials of the absolute row sums r of
    D f D^-1 for any positive diagonal D (a permanent bound; the products
    along permutations do not change under D); with the residual |p(x)| this bounds |dp|, and a root of
    the exact polynomial lies within about |dp| / |p'(x)| of x where
    |dp| |p''(x)| <= p'(x)^2 / 10 (a Newton step, no second root nearby). Rows whose bound exceeds max(1e-6 |x|, 16 eps ||f||)
    or that did not converge are recomputed with LAPACK's eigvalsh.
    """
    h1, h2, h3 = h
    s11, s22, s33, s12, s23, s13 = s
    m2 = lambda a, b, c: a * b - c * c  # noqa: E731  2x2 minor
    c1 = s11 + s22 + s33 + m
    c2 = m2(s11, s22, s12) + m2(s11, s33, s13) + m2(s22, s33, s23) + m * (s11 + s22 + s33) - (h1 * h1 + h2 * h2 + h3 * h3)
    adj = (  # adjugate of Sigma: diagonal, then (1,2), (2,3), (1,3)
        m2(s22, s33, s23), m2(s11, s33, s13), m2(s11, s22, s12),
        s13 * s23 - s12 * s33, s12 * s13 - s11 * s23, s12 * s23 - s13 * s22,
    )
    det_s = s11 * adj[0] + s12 * adj[3] + s13 * adj[5]
    bordered = lambda saa, sbb, sab, ha, hb: m * m2(saa, sbb, sab) - (sbb * ha * ha - 2 * sab * ha * hb + saa * hb * hb)  # noqa: E731
    c3 = det_s + bordered(s11, s22, s12, h1, h2) + bordered(s11, s33, s13, h1, h3) + bordered(s22, s33, s23, h2, h3)
    c4 = m * det_s - (
        adj[0] * h1 * h1 + adj[1] * h2 * h2 + adj[2] * h3 * h3 + 2 * (adj[3] * h1 * h2 + adj[4] * h2 * h3 + adj[5] * h1 * h3)
    )
    norm = np.sqrt(s11**2 + s22**2 + s33**2 + m**2 + 2 * (s12**2 + s23**2 + s13**2 + h1**2 + h2**2 + h3**2))
    x = np.minimum.reduce([
        s11 - np.abs(s12) - np.abs(s13) - np.abs(h1),
        s22 - np.abs(s12) - np.abs(s23) - np.abs(h2),
        s33 - np.abs(s13) - np.abs(s23) - np.abs(h3),
        m - np.abs(h1) - np.abs(h2) - np.abs(h3),
    ])
    rows = slice(None)
    for sweep in range(20):
        xa, a1, a2, a3, a4 = x[rows], c1[rows], c2[rows], c3[rows], c4[rows]
        p = (((xa - a1) * xa + a2) * xa - a3) * xa + a4
        d1 = ((4 * xa - 3 * a1) * xa + 2 * a2) * xa - a3
        d2 = (12 * xa - 6 * a1) * xa + 2 * a2
        with np.errstate(divide="ignore", invalid="ignore"):
            g = d1 / p
            root = np.sqrt(np.maximum(3.0 * (4.0 * (g * g - d2 / p) - g * g), 0.0))
            den = np.where(g >= 0, g + root, g - root)
            step = np.where((p != 0) & (den != 0), 4.0 / den, 0.0)
        x[rows] = xa - step
        moving = np.abs(step) > 1e-12 * norm[rows]
        if not moving.any():
            rows = np.arange(0)
            break
        if sweep >= 3:  # the few slow rows go on alone
            rows = (np.arange(x.size) if isinstance(rows, slice) else rows)[moving]
    diag = (np.abs(s11) + np.abs(s22) + np.abs(s33)) / 3
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.sqrt(np.abs(m) / diag)
    t = np.where(np.isfinite(t) & (t > 0), t, 1.0)  # D = diag(1, 1, 1, t): D f D^-1 balances Sigma against m
    r1 = np.abs(s11) + np.abs(s12) + np.abs(s13) + np.abs(h1) / t
    r2 = np.abs(s12) + np.abs(s22) + np.abs(s23) + np.abs(h2) / t
    r3 = np.abs(s13) + np.abs(s23) + np.abs(s33) + np.abs(h3) / t
    r4 = t * (np.abs(h1) + np.abs(h2) + np.abs(h3)) + np.abs(m)
    e1, e2 = r1 + r2 + r3 + r4, r1 * (r2 + r3 + r4) + r2 * (r3 + r4) + r3 * r4
    e3, e4 = r1 * r2 * (r3 + r4) + (r1 + r2) * r3 * r4, r1 * r2 * r3 * r4
    ax = np.abs(x)
    p_error = 64 * EPS * ((((ax + e1) * ax + e2) * ax + e3) * ax + e4)
    p_error += np.abs((((x - c1) * x + c2) * x - c3) * x + c4)
    d1 = ((4 * x - 3 * c1) * x + 2 * c2) * x - c3
    d2 = (12 * x - 6 * c1) * x + 2 * c2
    with np.errstate(divide="ignore", invalid="ignore"):
        accurate = (p_error <= np.maximum(1e-6 * ax, 16 * EPS * norm) * np.abs(d1)) & (p_error * np.abs(d2) <= 0.1 * d1 * d1)
    bad = ~accurate
    bad[rows] = True
    idx = np.flatnonzero(bad)
    if idx.size:
        f = np.zeros((idx.size, 4, 4))
        f[:, 0, 0], f[:, 1, 1], f[:, 2, 2], f[:, 3, 3] = s11[idx], s22[idx], s33[idx], m[idx]
        f[:, 0, 1] = f[:, 1, 0] = s12[idx]
        f[:, 1, 2] = f[:, 2, 1] = s23[idx]
        f[:, 0, 2] = f[:, 2, 0] = s13[idx]
        f[:, 0, 3] = f[:, 3, 0] = h1[idx]
        f[:, 1, 3] = f[:, 3, 1] = h2[idx]
        f[:, 2, 3] = f[:, 3, 2] = h3[idx]
        x[idx] = np.linalg.eigvalsh(f)[:, 0]
    return x, norm


@dataclass(frozen=True)
class Consistency:
    """Verdicts and margins for a batch of rows (all arrays share the batch shape)."""

    verdict: np.ndarray  # int codes, see LABELS; on the numbers as written where they were given
    mass: np.ndarray
    sigma_com_eigenvalues: np.ndarray  # (..., 3) ascending; half the triangle slacks
    triangle_slack: np.ndarray  # s1 / tr(Sigma_CoM) = 2 s1 / tr(I_CoM); > 0 iff strict triangle inequalities
    lambda_min_rel: np.ndarray  # lambda_min(f) / ||f||_F
    decided_exactly: np.ndarray  # bool: the float margin was below resolution (or out of range)
    degenerate_rank: np.ndarray  # rank of Sigma_CoM where degenerate, else -1
    invalid_field: np.ndarray  # index into PHI_FIELDS of the first non-finite entry, else -1
    float_verdict: np.ndarray = None  # int codes of the float64 values (differs from verdict only as written)
    float64_note: np.ndarray = None  # object: where the float64 class differs, what it is, else None

    @property
    def labels(self):
        return np.asarray(LABELS, dtype=object)[self.verdict]

    def reason(self, i):
        """A one-line reason for row ``i`` (a flat index)."""
        v = self.verdict.flat[i]
        note = None if self.float64_note is None else self.float64_note.flat[i]
        if v == INVALID:
            return f"non-finite value in field {PHI_FIELDS[self.invalid_field.flat[i]]}"
        exact = " (margin below float resolution: decided exactly on the given values)" \
            if self.decided_exactly.flat[i] else ""
        s = self.sigma_com_eigenvalues.reshape(-1, 3)[i]
        why = _why(v, self.mass.flat[i], s, self.degenerate_rank.flat[i], self.triangle_slack.flat[i],
                   self.lambda_min_rel.flat[i])
        if note is None:
            return why + exact
        return (f"as written: {LABELS[v]}: {why} (decided exactly on the decimals); as float64: {note}, which "
                f"engines that read doubles will see")

    def rows(self):
        """One dict per row, for tables and JSON."""
        for i in range(self.verdict.size):
            row = {
                "verdict": LABELS[self.verdict.flat[i]],
                "reason": self.reason(i),
                "triangle_slack_rel": _finite_or_none(self.triangle_slack.flat[i]),
                "lambda_min_rel": _finite_or_none(self.lambda_min_rel.flat[i]),
                "decided_exactly": bool(self.decided_exactly.flat[i]),
            }
            if self.float_verdict is not None and self.float_verdict.flat[i] != self.verdict.flat[i]:
                row["float64_verdict"] = LABELS[self.float_verdict.flat[i]]
            yield row


def _why(v, m, s, rank, slack, lam):
    """The reason of a verdict from the mass, the eigenvalues s of Sigma_CoM and the margins."""
    if v == INCONSISTENT and not m > 0:
        return f"mass <= 0 (m = {m:.6g})"
    lam_text = f"lambda_min(f)/||f||_F = {lam:.3e}" if np.isfinite(lam) else "lambda_min(f) not computed"
    if v == CONSISTENT:
        return f"f > 0: strict triangle inequalities of I_CoM with slack {slack:.3e} of tr(I_CoM); {lam_text}"
    if v == DEGENERATE:
        return (f"f >= 0 and singular: only a {DEGENERATE_KIND[rank]} realises it (a triangle inequality of I_CoM "
                f"holds with equality); {lam_text}")
    tr_icom = 2.0 * s.sum()
    j = tr_icom / 2.0 - s  # principal moments of I_CoM, descending with s ascending
    excess = -2.0 * s[0]
    amount = f"by {excess:.6g} ({-slack:.3e} of tr(I_CoM))" if tr_icom > 0 else \
        f"by {excess:.6g} (tr(I_CoM) = {tr_icom:.3g} <= 0)"
    return (f"triangle inequality of I_CoM fails: largest principal moment {j[0]:.6g} exceeds the sum of the "
            f"others {j[1] + j[2]:.6g} {amount}; {lam_text}")


def _finite_or_none(x):
    return float(x) if np.isfinite(x) else None


def decide_exactly(phi_row):
    """(verdict code, rank of Sigma_CoM or -1) of one row, exactly: entries are floats (their exact values) or
    Fractions (a decimal as written, see exact.written_fraction).

    With D the common denominator, M = D m, H = D h, K = D I are integers and
    2 D^2 (m Sigma - h h^T) = M (tr(K) I3 - 2K) - 2 H H^T, whose definiteness
    is that of Sigma_CoM when m > 0.
    """
    ratios = [Fraction(x).as_integer_ratio() for x in phi_row]
    if ratios[0][0] <= 0:
        return INCONSISTENT, -1
    den = math.lcm(*(d for _, d in ratios))
    mass, h1, h2, h3, i11, i22, i33, i12, i23, i13 = (n * (den // d) for n, d in ratios)
    k = [[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]]
    h = (h1, h2, h3)
    tr = i11 + i22 + i33
    a = [[mass * ((tr if i == j else 0) - 2 * k[i][j]) - 2 * h[i] * h[j] for j in range(3)] for i in range(3)]
    kind, rank = exact.definiteness(a)
    if kind == "pd":
        return CONSISTENT, -1
    if kind == "psd":
        return DEGENERATE, rank
    return INCONSISTENT, -1


def physical_consistency(phi, *, margins=True, written=None):
    """Classify inertial parameters ``phi`` of shape (..., 10); see the module docstring.

    ``written`` (optional, shape (..., 10), entries str or None): the numbers as a file writes them; where given,
    a row whose float decision is not certain is decided exactly on them. ``margins=False`` skips
    lambda_min(f)/||f||_F (the one margin that needs an iterative solve per row); the verdict does not depend on
    it. Large batches are split over the machine's cores (NumPy releases the GIL in its loops).
    """
    phi = np.asarray(phi, dtype=float)
    if phi.shape[-1:] != (10,):
        raise ValueError(f"inertial parameters need 10 entries per row, got shape {phi.shape}")
    shape = phi.shape[:-1]
    flat = phi.reshape(-1, 10)
    text = None
    if written is not None:
        text = np.asarray(written, dtype=object).reshape(-1, 10)
        if text.shape != flat.shape:
            raise ValueError(f"written numbers need the shape of phi {phi.shape}, got {np.shape(written)}")
    workers = min(available_cores(), 8)
    if workers > 1 and len(flat) >= CHUNK:
        parts = np.array_split(np.arange(len(flat)), workers)
        with ThreadPoolExecutor(workers) as pool:
            parts = list(pool.map(lambda rows: _classify(flat[rows], margins, None if text is None else text[rows]),
                                  parts))
    else:
        parts = [_classify(flat, margins, text)]
    return Consistency(*(np.concatenate(arrays).reshape(shape + arrays[0].shape[1:]) for arrays in zip(*parts)))


def _unit_exponents(cols, positive):
    """Per row (a, b) with Phi -> (2^-a m, 2^-(a+b) h, 2^-(a+2b) I) of unit mass and unit size (every scaled
    entry and h_i^2 / m at most about 1); rows without positive mass get b = 0 and a from their largest entry."""
    m, h, inertia = cols[0], np.abs(cols[1:4]).max(axis=0), np.abs(cols[4:]).max(axis=0)
    a = np.where(positive, np.frexp(m)[1], np.frexp(np.abs(cols).max(axis=0))[1])
    e_h, e_i = np.frexp(h)[1].astype(float), np.frexp(inertia)[1].astype(float)
    size = np.maximum(np.where(inertia > 0, e_i - a, -np.inf), np.where(h > 0, 2 * (e_h - a), -np.inf))
    b = np.where(positive & np.isfinite(size), np.ceil(np.where(np.isfinite(size), size, 0) / 2), 0).astype(int)
    return a, b


def _classify(flat, margins, written):
    """The fields of :class:`Consistency` for rows (K, 10), in field order."""
    finite = np.isfinite(flat)
    invalid = ~finite.all(axis=1)
    invalid_field = np.where(invalid, np.argmin(finite, axis=1), -1)
    cols = np.where(finite, flat, 0.0).T.copy()
    mass = cols[0].copy()
    positive = (mass > 0) & ~invalid
    a, b = _unit_exponents(cols, positive)
    m = np.ldexp(cols[0], -a)
    h1, h2, h3 = np.ldexp(cols[1:4], -(a + b))
    i11, i22, i33, i12, i23, i13 = np.ldexp(cols[4:], -(a + 2 * b))

    half_tr = 0.5 * (i11 + i22 + i33)
    inv_m = np.where(positive, 1.0 / np.where(positive, m, 1.0), 0.0)
    s11, s22, s33 = half_tr - i11 - h1 * h1 * inv_m, half_tr - i22 - h2 * h2 * inv_m, half_tr - i33 - h3 * h3 * inv_m
    s12, s23, s13 = -i12 - h1 * h2 * inv_m, -i23 - h2 * h3 * inv_m, -i13 - h1 * h3 * inv_m
    with np.errstate(all="ignore"):
        eig = _sym3_eigenvalues(s11, s22, s33, s12, s23, s13)
        trace = eig.sum(axis=1)
        slack = np.where(positive, eig[:, 0] / trace, np.nan)
    scale = (
        np.abs(half_tr - i11) + np.abs(half_tr - i22) + np.abs(half_tr - i33)
        + 2.0 * (np.abs(i12) + np.abs(i23) + np.abs(i13))
        + (h1 * h1 + h2 * h2 + h3 * h3) * inv_m
    )
    unresolved = positive & ~(np.abs(eig[:, 0]) > RESOLUTION * EPS * scale)  # NaN (out of range) included
    verdict = np.where(positive & (eig[:, 0] > 0), CONSISTENT, INCONSISTENT).astype(np.int8)
    verdict[invalid] = INVALID
    rank = np.full(verdict.shape, -1, dtype=np.int8)
    with np.errstate(over="ignore"):
        eig = np.ldexp(eig, (a + 2 * b)[:, None])

    if margins:
        k = np.frexp(np.abs(cols).max(axis=0))[1]  # f(2^-k Phi) = 2^-k f(Phi): the relative margin unchanged
        um, uh1, uh2, uh3, u11, u22, u33, u12, u23, u13 = np.ldexp(cols, -k)
        uhalf = 0.5 * (u11 + u22 + u33)
        with np.errstate(all="ignore"):
            lo, norm = _pseudo_inertia_lambda_min(um, (uh1, uh2, uh3), (uhalf - u11, uhalf - u22, uhalf - u33,
                                                                          -u12, -u23, -u13))
            lam = np.where(norm > 0, lo / norm, 0.0)
    else:
        lam = np.full(verdict.shape, np.nan)
    lam[invalid] = np.nan
    slack[invalid] = np.nan
    float_verdict = verdict.copy()
    notes = np.full(verdict.shape, None, dtype=object)

    # the written decimals are read only where they can matter: unresolved rows and those _float_may_differ names
    maybe = np.zeros(len(flat), bool) if written is None else unresolved | (verdict == INVALID) | ~(flat[:, 0] > 0)
    given = {i: _fractions(written[i]) for i in np.flatnonzero(maybe)}
    redo = unresolved.copy()
    for i, q in given.items():
        redo[i] |= q is not None and _float_may_differ(q, flat[i], verdict[i])
    if margins:  # a margin too small for its float to carry the verdict's sign (m = 1e-308, I = 1e308)
        expected = np.where(verdict == CONSISTENT, 1.0, np.where(positive, -1.0, np.nan))
        for i in np.flatnonzero(~redo & (np.sign(lam) != expected) & np.isfinite(expected)):
            lam[i] = _exact_margins([Fraction(x) for x in flat[i]], verdict[i], -1, True)[2]
    for i in np.flatnonzero(redo):
        decision = _ExactRow(flat[i], given.get(i), margins)
        verdict[i], rank[i], float_verdict[i] = decision.verdict, decision.rank, decision.float_verdict
        eig[i], slack[i], lam[i] = decision.eigenvalues, decision.slack, decision.lambda_min_rel
        notes[i] = decision.float64_note()
        invalid_field[i] = -1 if verdict[i] != INVALID else invalid_field[i]
    return (verdict, mass, eig, slack, lam, redo, rank, invalid_field, float_verdict, notes)


def _fractions(row):
    """The row as written: a tuple of Fractions (None for an entry with no usable text), or None if nothing is."""
    values = tuple(exact.written_fraction(x) for x in row)
    return None if all(v is None for v in values) else values


def _float_may_differ(written, floats, float_verdict):
    """Whether a row resolved in floats may still be in another class as written: its float values left the range
    (overflow to inf, or a mass that underflowed to 0)."""
    return float_verdict == INVALID or (floats[0] <= 0 and written[0] is not None and written[0] > 0)


class _ExactRow:
    """One row decided exactly, with its margins computed at the precision its verdict needs."""

    def __init__(self, floats, written, margins):
        as_float = [Fraction(x) for x in floats] if np.isfinite(floats).all() else None
        if as_float is None:
            self.float_verdict, self.float_rank = INVALID, -1
        else:
            self.float_verdict, self.float_rank = decide_exactly(as_float)
        self.float_row = as_float
        self.row = as_float if written is None else [w if w is not None else Fraction(x) if np.isfinite(x) else None
                                                     for w, x in zip(written, floats)]
        if self.row is None or any(x is None for x in self.row):
            self.row, self.verdict, self.rank = None, INVALID, -1
        elif written is None:
            self.verdict, self.rank = self.float_verdict, self.float_rank
        else:
            self.verdict, self.rank = decide_exactly(self.row)
        self.eigenvalues, self.slack, self.lambda_min_rel = _exact_margins(self.row, self.verdict, self.rank, margins)

    def float64_note(self):
        if self.float_verdict == self.verdict:
            return None
        if self.float_verdict == INVALID:
            return "a number overflows to inf (invalid)"
        if self.float_verdict == DEGENERATE:
            return f"degenerate, a {DEGENERATE_KIND[self.float_rank]}"
        if self.float_verdict == CONSISTENT:
            return "consistent (strictly, by rounding)"
        if not self.float_row[0] > 0:
            return "inconsistent: the mass rounds to 0"
        slack = _exact_margins(self.float_row, INCONSISTENT, -1, False)[1]
        return f"inconsistent by {-slack:.2g} of tr(I_CoM)"


def _exact_margins(row, verdict, rank, margins, first_bits=64, last_bits=8192):
    """(eigenvalues of Sigma_CoM, s1 / tr, lambda_min(f)/||f||_F) of an exact row, as floats whose signs agree with
    its exact verdict: computed with mpmath (a context per thread) at growing precision until they do."""
    if row is None:
        return np.full(3, np.nan), np.nan, np.nan
    m, h, inertia = row[0], row[1:4], row[4:]
    i11, i22, i33, i12, i23, i13 = inertia
    half = (i11 + i22 + i33) / 2
    sigma = [[half - i11, -i12, -i13], [-i12, half - i22, -i23], [-i13, -i23, half - i33]]
    s_com = [[sigma[r][c] - h[r] * h[c] / m for c in range(3)] for r in range(3)] if m > 0 else None
    f = [sigma[r] + [h[r]] for r in range(3)] + [list(h) + [m]]
    if not hasattr(_THREAD, "mp"):
        _THREAD.mp = mpmath.MPContext()
    mp = _THREAD.mp
    mp.prec = first_bits
    while True:
        lam = None
        if margins and any(x != 0 for row_f in f for x in row_f):
            lam = min(mp.eigsy(_mp(mp, f), eigvals_only=True)) / mp.mnorm(_mp(mp, f), "f")
        elif margins:
            lam = mp.mpf(0)
        if s_com is None:  # no mass: the verdict needs no eigenvalue of Sigma_CoM
            return np.full(3, np.nan), np.nan, np.nan if lam is None else _signed_float(lam, mp)
        s = sorted(mp.eigsy(_mp(mp, s_com), eigvals_only=True))
        if verdict == DEGENERATE:
            s[: 3 - rank] = [mp.mpf(0)] * (3 - rank)
            lam = mp.mpf(0) if margins else None
        sign = 1 if verdict == CONSISTENT else -1 if verdict == INCONSISTENT else 0
        agree = sign == 0 or (mp.sign(s[0]) == sign and (lam is None or mp.sign(lam) == sign))
        if agree or mp.prec >= last_bits:
            slack = s[0] / sum(s) if sum(s) != 0 else mp.mpf(0)
            return (np.array([float(x) for x in s]), _signed_float(slack, mp),
                    np.nan if lam is None else _signed_float(lam, mp))
        mp.prec *= 4


_THREAD = threading.local()  # each thread its own mpmath context: the precision is a context's state


def _mp(mp, rows):
    return mp.matrix([[mp.mpf(x.numerator) / x.denominator for x in row] for row in rows])


def _signed_float(x, mp):
    """float(x), but a nonzero x too small for a float keeps its sign as the smallest subnormal."""
    value = float(x)
    return value if value != 0 or x == 0 else math.copysign(5e-324, float(mp.sign(x)))
