"""Theorems about every body inside a link's geometry, decided exactly on the numbers as written.

Premise: the link's mass lies inside its geometry G (:mod:`.geometry`: a union of URDF primitives) with a
density of at most ``max_density`` (default 22,600 kg/m^3, osmium's, the densest element). Each hard finding
proves that no such mass distribution has the declared mass m, centre of mass c and inertia I_CoM:

- ``mass-exceeds-densest``: m > rho_max vol(G); vol(G) <= the sum of the primitives' volumes (overlaps count
  twice), so m > rho_max sum_i vol(P_i) suffices.
- ``com-outside-geometry``: c lies outside the convex hull of G, which holds every CoM of a nonnegative mass
  distribution on G (the CoM is an average of points of G). Decided by each primitive's exact membership test
  (inside one: inside the hull) and, for several primitives, by their bounding box in the link frame (outside it:
  outside the hull); anything else is "not decided".
- ``second-moment-below-densest-ball``: tr(I_CoM) = 2 int rho |x - c|^2 dx is smallest, over densities
  0 <= rho <= rho_max of mass m, for the ball of density rho_max centred at c (the bathtub principle, Lieb and
  Loss, Analysis, 2nd ed., Theorem 1.14): tr(I_CoM) >= 6/5 m R^2 with R = (3 m / (4 pi rho_max))^(1/3).
  Cubed: tr^3 * 2000 pi^2 rho_max^2 >= 1944 m^5. It needs no geometry and is decided on every link with mass.
- ``outside-bounding-ellipsoid``: for an ellipsoid E = {x : (x - e)^T A^-1 (x - e) <= 1} holding G,
  tr(Q f(Phi)) = int rho (1 - (x - e)^T A^-1 (x - e)) dx >= 0 with Q = [[-A^-1, A^-1 e], [e^T A^-1,
  1 - e^T A^-1 e]] and f(Phi) the pseudo-inertia (Wensing, Kim and Slotine, "Linear Matrix Inequalities for
  Physically Consistent Inertial Parameter Identification: A Statistical Perspective on the Mass Distribution",
  IEEE RA-L 3(1), 2018, eq. 23). Written out: m >= sum_k (S_kk + m d_k^2) / a_k^2 in E's axes, with S the
  covariance about the CoM (tr(I_CoM)/2 I3 - I_CoM, DefTrafoInertialParameters) and d = c - e. The ellipsoids,
  each the smallest-volume one holding the primitive (unique, John 1948, so it shares the primitive's
  symmetries and is axis-aligned in its frame): a sphere itself; a box of half-extents b_k the ellipsoid
  through its corners, a_k = sqrt(3) b_k; a cylinder of radius r and half-length eta the spheroid with
  a_1 = a_2 = sqrt(3/2) r, a_3 = sqrt(3) eta (minimising a_1^2 a_3 subject to r^2/a_1^2 + eta^2/a_3^2 = 1 gives
  r^2/a_1^2 = 2/3). For several primitives: the corner ellipsoid of their bounding box in the link frame.

Soft findings (notes, not counted in the exit status): the implied density m / sum_i vol(P_i) below
``PLAUSIBLE_DENSITY`` (100 kg/m^3: lighter than any solid engineering material but foams; above 22,600 the
hard finding fires), and principal moments more than ``MOMENT_RATIO`` times off those of the geometry filled
uniformly at the declared mass.

Arithmetic: the file's decimals are the rationals they denote (flint ``fmpq``, exact); where pi, a square root
or the cosine of a written angle enters, an ``arb`` ball (rounded outward: it holds the true value). A sign is
decided when the ball excludes zero, at 64, 256 and then 1024 bits; an exact zero is decided too. A sign not
decided at 1024 bits leaves the finding "not decided" (only an exact tie with a turned frame can).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from flint import arb, ctx, fmpq
from flint.utils.flint_exceptions import DomainError

from inertiaproof.model.exact import written_fraction
from inertiaproof.model.inertia import inertia_com, rotation_rpy
from inertiaproof.model.solids import covariance, solid

from .geometry import _decimal

__all__ = ["DENSEST", "HARD", "link_findings", "MOMENT_RATIO", "PLAUSIBLE_DENSITY", "SOFT"]

DENSEST = 22600  # kg/m^3: osmium (22,590), the densest element, rounded up
PLAUSIBLE_DENSITY = 100  # kg/m^3
MOMENT_RATIO = 10
PRECISIONS = (64, 256, 1024)
HARD = ("mass-exceeds-densest", "com-outside-geometry", "second-moment-below-densest-ball",
        "outside-bounding-ellipsoid")
SOFT = ("implausible-density", "inertia-unlike-geometry")


# -- numbers -------------------------------------------------------------------

def _q(x):
    """An exact rational (fmpq) of a Fraction or int."""
    x = Fraction(x)
    return fmpq(x.numerator, x.denominator)


def _exact(text, value):
    """The rational a decimal as written denotes, else the float the reader holds."""
    found = written_fraction(text) if text is not None else None
    return _q(found if found is not None else Fraction(float(value)))


def _sign(value):
    """The sign (+1, 0, -1) of ``value()``, which builds its number at the working precision; None when the ball
    still holds zero at the last precision."""
    for prec in PRECISIONS:
        with ctx.workprec(prec):
            x = value()
            if isinstance(x, (int, fmpq)):
                return (x > 0) - (x < 0)
            if x > 0:
                return 1
            if x < 0:
                return -1
            if x == 0:
                return 0
    return None


def _root(x):
    """sqrt(x) for x >= 0: exact for a rational square, else a ball (the nonnegative part of a ball's)."""
    if isinstance(x, fmpq):
        try:
            return x.sqrt()
        except DomainError:
            return arb(x).sqrt()
    return x.nonnegative_part().sqrt()


def _sq(x):
    """x * x: flint's ``arb ** 2`` is nan on a ball holding zero."""
    return x * x


def _min(a, b):
    return min(a, b) if isinstance(a, fmpq) and isinstance(b, fmpq) else arb(a).min(arb(b))


def _max(a, b):
    return max(a, b) if isinstance(a, fmpq) and isinstance(b, fmpq) else arb(a).max(arb(b))


IDENTITY = tuple(tuple(fmpq(int(i == j)) for j in range(3)) for i in range(3))


def _rotation(rpy):
    """URDF's R = Rz(yaw) Ry(pitch) Rx(roll) (as :func:`inertiaproof.model.inertia.rotation_rpy`): the exact
    identity when rpy is zero, else balls at the working precision."""
    if not any(rpy):
        return IDENTITY
    (sr, cr), (sp, cp), (sy, cy) = (arb(_q(a)).sin_cos() for a in rpy)
    return ((cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
            (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
            (-sp, cp * sr, cp * cr))


def _transpose(a):
    return tuple(zip(*a))


def _matmul(a, b):
    return tuple(tuple(sum((a[i][k] * b[k][j] for k in range(3)), fmpq(0)) for j in range(3)) for i in range(3))


def _apply(a, v):
    return tuple(sum((a[i][k] * v[k] for k in range(3)), fmpq(0)) for i in range(3))


# -- the primitives ------------------------------------------------------------

def _volume(p):
    """(a, b) with vol = a + b pi, both rational."""
    d = [_q(x) for x in p.dims]
    if p.kind == "box":
        return d[0] * d[1] * d[2], fmpq(0)
    if p.kind == "cylinder":
        return fmpq(0), d[0] * d[0] * d[1]
    return fmpq(0), fmpq(4, 3) * d[0] * _sq(d[0])


def _local(p, point):
    """The point (link frame) in the primitive's frame: R^T (x - xyz)."""
    return _apply(_transpose(_rotation(p.pose.rpy)), [point[k] - _q(p.pose.xyz[k]) for k in range(3)])


def _slacks(p, point):
    """Numbers that are all >= 0 exactly when the point lies in the closed primitive."""
    y = _local(p, point)
    d = [_q(x) for x in p.dims]
    if p.kind == "box":
        return [d[k] / 2 - abs(y[k]) for k in range(3)]
    if p.kind == "cylinder":
        return [_sq(d[0]) - _sq(y[0]) - _sq(y[1]), d[1] / 2 - abs(y[2])]
    return [_sq(d[0]) - _sq(y[0]) - _sq(y[1]) - _sq(y[2])]


def _half_extents(p):
    """Half the primitive's extent along each link axis: box sum_j |R_kj| b_j; cylinder |R_k3| eta + r sqrt(1 -
    R_k3^2); sphere r."""
    r = _rotation(p.pose.rpy)
    d = [_q(x) for x in p.dims]
    if p.kind == "box":
        return [sum((abs(r[k][j]) * d[j] / 2 for j in range(3)), fmpq(0)) for k in range(3)]
    if p.kind == "cylinder":
        return [abs(r[k][2]) * d[1] / 2 + d[0] * _root(1 - _sq(r[k][2])) for k in range(3)]
    return [d[0]] * 3


def _bounding_box(primitives):
    """(lo, hi) of the union's axis-aligned bounding box in the link frame."""
    lo = hi = None
    for p in primitives:
        e, c = _half_extents(p), [_q(x) for x in p.pose.xyz]
        low, high = [c[k] - e[k] for k in range(3)], [c[k] + e[k] for k in range(3)]
        lo = low if lo is None else [_min(a, b) for a, b in zip(lo, low)]
        hi = high if hi is None else [_max(a, b) for a, b in zip(hi, high)]
    return lo, hi


def ellipsoid(primitives):
    """(centre, axes, squared semi-axes) of the ellipsoid used for ``outside-bounding-ellipsoid`` (see the
    module): ``axes`` turns the ellipsoid's frame into the link frame."""
    if len(primitives) == 1:
        p = primitives[0]
        d = [_q(x) for x in p.dims]
        squared = {"box": lambda: [3 * x * x / 4 for x in d], "sphere": lambda: [_sq(d[0])] * 3,
                   "cylinder": lambda: [3 * _sq(d[0]) / 2] * 2 + [3 * _sq(d[1]) / 4]}[p.kind]()
        return [_q(x) for x in p.pose.xyz], _rotation(p.pose.rpy), squared
    lo, hi = _bounding_box(primitives)
    return [(a + b) / 2 for a, b in zip(lo, hi)], IDENTITY, [3 * _sq((b - a) / 2) for a, b in zip(lo, hi)]


# -- the findings --------------------------------------------------------------

class _Body:
    """The declared m, c (link frame), I_CoM (inertial axes) and the inertial axes' rpy, exact."""

    def __init__(self, inertial, pose):
        written = inertial.written or (None,) * 7
        self.mass = _exact(written[0], inertial.mass)
        i = inertial.inertia
        six = [(i[0, 0], 0, 0), (i[1, 1], 1, 1), (i[2, 2], 2, 2), (i[0, 1], 0, 1), (i[1, 2], 1, 2), (i[0, 2], 0, 2)]
        self.inertia = [[fmpq(0)] * 3 for _ in range(3)]
        for text, (value, a, b) in zip(written[1:], six):
            self.inertia[a][b] = self.inertia[b][a] = _exact(text, value)
        self.trace = self.inertia[0][0] + self.inertia[1][1] + self.inertia[2][2]
        self.pose = pose  # None: the inertial origin is not read exactly (urdf.py reports it)
        self.com = None if pose is None else [_q(x) for x in pose.xyz]

    def covariance_in(self, axes):
        """The diagonal of the covariance about the CoM, S = tr(I_CoM)/2 I3 - I_CoM, in the frame ``axes``."""
        sigma = [[(self.trace / 2 if a == b else 0) - self.inertia[a][b] for b in range(3)] for a in range(3)]
        n = _matmul(_transpose(axes), _rotation(self.pose.rpy))
        return [sum((n[k][a] * sigma[a][b] * n[k][b] for a in range(3) for b in range(3)), fmpq(0))
                for k in range(3)]


def _mass_exceeds(body, primitives, rho):
    a, b = fmpq(0), fmpq(0)
    for p in primitives:
        da, db = _volume(p)
        a, b = a + da, b + db
    return _sign(lambda: body.mass - rho * (a + b * arb.pi()) if b else body.mass - rho * a) == 1, a, b


def _com_outside(body, primitives):
    """True (outside the hull), False (inside) or None (not decided)."""
    undecided = False
    for p in primitives:
        signs = [_sign(lambda k=k: _slacks(p, body.com)[k]) for k in range(len(_slacks(p, body.com)))]
        if all(s is not None and s >= 0 for s in signs):
            return False
        undecided |= not any(s == -1 for s in signs)
    if undecided:
        return None
    if len(primitives) == 1:
        return True
    outside = [_sign(lambda k=k: body.com[k] - _bounding_box(primitives)[1][k]) for k in range(3)]
    outside += [_sign(lambda k=k: _bounding_box(primitives)[0][k] - body.com[k]) for k in range(3)]
    return True if 1 in outside else None


def _ball_bound(body, rho):
    """tr^3 2000 pi^2 rho^2 - 1944 m^5 (< 0: the second-moment finding)."""
    return body.trace * _sq(body.trace) * 2000 * _sq(arb.pi()) * _sq(rho) - 1944 * body.mass * _sq(_sq(body.mass))


def _ellipsoid_value(body, primitives):
    """m - sum_k (S_kk + m d_k^2) / a_k^2, i.e. tr(Q f(Phi)) (< 0: the ellipsoid finding)."""
    centre, axes, squared = ellipsoid(primitives)
    d = _apply(_transpose(axes), [body.com[k] - centre[k] for k in range(3)])
    s = body.covariance_in(axes)
    return body.mass - sum(((s[k] + body.mass * _sq(d[k])) / squared[k] for k in range(3)), fmpq(0))


def _uniform(mass, primitives):
    """The geometry filled uniformly at ``mass``: (principal moments about its CoM, the ``<inertial>`` text of a
    single primitive or None). Several primitives are split by volume, as if they did not overlap."""
    volumes = [float(a) + float(b) * np.pi for a, b in map(_volume, primitives)]
    phi = sum(solid(p.kind, mass * v / sum(volumes), [float(x) for x in p.dims],
                    rotation_rpy([float(x) for x in p.pose.rpy]), [float(x) for x in p.pose.xyz])
              for p, v in zip(primitives, volumes))
    moments = np.linalg.eigvalsh(inertia_com(phi)).tolist()
    if len(primitives) != 1:
        return moments, None
    p = primitives[0]
    sigma, _ = covariance(p.kind, Fraction(mass), np.array(p.dims, dtype=object))
    diagonal = [sum(sigma[j, j] for j in range(3)) - sigma[k, k] for k in range(3)]
    ixx, iyy, izz = (f"{float(x):.9g}" for x in diagonal)
    text = (f'<inertial><origin xyz="{" ".join(map(_decimal, p.pose.xyz))}" '
            f'rpy="{" ".join(map(_decimal, p.pose.rpy))}"/><mass value="{mass:.9g}"/>'
            f'<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="0" iyz="0" ixz="0"/></inertial>')
    return moments, text


def link_findings(name, inertial, geometry, *, max_density=DENSEST):
    """The findings on one link as a JSON-ready dict: ``findings`` (rule, hard, message), ``not_decided``
    (rules the arithmetic or the geometry could not decide), ``geometry`` and the ``uniform`` proposal; None for a
    link without positive mass."""
    if inertial is None or not inertial.mass > 0:
        return None
    rho = _q(Fraction(max_density))
    body = _Body(inertial, None if geometry is None else geometry.inertial_pose)
    m = float(body.mass)
    findings, not_decided = [], []

    def found(rule, message, **numbers):
        findings.append({"rule": rule, "hard": rule in HARD, "message": f"link '{name}': {message}",
                         "numbers": numbers})

    ball = _sign(lambda: _ball_bound(body, rho))
    radius = (3 * m / (4 * np.pi * max_density)) ** (1 / 3)
    if ball == -1:
        found("second-moment-below-densest-ball",
              f"tr(I_CoM) = {float(body.trace):.6g} kg m^2 is below 6/5 m R^2 = {1.2 * m * radius**2:.6g} kg m^2, the "
              f"least of any body of mass {m:g} kg and density at most {max_density:g} kg/m^3 (a ball of radius "
              f"R = {radius:.4g} m)", trace=float(body.trace), bound=1.2 * m * radius**2)
    elif ball is None:
        not_decided.append("second-moment-below-densest-ball: the bound is not decided at 1024 bits")
    out = {"geometry": None, "findings": findings, "not_decided": not_decided, "uniform": None}
    if geometry is None or geometry.unread or body.pose is None or getattr(geometry, "meshes", ()):
        if geometry is not None:  # a mesh is decided by .mesh_bodies, which calls this without the geometry
            out["geometry"] = {"source": geometry.source, "primitives": [],
                               "not_read": geometry.unread or ("the <inertial> origin is not read" if body.pose is None
                                                               else "a <mesh>: decided by audit.mesh_bodies")}
        return out
    shapes = geometry.primitives
    where = f"its {geometry.source} " + "; ".join(p.describe() for p in shapes)
    out["geometry"] = {"source": geometry.source, "primitives": [p.describe() for p in shapes], "not_read": None}
    heavy, a, b = _mass_exceeds(body, shapes, rho)
    volume = float(a) + float(b) * np.pi
    if heavy:
        found("mass-exceeds-densest", f"mass {m:g} kg exceeds what the densest material ({max_density:g} kg/m^3) "
              f"fits in {where} (volume {volume:.6g} m^3: at most {max_density * volume:.6g} kg)",
              mass=m, volume=volume, density=m / volume)
    outside = _com_outside(body, shapes)
    com = " ".join(_decimal(x) for x in body.pose.xyz)
    if outside:
        found("com-outside-geometry", f"centre of mass ({com}) lies outside the convex hull of {where}", com=com)
    elif outside is None:
        not_decided.append(f"com-outside-geometry: the centre of mass ({com}) is outside every primitive and "
                           "inside their bounding box, or on a boundary the arithmetic cannot decide")
    value = _sign(lambda: _ellipsoid_value(body, shapes))
    if value == -1:
        _, _, squared = ellipsoid(shapes)
        axes = ", ".join(f"{float(arb(x).sqrt()):.4g}" for x in squared)
        found("outside-bounding-ellipsoid", f"tr(Q f(Phi)) < 0 for the ellipsoid with semi-axes ({axes}) m holding "
              f"{where}: no mass distribution inside it has this inertia (mass {m:g} kg, tr(I_CoM) "
              f"{float(body.trace):.6g} kg m^2, centre ({com}))")
    elif value is None:
        not_decided.append("outside-bounding-ellipsoid: tr(Q f(Phi)) is not decided at 1024 bits")
    if m / volume < PLAUSIBLE_DENSITY:
        found("implausible-density", f"implied density {m / volume:.4g} kg/m^3 (mass {m:g} kg in {where}, volume "
              f"{volume:.6g} m^3) is below {PLAUSIBLE_DENSITY} kg/m^3, lighter than solid parts", density=m / volume)
    moments, text = _uniform(m, shapes)
    declared = np.linalg.eigvalsh(np.array([[float(x) for x in row] for row in body.inertia])).tolist()
    ratio = max(max(x / y, y / x) for x, y in zip(declared, moments)) if min(declared) > 0 else 0.0
    if ratio > MOMENT_RATIO:  # a zero or negative moment is a verdict and a sign already
        found("inertia-unlike-geometry", f"principal moments ({', '.join(f'{x:.4g}' for x in declared)}) kg m^2 are "
              f"up to {ratio:.3g}x off those of {where} filled uniformly at {m:g} kg "
              f"({', '.join(f'{x:.4g}' for x in moments)})", ratio=float(ratio))
    out["uniform"] = {"principal_moments": moments, "text": text,
                      "span": None if geometry.inertial_span is None else geometry.inertial_span.region()}
    return out
