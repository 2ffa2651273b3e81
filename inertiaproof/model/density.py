"""Mass densities as JSON-able mixtures, and their moments (MassDistributionToInertialParam).

A density is ``{"components": [c1, c2, ...]}`` and rho is the sum of the
components' densities, each a function R^3 -> R (Lebesgue densities):

- ``{"type": "solid", "shape", "mass", "dims", "quaternion", "position"}``: a
  uniform solid of :mod:`inertiaproof.model.solids`, density mass / volume on it;
- ``{"type": "bernstein_box", "sides", "coefficients", "quaternion", "position"}``:
  on the centred box with these sides, in its own frame y,
  rho(y) = sum_k c_k B_{k1,d1}(t1) B_{k2,d2}(t2) B_{k3,d3}(t3) with t = y / sides + 1/2
  and B_{k,d}(t) = C(d, k) t^k (1 - t)^(d - k); ``coefficients`` is a
  (d1 + 1) x (d2 + 1) x (d3 + 1) nested list.

A component's own frame is turned by R(q) = M(q) / |q|^2 from the quaternion
q = (w, x, y, z) (rational in q, so the rotation is exactly orthogonal for
rational q) and moved to ``position``. Every float is a rational number, so
:func:`moments` with ``exact=True`` computes the moments of the density the
floats describe in rational arithmetic.

Nonnegative masses and Bernstein coefficients make rho >= 0 (the Bernstein
basis is >= 0 on [0, 1]); negative ones describe signed densities, which
:func:`certified_nonnegative` reports.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from inertiaproof.errors import InputError, numbers

from . import solids
from .inertia import inertia_from_sigma, pack

__all__ = [
    "bernstein_axis_moments", "bernstein_values", "bounding_box", "certified_nonnegative", "component_moments",
    "evaluate", "MAX_DEGREE", "moment_matrix", "moments", "parse", "phi", "pseudo_inertia_exact", "rotation",
    "TYPES",
]

TYPES = ("solid", "bernstein_box")
MAX_DEGREE = 8


def rotation(q):
    """R(q) = M(q) / |q|^2 for a quaternion (w, x, y, z), not necessarily of unit length; exact for exact q."""
    w, x, y, z = q
    n = w * w + x * x + y * y + z * z
    return np.array([
        [w * w + x * x - y * y - z * z, 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), w * w - x * x + y * y - z * z, 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), w * w - x * x - y * y + z * z],
    ]) / n


def parse(spec, where="density"):
    """A validated copy of a density spec (plain lists of floats); InputError naming the field otherwise."""
    if not isinstance(spec, dict) or not isinstance(spec.get("components"), list) or not spec["components"]:
        raise InputError(f"{where}: expected {{'components': [...]}} with at least one component")
    out = []
    for i, c in enumerate(spec["components"]):
        at = f"{where}: component {i}"
        if not isinstance(c, dict) or c.get("type") not in TYPES:
            raise InputError(f"{at}: 'type' must be one of {', '.join(TYPES)}")
        q = numbers(c.get("quaternion", [1, 0, 0, 0]), f"{at}: field 'quaternion'", (4,))
        if not q @ q > 0:
            raise InputError(f"{at}: field 'quaternion' is zero")
        entry = {"type": c["type"], "quaternion": q.tolist(),
                 "position": numbers(c.get("position", [0, 0, 0]), f"{at}: field 'position'", (3,)).tolist()}
        if c["type"] == "solid":
            mass = numbers(c.get("mass"), f"{at}: field 'mass'")
            if mass.shape != () or mass == 0:
                raise InputError(f"{at}: field 'mass' must be one nonzero number")
            try:
                dims = solids.validate(c.get("shape"), numbers(c.get("dims"), f"{at}: field 'dims'"))
            except ValueError as exc:
                raise InputError(f"{at}: {exc}") from None
            entry.update(shape=c["shape"], mass=float(mass), dims=dims.tolist())
        else:
            sides = numbers(c.get("sides"), f"{at}: field 'sides'", (3,))
            if not np.all(sides > 0):
                raise InputError(f"{at}: field 'sides' must be > 0, got {sides.tolist()}")
            coef = numbers(c.get("coefficients"), f"{at}: field 'coefficients'")
            if coef.ndim != 3 or max(coef.shape) > MAX_DEGREE + 1 or not np.any(coef != 0):
                raise InputError(f"{at}: field 'coefficients' must be a nonzero 3-D nested list of at most "
                                 f"{MAX_DEGREE + 1} per axis, got shape {coef.shape}")
            entry.update(sides=sides.tolist(), coefficients=coef.tolist())
        out.append(entry)
    return {"components": out}


def certified_nonnegative(spec):
    """True when every mass and Bernstein coefficient is >= 0, which makes rho >= 0 everywhere."""
    return all(
        c["mass"] > 0 if c["type"] == "solid" else bool(np.all(np.asarray(c["coefficients"]) >= 0))
        for c in spec["components"]
    )


def bernstein_axis_moments(side, degree, one):
    """int y^j B_{k,d}(y / L + 1/2) dy over [-L/2, L/2] for j = 0, 1, 2 and k = 0..d (three arrays)."""
    k = np.arange(degree + 1)
    d1, d2, d3 = degree + 1, degree + 2, degree + 3
    mu0 = np.array([one / d1 for _ in k])
    mu1 = np.array([one * (i + 1) / (d1 * d2) for i in k])
    mu2 = np.array([one * (i + 1) * (i + 2) / (d1 * d2 * d3) for i in k])
    return side * mu0, side**2 * (mu1 - mu0 / 2), side**3 * (mu2 - mu1 + mu0 / 4)


def _bernstein_moments(sides, coef, one):
    """(m, h, Sigma) of a Bernstein box in its own frame."""
    axes = [bernstein_axis_moments(s, n - 1, one) for s, n in zip(sides, coef.shape)]
    zeroth = [a[0] for a in axes]

    def contract(vectors):
        return np.einsum("abc,a,b,c->", coef, *vectors)

    m = contract(zeroth)
    h = np.array([contract([axes[i][1] if i == j else zeroth[i] for i in range(3)]) for j in range(3)])
    sigma = np.empty((3, 3), dtype=h.dtype)
    for r in range(3):
        for s in range(r, 3):
            if r == s:
                vectors = [axes[i][2] if i == r else zeroth[i] for i in range(3)]
            else:
                vectors = [axes[i][1] if i in (r, s) else zeroth[i] for i in range(3)]
            sigma[r, s] = sigma[s, r] = contract(vectors)
    return m, h, sigma


def component_moments(c, exact=False):
    """(m, h, Sigma) of one component about the frame origin; Fractions if exact."""
    conv = (lambda a: np.vectorize(Fraction, otypes=[object])(np.asarray(a, dtype=float))) if exact else \
        (lambda a: np.asarray(a, dtype=float))
    one = Fraction(1) if exact else 1.0
    r = rotation(conv(c["quaternion"]))
    p = conv(c["position"])
    if c["type"] == "solid":
        mass = Fraction(c["mass"]) if exact else float(c["mass"])
        return solids.moments(c["shape"], mass, conv(c["dims"]), r, p)
    m, h_own, sigma_own = _bernstein_moments(conv(c["sides"]), conv(c["coefficients"]), one)
    h_turned = r @ h_own
    cross = np.outer(h_turned, p)
    return m, h_turned + m * p, r @ sigma_own @ r.T + cross + cross.T + m * np.outer(p, p)


def moments(spec, exact=False):
    """(m, h, Sigma = int rho x x^T dx) of the density: sums over its components."""
    parts = [component_moments(c, exact) for c in spec["components"]]
    return sum(p[0] for p in parts), sum(p[1] for p in parts), sum(p[2] for p in parts)


def phi(spec):
    """Phi (paper order) of the density, in floats."""
    m, h, sigma = moments(spec)
    return pack(m, h, inertia_from_sigma(sigma))


def moment_matrix(m, h, sigma):
    """f = [[Sigma, h], [h^T, m]] = int rho [x; 1] [x; 1]^T dx (DefTrafoInertialParameters), in the inputs' type."""
    f = np.empty((4, 4), dtype=np.asarray(sigma).dtype)
    f[:3, :3], f[:3, 3], f[3, :3], f[3, 3] = sigma, h, h, m
    return f


def pseudo_inertia_exact(spec):
    """f(Phi) in Fractions, exact for the density the floats describe."""
    return moment_matrix(*moments(spec, exact=True))


def bernstein_values(t, degree):
    """B_{k,d}(t) for k = 0..d, shape (..., d + 1)."""
    k = np.arange(degree + 1)
    binom = np.array([math.comb(degree, i) for i in k], dtype=float)
    return binom * t[..., None] ** k * (1.0 - t[..., None]) ** (degree - k)


def evaluate(spec, x):
    """rho(x) at points x (..., 3)."""
    x = np.asarray(x, dtype=float)
    total = np.zeros(x.shape[:-1])
    for c in spec["components"]:
        y = np.einsum("...i,ij->...j", x - np.asarray(c["position"]), rotation(np.asarray(c["quaternion"])))
        if c["type"] == "solid":
            inside = solids.contains(c["shape"], c["dims"], y)
            total += inside * (c["mass"] / solids.volume(c["shape"], c["dims"]))
            continue
        sides = np.asarray(c["sides"])
        coef = np.asarray(c["coefficients"])
        t = y / sides + 0.5
        inside = np.all((t >= 0) & (t <= 1), axis=-1)
        t = t[inside]
        b = [bernstein_values(t[:, i], coef.shape[i] - 1) for i in range(3)]
        total[inside] += np.einsum("abc,na,nb,nc->n", coef, *b)
    return total


def bounding_box(spec):
    """(lower, upper) corners of an axis-aligned box that contains the carrier.

    Each component's own-frame box (cone: [-r, r]^2 x [0, h]), turned and moved;
    ellipsoids get their exact extents sqrt(sum_j R_ij^2 a_j^2).
    """
    lows, highs = [], []
    for c in spec["components"]:
        r = rotation(np.asarray(c["quaternion"], dtype=float))
        p = np.asarray(c["position"], dtype=float)
        d = np.asarray(c.get("dims", c.get("sides")), dtype=float)
        if c["type"] == "solid" and c["shape"] == "tetrahedron":
            corners = d.reshape(4, 3)
        elif c["type"] == "solid" and c["shape"] in ("ellipsoid", "sphere"):
            extent = np.sqrt((r**2) @ (np.broadcast_to(d, (3,)) ** 2))
            lows.append(p - extent)
            highs.append(p + extent)
            continue
        else:
            half = {"cylinder": lambda: [d[0], d[0], d[1] / 2], "cone": lambda: [d[0], d[0], d[1] / 2]}.get(
                c.get("shape"), lambda: d / 2)()
            centre = np.array([0.0, 0.0, d[1] / 2]) if c.get("shape") == "cone" else np.zeros(3)
            corners = centre + np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
        world = corners @ r.T + p
        lows.append(world.min(axis=0))
        highs.append(world.max(axis=0))
    return np.min(lows, axis=0), np.max(highs, axis=0)
