"""What MuJoCo, Drake, PyBullet and Gazebo do with a link's inertia as written.

Each rule below is the engine's own, read from its source and checked
against the engine where it installs here (README, "What each engine will
do", cites the files). The audit's own verdict (Theorem 1, strict triangle
inequalities decided exactly) is stricter than every engine's: engines accept
degenerate inertias (the triangle inequality with equality) and, within their
tolerances, slightly inconsistent ones.

- MuJoCo (mjCBody::Compile, mjuu_fullInertia, CheckBodyMassInertia): a full
  matrix (URDF ``<inertia>``, MJCF ``fullinertia``) is diagonalised and
  rejected when its smallest eigenvalue is below mjEPS = 1e-14 (an all-zero
  URDF inertia counts as absent); mass and principal moments are raised to
  ``boundmass``/``boundinertia`` (0 by default, so negatives become 0); then
  A + B >= C on the principal moments with no tolerance, else rejected (or,
  with ``balanceinertia``, all three set to their mean); a body with a joint
  needs mass and every principal moment >= mjMINVAL = 1e-15 unless a body
  welded to it has them.
- Drake (RotationalInertia::CouldBePhysicallyValid, ParseSpatialInertia):
  principal moments p with eps = 16 DBL_EPSILON max(1, tr/2): p_i >= -eps and
  p_0 + p_1 + eps >= p_2; its URDF parser warns and substitutes a solid sphere
  of water density with the link's mass (1 kg when the mass is not positive);
  mass 0 with zero inertia is a massless body.
- PyBullet (BulletURDFImporter::getMassAndInertia): ``loadURDF`` ignores the
  file's inertia unless URDF_USE_INERTIA_FROM_FILE (it computes one from the
  collision shapes); with the flag a principal moment < 0 or greater than the
  sum of the other two (strict, no tolerance; Jacobi diagonalisation to 1e-6
  when products are nonzero) zeroes the inertia with a warning.
- Gazebo (gz-math MassMatrix3::IsValid; sdformat Link::Load, parser_urdf.cc):
  mass >= 0, leading minors + eps >= 0, principal moments p_i + eps >= 0 and
  p_i + p_j + eps >= p_k with eps = 10 DBL_EPSILON |tr|/2; invalid: the error
  "A link named X has invalid inertia." and gz-sim does not load the model; a
  URDF link with mass <= 0 is dropped with its joint ("not modeled in sdf")
  unless a fixed joint lumps it into its parent.

A URDF ``<inertial>`` that urdfdom cannot parse (:class:`.urdf.Problem`) gets
:func:`unread_column` instead, from what the engines installed here do with
such a file (observed with MuJoCo 4.0 and pybullet 3.2.7 on a two-link arm,
``tests/test_audit_problems.py`` checks it where they install):

- a missing element or attribute (``<mass>``, its ``value``, ``<inertia>``,
  an inertia attribute): MuJoCo refuses the file ("XML Error: missing
  element: 'inertia'", "required attribute missing: 'iyy'"); PyBullet
  refuses it with and without URDF_USE_INERTIA_FROM_FILE ("Inertial element
  must have inertia element", "failed to parse link", "Cannot load URDF
  file.");
- a value that is not a number or not finite, or a wrong count of numbers:
  MuJoCo refuses the file ("bad format in attribute", "does not have enough
  data"; nan or an infinite inertia entry fail the mjMINVAL check of a
  moving body); PyBullet loads it (a mass that is not a number as 0, an
  inertia entry as 0 and then "Bad inertia tensor properties", an origin
  that is not three numbers ignored with "Couldn't parse vector3").

Drake and Gazebo are not installed here: their column says so rather than
guess (urdfdom and Pinocchio are in the problem's own message).

SDFormat (``fmt="sdf"``, :mod:`.sdf`): MuJoCo does not read it; Drake's
SDFormat parser checks an inertia as its URDF parser does (the rule above);
pybullet's ``loadSDF`` (observed with pybullet 3.2.7) keeps the file's mass
and computes the inertia from the collision shapes, with no flag to use the
file's; Gazebo reads it natively (MassMatrix3::IsValid, no link dropped).
:func:`sdf_unread_column` for what SDFormat defaults.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ENGINES", "engine_column", "MJ_EPS", "MJ_MINVAL", "sdf_unread_column", "unread_column"]

ENGINES = ("mujoco", "drake", "pybullet", "gazebo")
EPS = np.finfo(float).eps
MJ_EPS, MJ_MINVAL = 1e-14, 1e-15
ROUNDING = 16 * EPS  # relative rounding of eigvalsh on a 3x3 symmetric matrix, generously


def _moments(inertia):
    """Principal moments ascending, and whether they were computed (products nonzero) or read off."""
    if not (inertia[0, 1] or inertia[0, 2] or inertia[1, 2]):
        return np.sort(np.diag(inertia)), False
    return np.linalg.eigvalsh(inertia), True


def _answer(action, text, borderline=False):
    return {"action": action, "text": text + (" (borderline: within rounding of its threshold)" if borderline else "")}


def mujoco(mass, inertia, *, moving, rescued=False, full=True, compiler=None, from_geoms=False):
    """``full``: the inertia is a full matrix (URDF, fullinertia); ``rescued``: a welded body carries mass."""
    compiler = compiler or {}
    if from_geoms:
        return _answer("loads", "loads: MuJoCo computed it from the geoms")
    p, computed = _moments(inertia)
    six = inertia[np.triu_indices(3)]
    if full and six.any() and p[0] < MJ_EPS:
        return _answer("rejects", "rejects: error 'inertia must have positive eigenvalues' in fullinertia",
                       computed and abs(p[0] - MJ_EPS) <= ROUNDING * np.abs(p).sum())
    if full and not six.any():
        p = np.zeros(3)
    m = max(mass, compiler.get("boundmass", 0.0))
    p = np.maximum(p, compiler.get("boundinertia", 0.0))
    if m < 0 or (p < 0).any():
        return _answer("rejects", "rejects: mass and inertia cannot be negative")
    excess = p[2] - p[0] - p[1]
    if excess > 0:
        if compiler.get("balanceinertia"):
            return _answer("balances", f"balances: all three principal moments set to {p.mean():.6g}")
        return _answer("rejects", "rejects: inertia must satisfy A + B >= C; use 'balanceinertia' to fix",
                       computed and excess <= ROUNDING * p.sum())
    if moving and not rescued and (m < MJ_MINVAL or p[0] < MJ_MINVAL):
        return _answer("rejects", "rejects: mass and inertia of moving bodies must be larger than mjMINVAL")
    return _answer("loads", "loads")


def drake(mass, inertia, *, mjcf=False):
    p, computed = _moments(inertia)
    eps = 16 * EPS * max(1.0, 0.5 * abs(np.trace(inertia)))
    margin = min(p[0] + eps, p[0] + p[1] + eps - p[2])
    valid = margin >= 0
    borderline = computed and abs(margin) <= ROUNDING * np.abs(p).sum()
    if mjcf:
        if not valid:
            return _answer("rejects", "rejects: Spatial inertia fails SpatialInertia::IsPhysicallyValid()", borderline)
        if mass <= 0 and inertia.any():
            return _answer("rejects", "fails on mass <= 0 (observed: condition 'mass > 0' failed)")
        return _answer("loads", "loads")
    if not valid:
        stand_in = mass if mass > 0 else 1.0
        return _answer("replaces", f"warns, replaces it by a {stand_in:.4g} kg sphere of water density "
                       "(did not pass CouldBePhysicallyValid)", borderline)
    if mass == 0 and not inertia.any():
        return _answer("loads", "loads: a massless body")
    if mass <= 0:
        return _answer("replaces", "warns, replaces it by a 1 kg sphere of water density (mass <= 0)")
    return _answer("loads", "loads")


def pybullet(mass, inertia):
    p, computed = _moments(inertia)
    bad = p[0] < 0 or p[2] > p[0] + p[1]
    borderline = computed and abs(p[2] - p[0] - p[1]) <= 1e-6 * np.abs(p).sum()
    default = "ignores it by default (inertia from the collision shapes)"
    if mass == 0:
        return _answer("loads", "loads: a static (massless) link")
    if bad:
        return _answer("zeroes", f"{default}; with URDF_USE_INERTIA_FROM_FILE: warns 'Bad inertia tensor "
                       "properties' and zeroes it", borderline)
    return _answer("loads", f"{default}; loads it with URDF_USE_INERTIA_FROM_FILE", borderline)


def gazebo(mass, inertia, *, lumped=False):
    if mass <= 0 and not lumped:
        return _answer("drops", "drops the link and its joint (mass <= 0: not modeled in sdf)")
    p, computed = _moments(inertia)
    eps = 10 * EPS * abs(np.trace(inertia)) / 2
    minors = (inertia[0, 0] + eps >= 0 and inertia[0, 0] * inertia[1, 1] - inertia[0, 1] ** 2 + eps >= 0
              and np.linalg.det(inertia) + eps >= 0)
    margin = min(p[0] + eps, p[0] + p[1] + eps - p[2])
    if mass < 0 or not minors or margin < 0:
        return _answer("rejects", "rejects: 'A link named ... has invalid inertia.' (the model does not load)",
                       computed and abs(margin) <= ROUNDING * np.abs(p).sum())
    return _answer("loads", "loads")


def engine_column(mass, inertia, *, fmt, moving, rescued=False, lumped=False, full=True, compiler=None,
                  from_geoms=False):
    """{engine: {"action", "text"}} for one link's inertia about its CoM as written (``fmt``: urdf or mjcf)."""
    inertia = np.asarray(inertia, dtype=float)
    out = {"mujoco": mujoco(mass, inertia, moving=moving, rescued=rescued, full=full, compiler=compiler,
                            from_geoms=from_geoms)}
    if fmt == "mjcf":
        out["drake"] = drake(mass, inertia, mjcf=True) if not from_geoms else _answer("loads", "loads")
        out["pybullet"] = _answer("not_documented", "not documented for MJCF")
        out["gazebo"] = _answer("not_documented", "does not read MJCF")
        return out
    if fmt == "sdf":
        out["mujoco"] = _answer("not_documented", "does not read SDFormat")
        out["drake"] = drake(mass, inertia)  # its SDFormat parser checks the inertia as its URDF parser does
        out["pybullet"] = _answer("loads", "loads a static (massless) link") if mass == 0 else _answer(
            "ignores", "ignores it: loadSDF keeps the mass and computes the inertia from the collision shapes")
        out["gazebo"] = gazebo(mass, inertia, lumped=True)  # native: no link is dropped
        return out
    out["drake"] = drake(mass, inertia)
    out["pybullet"] = pybullet(mass, inertia)
    out["gazebo"] = gazebo(mass, inertia, lumped=lumped)
    return out


NOT_INSTALLED = _answer("not_verified", "not verified: not installed here")


def unread_column(missing, fmt="urdf"):
    """{engine: {"action", "text"}} for a URDF link whose ``<inertial>`` urdfdom cannot parse (see the module):
    ``missing``, an element or attribute is missing; else a value is not a finite number or has the wrong count.
    ``fmt="sdf"``: an SDFormat link whose ``<inertial>`` (or part of it) is missing or not a number
    (:func:`sdf_unread_column`)."""
    if fmt == "sdf":
        return sdf_unread_column(missing)
    if missing:
        return {"mujoco": _answer("rejects", "rejects the file: 'XML Error: missing element' (or 'required "
                                  "attribute missing')"),
                "drake": NOT_INSTALLED,
                "pybullet": _answer("rejects", "cannot load the file, with or without URDF_USE_INERTIA_FROM_FILE "
                                    "('failed to parse link')"),
                "gazebo": NOT_INSTALLED}
    return {"mujoco": _answer("rejects", "rejects the file: 'XML Error: bad format in attribute' (or not enough "
                              "data; nan or an infinite inertia entry: mass and inertia below mjMINVAL)"),
            "drake": NOT_INSTALLED,
            "pybullet": _answer("loads", "loads it, reading a value that is not a number as 0 (an origin that is not "
                                "three numbers is ignored with 'Couldn't parse vector3')"),
            "gazebo": NOT_INSTALLED}


def sdf_unread_column(missing):
    """{engine: {"action", "text"}} for an SDFormat link with a missing ``<inertial>``, ``<mass>``, ``<inertia>`` or
    diagonal moment (``missing``) or a value that is not a number. Gazebo (sdformat) reads the specification's
    defaults (its Link's default inertial: 1 kg, unit diagonal); pybullet 3.2.7's loadSDF, observed here: a link
    without ``<inertial>`` gets 1 kg ("No inertial data for link") and the inertia of its collision shapes, an
    ``<inertial>`` without ``<mass>``, ``<inertia>`` or any of the six entries makes the file fail to load."""
    if missing:
        gazebo_does = _answer("defaults", "loads SDFormat's defaults for what is missing (mass 1 kg, ixx = iyy = "
                              "izz = 1 kg m^2), without a warning")
        bullet = _answer("defaults", "a link without <inertial>: warns 'No inertial data for link', mass 1 kg, "
                         "inertia from the collision shapes; else cannot load the file ('Cannot load SDF file.')")
    else:
        gazebo_does = _answer("not_verified", "not verified: sdformat reports an error and keeps the default; "
                              "not installed here")
        bullet = NOT_INSTALLED | {"text": "not verified for a value that is not a number"}
    return {"mujoco": _answer("not_documented", "does not read SDFormat"), "drake": NOT_INSTALLED,
            "pybullet": bullet, "gazebo": gazebo_does}
