"""Theorems about every body inside a link's geometry that holds meshes, each with a stated rounding bound.

The premise is that of :mod:`.bodies_inside`: the link's mass lies inside its geometry G (its meshes, read by
:mod:`.meshes`, each scaled by its ``scale`` and placed by its ``<origin>``, and any URDF primitives beside them)
with a density of at most ``max_density``. A link whose geometry holds no mesh is :mod:`.bodies_inside`'s.

The cloud: every mesh vertex placed in the link frame in float64, p = R (s . v) + t, with a per-coordinate bound
E = 2^-45 max(1, |rpy|_max) (sum_j |R_kj s_j v_j| + |t_k|) on its error against the exact placement (the written
scale, xyz and rpy: s, t rounded once, R's entries from libm's sin and cos, products of three and sums of three:
within 32 u max(1, |rpy|) of those terms, u = 2^-53); a primitive contributes the corners of its bounding box in its
own frame (a cylinder's [-r, r]^2 x [-eta, eta], a sphere's cube), placed the same way. hull(G) lies in the convex
hull of the true cloud: every test below holds for every point within E of each float point.

- ``mass-exceeds-densest``: m > rho_max V for a certified upper bound V of vol(G): when every mesh is fit (closed,
  consistently wound, positive signed volume: :class:`.meshes.MeshSolid`) the sum of |s_x s_y s_z| (V_mesh +
  its rounding bound) and the primitives' exact volumes; always also the smaller of two enclosures of the whole
  cloud, its axis-aligned box (outward-rounded corners, exact product) and the enclosing ellipsoid below
  (4/3 pi rho^(3/2) / |det L|, in balls): a mesh that is not watertight bounds no solid, only its hull does.
- ``com-outside-geometry``: n . c > max_p n . p for a direction n (a coordinate axis, or the facet most violated
  by c of Qhull's hull of the hint vertices, :attr:`.meshes.MeshSolid.hull`), with the maximum over every cloud point rounded up (2^-50 sum |n_k p_k| + E . |n|)
  and n . c exact (n, a float, and c, the written decimals, as rationals): c is then outside hull(G).
- ``second-moment-below-densest-ball``: needs no geometry (:mod:`.bodies_inside`).
- ``outside-bounding-ellipsoid``: an ellipsoid {x : |L (x - e)|^2 <= rho} holding the cloud: Khachiyan's
  minimum-volume enclosing ellipsoid of the hint vertices' hull (at most ``KHACHIYAN_ROUNDS`` rounds, stopping at
  a step below ``KHACHIYAN_TOLERANCE``), then rho an upper bound of max_p |L (p - e)|^2 over every cloud point
  (each |L (p - e)|_k rounded up by 2^-50 (|L| (|p| + |e|))_k plus (|L| E)_k; the sum of squares by 2^-48
  relative), so the true cloud is inside, checked. tr(Q f(Phi)) = m rho - m (c - e)^T M (c - e) - tr(M Sigma) with
  M = L^T L, Sigma = R_in S R_in^T the covariance about the CoM in link axes, decided exactly (L and e as
  rationals, rpy of the inertial frame in balls); the axis-aligned box's corner ellipsoid is tried as well. A
  negative value for either proves that no mass distribution inside G has this inertia.

Soft findings: the implied density m / vol below ``PLAUSIBLE_DENSITY`` (vol: the fit meshes' volumes, else the float
volume of the cloud's hull), and, when every mesh is fit, principal moments more than ``MOMENT_RATIO`` times off
those of G filled uniformly at the declared mass (trimesh's mass properties; parts split by volume as if they did not
overlap), whose ``<inertial>`` (CoM of G, link axes) is the repair proposal.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from flint import arb, fmpq

from inertiaproof.model.inertia import rotation_rpy
from inertiaproof.model.solids import covariance

from .bodies_inside import (
    DENSEST,
    HARD,
    MOMENT_RATIO,
    PLAUSIBLE_DENSITY,
    _Body,
    _matmul,
    _q,
    _rotation,
    _sign,
    _transpose,
    _volume,
)
from .bodies_inside import link_findings as primitive_findings
from .geometry import _decimal
from .mesh_files import MeshUnread, resolve
from .meshes import read_mesh

__all__ = ["KHACHIYAN_ROUNDS", "KHACHIYAN_TOLERANCE", "link_findings", "mvee"]

KHACHIYAN_ROUNDS = 100
KHACHIYAN_TOLERANCE = 1e-3
PLACEMENT = 2.0**-45  # relative bound of a placed vertex coordinate (see the module)
ROUND = 2.0**-50
TINY = 1e-300


def _up(x):
    return x + np.abs(x) * ROUND + TINY


def _down(x):
    return x - np.abs(x) * ROUND - TINY


def _exact(x):
    """The float ``x`` as the rational it is."""
    return fmpq(*float(x).as_integer_ratio())


# -- the cloud -----------------------------------------------------------------

def _placed(points, scale, pose):
    """(P, E): ``points`` scaled, turned and moved into the link frame in float64, and the bound E (see the
    module); E is zero where nothing is applied to vertices read exactly."""
    s = np.array([float(x) for x in scale])
    t = np.array([float(x) for x in pose.xyz])
    rpy = [float(x) for x in pose.rpy]
    if all(x == 1 for x in scale) and not any(pose.xyz) and not any(pose.rpy):
        return points, np.zeros_like(points)
    r = rotation_rpy(rpy)
    sv = points * s
    p = sv @ r.T + t
    e = PLACEMENT * max(1.0, max(abs(x) for x in rpy)) * (np.abs(sv) @ np.abs(r).T + np.abs(t)) + TINY
    return p, e


def _corners(p):
    """The corners of a primitive's bounding box in its own frame (float64; their rounding is inside E)."""
    d = [float(x) for x in p.dims]
    half = {"box": [x / 2 for x in d], "cylinder": [d[0], d[0], d[1] / 2], "sphere": [d[0]] * 3}[p.kind]
    signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float)
    return signs * np.array(half)


class _Cloud:
    """Every placed point with its bound, and a few of them that span its hull (Qhull's, as hints)."""

    def __init__(self, parts):
        self.points = np.concatenate([p for p, _, _ in parts])
        self.error = np.concatenate([e for _, e, _ in parts])
        self.hints = np.concatenate([h for _, _, h in parts])
        self.hull = None
        from scipy.spatial import ConvexHull, QhullError

        try:
            self.hull = ConvexHull(self.hints)
        except (QhullError, ValueError):
            self.hull = None

    def box(self):
        """(lo, hi) floats, outward-rounded: every true point lies in [lo, hi]."""
        return _down((self.points - self.error).min(axis=0)), _up((self.points + self.error).max(axis=0))

    def support(self, n):
        """An upper bound of max over the true points of n . p (float)."""
        n = np.asarray(n, float)
        value = self.points @ n + ROUND * (np.abs(self.points) @ np.abs(n)) + self.error @ np.abs(n)
        return float(_up(value.max()))


def mvee(points, rounds=KHACHIYAN_ROUNDS, tolerance=KHACHIYAN_TOLERANCE):
    """Khachiyan's minimum-volume enclosing ellipsoid of ``points`` (n, 3): (centre e, A) with (x - e)^T A (x - e)
    <= 1 approximately (not checked here: the caller certifies what it uses); None when the points are flat.

    Each round moves weight to the point farthest out in the current ellipsoid's metric, m_i = q_i^T X^-1 q_i
    (q_i = (x_i, 1), X = sum_i u_i q_i q_i^T); X^-1 and m follow the rank-one step by Sherman and Morrison, and
    are recomputed from u every 50 rounds."""
    mean = points.mean(axis=0)
    spread = max(float(np.abs(points - mean).max()), TINY)
    x = (points - mean) / spread
    n = len(x)
    q = np.column_stack([x, np.ones(n)])
    u = np.full(n, 1.0 / n)
    for k in range(rounds):
        if k % 50 == 0:
            try:
                inverse = np.linalg.inv(q.T @ (u[:, None] * q))
            except np.linalg.LinAlgError:
                return None
            m = np.einsum("ij,jk,ik->i", q, inverse, q)
        j = int(np.argmax(m))
        step = (m[j] - 4) / (4 * (m[j] - 1))
        if not step >= tolerance:
            break
        g = q @ (inverse @ q[j])  # q_i^T X^-1 q_j
        u *= 1 - step
        u[j] += step
        denominator = 1 - step + step * m[j]
        m = (m - step * g * g / denominator) / (1 - step)
        inverse = (inverse - step * np.outer(inverse @ q[j], q[j] @ inverse) / denominator) / (1 - step)
    centre = x.T @ u
    try:
        a = np.linalg.inv(x.T @ (u[:, None] * x) - np.outer(centre, centre)) / 3
    except np.linalg.LinAlgError:
        return None
    if not np.isfinite(a).all() or np.linalg.eigvalsh(a)[0] <= 0:
        return None
    return mean + spread * centre, a / spread**2


def _ellipsoids(cloud):
    """[(name, L, e, rho)]: ellipsoids {x : |L (x - e)|^2 <= rho} holding every true cloud point (see the module)."""
    out = []
    lo, hi = cloud.box()
    width = np.maximum(hi - lo, 1e-9 * max(float((hi - lo).max()), 1e-300))
    centre = (lo + hi) / 2
    out.append(("box corners", np.diag(1 / (np.sqrt(3) * width / 2)), centre))
    found = mvee(cloud.hints[cloud.hull.vertices] if cloud.hull is not None else cloud.hints)
    if found is not None:
        e, a = found
        w, v = np.linalg.eigh(a)
        out.append(("minimum-volume", np.sqrt(np.maximum(w, 0))[:, None] * v.T, e))
    ellipsoids = []
    for name, l_matrix, e in out:
        d = cloud.points - e
        w = d @ l_matrix.T
        bound = ROUND * ((np.abs(cloud.points) + np.abs(e)) @ np.abs(l_matrix).T) + cloud.error @ np.abs(l_matrix).T
        rho = float(_up((((np.abs(w) + bound) ** 2).sum(axis=1) * (1 + 4 * ROUND)).max()))
        if np.isfinite(rho) and rho > 0:
            ellipsoids.append((name, l_matrix, e, rho))
    return ellipsoids


# -- the link ------------------------------------------------------------------

def _read_parts(geometry, packages):
    """[(part, MeshSolid or None, resolved path)] of the link's meshes and primitives, or MeshUnread."""
    out = []
    for part in geometry.meshes:
        path = resolve(part.uri, part.base, packages)
        out.append((part, read_mesh(path), path))
    return out + [(p, None, None) for p in geometry.primitives]


def _cloud(parts):
    pieces = []
    for part, mesh, _ in parts:
        if mesh is None:
            corners = _corners(part)
            p, e = _placed(corners, (1, 1, 1), part.pose)
            if not e.any():
                e = PLACEMENT * np.abs(corners) + TINY  # the corners' own rounding
            pieces.append((p, e, p))
        else:
            p, e = _placed(mesh.vertices, part.scale, part.pose)
            pieces.append((p, e, p[mesh.hull] if mesh.hull is not None else p))
    return _Cloud(pieces)


_SHAPES = {}  # the parts' (content hash or primitive, scale, pose) -> (cloud, ellipsoids), in this process


def _shape(parts):
    """(cloud, ellipsoids) of the parts, computed once per process for the same meshes placed the same way."""
    key = tuple((mesh.sha256 if mesh is not None else (part.kind, part.dims), getattr(part, "scale", None),
                 part.pose) for part, mesh, _ in parts)
    if key not in _SHAPES:
        cloud = _cloud(parts)
        _SHAPES[key] = cloud, _ellipsoids(cloud)
    return _SHAPES[key]


def _mesh_volume(parts):
    """A certified upper bound (exact, with its pi part: (a, b) for a + b pi) of vol(G) when every mesh is fit,
    else None."""
    a, b = fmpq(0), fmpq(0)
    for part, mesh, _ in parts:
        if mesh is None:
            da, db = _volume(part)
            a, b = a + da, b + db
        elif not mesh.fit:
            return None
        else:
            factor = abs(_q(part.scale[0]) * _q(part.scale[1]) * _q(part.scale[2]))
            a += factor * (_exact(mesh.signed_volume) + _exact(mesh.volume_error))
    return a, b


def _sigma_link(body):
    """The covariance about the CoM in link axes, R_in S R_in^T (exact, or balls with a turned inertial frame)."""
    sigma = [[(body.trace / 2 if i == j else 0) - body.inertia[i][j] for j in range(3)] for i in range(3)]
    r = _rotation(body.pose.rpy)
    return _matmul(_matmul(r, sigma), _transpose(r))


def _ellipsoid_value(body, m_matrix, e, rho):
    """tr(Q f(Phi)) = m rho - m (c - e)^T M (c - e) - tr(M Sigma) (see the module)."""
    d = [body.com[k] - e[k] for k in range(3)]
    sigma = _sigma_link(body)
    quad = sum((d[i] * m_matrix[i][j] * d[j] for i in range(3) for j in range(3)), fmpq(0))
    trace = sum((m_matrix[i][j] * sigma[j][i] for i in range(3) for j in range(3)), fmpq(0))
    return body.mass * rho - body.mass * quad - trace


def _uniform(mass, parts):
    """(CoM, inertia about it in link axes) of G filled uniformly at ``mass`` (every mesh fit; float64)."""
    shares, centres, sigmas = [], [], []
    for part, mesh, _ in parts:
        r = rotation_rpy([float(x) for x in part.pose.rpy])
        t = np.array([float(x) for x in part.pose.xyz])
        if mesh is None:
            sigma, c = covariance(part.kind, 1.0, np.array([float(x) for x in part.dims]))
            a, b = _volume(part)
            shares.append(float(a) + float(b) * np.pi)
        else:
            s = np.array([float(x) for x in part.scale])
            i_unit = mesh.inertia_per_mass
            sigma = np.diag(s) @ (np.trace(i_unit) / 2 * np.eye(3) - i_unit) @ np.diag(s)
            c = s * mesh.centre
            shares.append(abs(float(np.prod(s))) * mesh.signed_volume)
        centres.append(r @ c + t)
        sigmas.append(r @ sigma @ r.T)
    weights = mass * np.array(shares) / sum(shares)
    com = sum(w * c for w, c in zip(weights, centres)) / mass
    total = sum(w * (s + np.outer(c - com, c - com)) for w, s, c in zip(weights, sigmas, centres))
    return com, np.trace(total) * np.eye(3) - total


def _inertial_text(mass, com, inertia):
    six = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[1, 2], inertia[0, 2]]
    names = ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")
    return (f'<inertial><origin xyz="{" ".join(f"{x:.9g}" for x in com)}" rpy="0 0 0"/><mass value="{mass:.9g}"/>'
            f'<inertia {" ".join(f"{n}={chr(34)}{x:.9g}{chr(34)}" for n, x in zip(names, six))}/></inertial>')


def link_findings(name, inertial, geometry, *, max_density=DENSEST, packages=None):
    """The findings on one link as :func:`.bodies_inside.link_findings` gives them, its meshes decided too (see the
    module); ``packages``: {NAME: folder} of ``--package``."""
    if geometry is None or not getattr(geometry, "meshes", ()) or geometry.unread:
        return primitive_findings(name, inertial, geometry, max_density=max_density)
    out = primitive_findings(name, inertial, None, max_density=max_density)  # the ball bound needs no geometry
    if out is None:
        return None
    described = [p.describe() for p in (*geometry.meshes, *geometry.primitives)]
    out["geometry"] = {"source": geometry.source, "primitives": described, "meshes": [], "not_read": None}
    if geometry.inertial_pose is None:
        out["geometry"]["not_read"] = "the <inertial> origin is not read"
        return out
    try:
        parts = _read_parts(geometry, packages)
    except MeshUnread as exc:
        out["geometry"]["not_read"] = f"link '{name}': {exc}"
        return out
    out["geometry"]["meshes"] = [{"uri": part.uri, "path": str(path), "scale": [float(s) for s in part.scale],
                                  **mesh.fitness()} for part, mesh, path in parts if mesh is not None]
    fit = all(mesh.fit for _, mesh, _ in parts if mesh is not None)
    if not fit:
        out["geometry"]["note"] = ("a mesh is not a closed, consistently wound solid: only its convex hull is used "
                                   "(the mass against an enclosure of it, the centre against the hull, the ellipsoid "
                                   "holding it); no uniform-density inertia")
    _decide(name, inertial, geometry, parts, fit, out, max_density)
    return out


def _decide(name, inertial, geometry, parts, fit, out, max_density):
    body = _Body(inertial, geometry.inertial_pose)
    rho_max = _q(Fraction(max_density))
    m = float(body.mass)
    where = f"its {geometry.source} " + "; ".join(out["geometry"]["primitives"])
    findings, not_decided = out["findings"], out["not_decided"]

    def found(rule, message, **numbers):
        findings.append({"rule": rule, "hard": rule in HARD,
                         "message": f"link '{name}': {message}", "numbers": numbers})

    cloud, ellipsoids = _shape(parts)
    # the mass
    lo, hi = cloud.box()
    candidates = []
    mesh_volume = _mesh_volume(parts) if fit else None
    if mesh_volume is not None:
        a, b = mesh_volume
        candidates.append(("the meshes' own volume", a, b))
    box = fmpq(1)
    for k in range(3):
        box *= _exact(hi[k]) - _exact(lo[k])
    candidates.append(("its bounding box", box, fmpq(0)))
    for label, l_matrix, e, rho in ellipsoids:
        det = abs(float(np.linalg.det(l_matrix)))
        if det > 0:  # (4/3) pi rho^(3/2) / |det L|, with det L from the exact entries
            entries = [[_exact(x) for x in row] for row in l_matrix]
            exact_det = (entries[0][0] * (entries[1][1] * entries[2][2] - entries[1][2] * entries[2][1])
                         - entries[0][1] * (entries[1][0] * entries[2][2] - entries[1][2] * entries[2][0])
                         + entries[0][2] * (entries[1][0] * entries[2][1] - entries[1][1] * entries[2][0]))
            if exact_det != 0:
                candidates.append((f"its {label} ellipsoid", None, (label, abs(exact_det), _exact(rho))))
    volumes = {}
    for label, a, b in candidates:
        if a is None:
            _, det, rho = b
            value = lambda det=det, rho=rho: body.mass - rho_max * fmpq(4, 3) * arb.pi() * arb(rho).sqrt() * rho / det
            volumes[label] = 4 / 3 * np.pi * float(rho) ** 1.5 / float(det)
        else:
            value = (lambda a=a, b=b: body.mass - rho_max * (a + b * arb.pi())) if b else \
                (lambda a=a: body.mass - rho_max * a)
            volumes[label] = float(a) + float(b) * np.pi
        if _sign(value) == 1:
            found("mass-exceeds-densest", f"mass {m:g} kg exceeds what the densest material ({max_density:g} kg/m^3) "
                  f"fits in {label} ({volumes[label]:.6g} m^3, an upper bound: at most "
                  f"{max_density * volumes[label]:.6g} kg) of {where}", mass=m, volume=volumes[label],
                  bound=label, density=m / volumes[label])
            break
    out["geometry"]["volume_bounds"] = volumes
    # the centre of mass
    com = np.array([float(x) for x in body.com])
    com_text = " ".join(_decimal(x) for x in body.pose.xyz)
    directions = [np.eye(3)[k] * s for k in range(3) for s in (1, -1)]
    if cloud.hull is not None:
        directions += list(cloud.hull.equations[:, :3])
    directions = np.array(directions)
    supports = [hi[0], -lo[0], hi[1], -lo[1], hi[2], -lo[2]]  # the box's faces
    excess = directions @ com - np.array(supports + list(-cloud.hull.equations[:, 3] if cloud.hull is not None else []))
    k = int(np.argmax(excess))
    if excess[k] > 0:
        n = directions[k]
        support = cloud.support(n)
        margin = sum((_exact(n[i]) * body.com[i] for i in range(3)), fmpq(0)) - _exact(support)
        if margin > 0:
            found("com-outside-geometry", f"centre of mass ({com_text}) lies outside the convex hull of {where}: "
                  f"n . c = {float(n @ com):.6g} m > {support:.6g} m, the largest n . p over every vertex, for "
                  f"n = ({', '.join(f'{x:.4g}' for x in n)})", com=com_text, excess=float(margin) / np.linalg.norm(n))
        else:
            not_decided.append(f"com-outside-geometry: the centre of mass ({com_text}) is within rounding of the "
                               "hull's boundary")
    # the ellipsoid
    for label, l_matrix, e, rho in ellipsoids:
        entries = [[_exact(x) for x in row] for row in l_matrix]
        m_matrix = _matmul(_transpose(entries), entries)
        value = _sign(lambda m_matrix=m_matrix, e=e, rho=rho: _ellipsoid_value(body, m_matrix, [_exact(x) for x in e],
                                                                          _exact(rho)))
        if value == -1:
            axes = np.sqrt(rho) / np.linalg.svd(l_matrix, compute_uv=False)
            found("outside-bounding-ellipsoid", f"tr(Q f(Phi)) < 0 for the {label} ellipsoid with semi-axes "
                  f"({', '.join(f'{x:.4g}' for x in sorted(axes))}) m holding {where}: no mass distribution inside "
                  f"it has this inertia (mass {m:g} kg, tr(I_CoM) {float(body.trace):.6g} kg m^2, centre ({com_text}))",
                  ellipsoid=label, semi_axes=sorted(axes.tolist()), trace=float(body.trace))
            break
        if value is None:
            not_decided.append(f"outside-bounding-ellipsoid: tr(Q f(Phi)) for the {label} ellipsoid is not decided "
                               "at 1024 bits")
    # soft
    volume = volumes.get("the meshes' own volume", cloud.hull.volume if cloud.hull is not None else 0.0)
    if volume > 0 and m / volume < PLAUSIBLE_DENSITY:
        found("implausible-density", f"implied density {m / volume:.4g} kg/m^3 (mass {m:g} kg in {where}, volume "
              f"{volume:.6g} m^3) is below {PLAUSIBLE_DENSITY} kg/m^3, lighter than solid parts", density=m / volume)
    if not fit or mesh_volume is None:
        return
    centre, inertia = _uniform(m, parts)
    moments = np.linalg.eigvalsh(inertia).tolist()
    declared = np.linalg.eigvalsh(np.array([[float(x) for x in row] for row in body.inertia])).tolist()
    ratio = max(max(x / y, y / x) for x, y in zip(declared, moments)) if min(declared) > 0 and min(moments) > 0 else 0
    if ratio > MOMENT_RATIO:
        found("inertia-unlike-geometry", f"principal moments ({', '.join(f'{x:.4g}' for x in declared)}) kg m^2 are "
              f"up to {ratio:.3g}x off those of {where} filled uniformly at {m:g} kg "
              f"({', '.join(f'{x:.4g}' for x in moments)})", ratio=float(ratio))
    out["uniform"] = {"principal_moments": moments, "com": centre.tolist(), "inertia": inertia.tolist(),
                      "text": _inertial_text(m, centre, inertia),
                      "span": None if geometry.inertial_span is None else geometry.inertial_span.region()}
