"""Scenes: a chain, its bodies and how their parameters change in time, from a TOML file.

See ``scenes/README.md`` for the format. Every mistake is reported as a
:class:`SceneError` naming the file, the line and the field.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from inertiaproof.dynamics.chain import COORDINATE_MAPS, Chain, Coordinate, Joint, Origin, Written, decimal
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Payload, Profile, Scaling
from inertiaproof.dynamics.trajectory import Path as LoadPath
from inertiaproof.errors import LARGEST, InputError, read_text
from inertiaproof.model import solids
from inertiaproof.model.consistency import EPS, INCONSISTENT, INVALID, RESOLUTION, physical_consistency
from inertiaproof.model.inertia import from_urdf, pack, rotation_rpy, urdf_inertia

__all__ = ["AdaptiveSettings", "ControlSettings", "load_gains", "load_scene", "parse_scene", "Scene", "SceneError"]


class SceneError(InputError):
    """A scene file that cannot be used; the message names file, line and field."""


class _Written(float):
    """A TOML float that remembers how the file writes it (bodies are judged on the decimals, not their floats)."""

    __slots__ = ("text",)

    def __new__(cls, text):
        value = super().__new__(cls, text)
        value.text = text
        return value


def _text(value):
    """The decimal a file writes for a number read from it (an integer as itself), or None."""
    if isinstance(value, bool):
        return None
    return getattr(value, "text", None) or (str(value) if isinstance(value, int) else None)


@dataclass(frozen=True)
class ControlSettings:
    """How a simulation of the scene drives it (inertiaproof.sim.control.controller): a controller of ``kind``
    with ``bandwidth`` rad/s and ``damping``, gains ``per_joint`` or ``uniform``, tracking
    home + amplitude sin(2 pi frequency t + k pi / 3) on joint k, over ``horizon`` seconds."""

    kind: str = "pd"
    bandwidth: float = 10.0
    damping: float = 1.0
    gains: str = "per_joint"
    home: tuple | None = None
    amplitude: float = 0.3
    frequency: float = 0.5
    horizon: float | None = None

    KINDS = ("pd", "computed_torque", "none")
    GAINS = ("per_joint", "uniform")


INTEGRATORS = ("auto", "RK45", "DOP853", "BDF", "Radau")  # of [adaptive] integrator (inertiaproof.sim.tracking.SOLVERS)


@dataclass(frozen=True)
class AdaptiveSettings:
    """Adaptive tracking of the scene's reference (inertiaproof.sim.tracking, ``inertiaproof adapt``): the sliding
    variable s = e' + lam e (lam in 1/s), K_D = kd diag(M(home, Theta(t0))) (kd in 1/s), the adaptation gain of
    each law by name, the initial estimate Theta_hat(0) = estimate Theta(t0) (one factor, or one per body), and the
    integrator of the runs (``method`` of inertiaproof.sim.tracking.simulate) and the counted work the APP checks'
    study of the scene may spend at least (``work`` of checks.applications.AppSettings: a scene whose runs need
    more than the profile gives says so; 0: the profile's)."""

    lam: float = 5.0
    kd: float = 10.0
    gamma: tuple = (("natural", 10.0), ("slotine-li", 1.0))  # (law name, gain) pairs
    estimate: tuple = (1.0,)
    integrator: str = "auto"
    work: float = 0.0

    def gain(self, law):
        return dict(self.gamma).get(law)


@dataclass(frozen=True)
class Scene:
    name: str
    chain: Chain
    trajectory: ParameterTrajectory
    description: str = ""
    source: str | None = None
    warnings: tuple = field(default_factory=tuple)
    control: ControlSettings = ControlSettings()
    adaptive: AdaptiveSettings = AdaptiveSettings()

    def features(self):
        """What this scene has; checks declare what they need of it."""
        have = {"chain"}
        if self.trajectory.time_varying:
            have.add("time_varying")
        if self.trajectory.internal_motion:
            have.add("internal_motion")
        if self.trajectory.mass_change:
            have.add("mass_change")
        return frozenset(have)

    def horizon(self, default=3.0):
        """Seconds a simulation of the scene covers: [control] horizon, else the time span up to ``default``."""
        if self.control.horizon is not None:
            return self.control.horizon
        t0, t1 = self.trajectory.span
        return min(t1 - t0, default)


# -- locating fields in the source -------------------------------------------

_HEADER = re.compile(r"^\s*\[(\[)?\s*([A-Za-z0-9_.\-]+)\s*\]?\]\s*(#.*)?$")


def _locate(text, path):
    """1-based line of a field given as a path like ('body', 1, 'solid', 'dims'), or None.

    Walks the path: a name is a table header ([a.b] or the i-th [[a.b]]) or a key inside the current
    table; once a key's value is an inline table or array, deeper names are looked up on that line.
    """
    lines = text.splitlines()
    headers = [(n, m.group(2)) for n, line in enumerate(lines) if (m := _HEADER.match(line))]
    lo, hi, found, dotted = 0, len(lines), None, ""
    parts = list(path)
    for i, part in enumerate(parts):
        if not isinstance(part, str):
            continue
        index = parts[i + 1] if i + 1 < len(parts) and isinstance(parts[i + 1], int) else 0
        name = f"{dotted}.{part}" if dotted else part
        tables = [n for n, h in headers if h == name and lo <= n < hi]
        if tables:
            lo = tables[min(index, len(tables) - 1)]
            hi = next((n for n, h in headers if n > lo and (h == name or not h.startswith(name + "."))), len(lines))
            found, dotted = lo, name
            continue
        key = re.compile(rf"(^|[{{,\s]){re.escape(part)}\s*=")
        line = next((n for n in range(lo, hi) if key.search(lines[n])
                     and not (n != lo and _HEADER.match(lines[n]))), None)
        if line is None:
            break
        found, lo, hi, dotted = line, line, line + 1, name
    return None if found is None else found + 1


def _field_name(path):
    out = ""
    for p in path:
        out += f"[{p + 1}]" if isinstance(p, int) else (f".{p}" if out else p)
    return out


class _Reader:
    """Typed access to the parsed TOML with errors that point into the file."""

    def __init__(self, text, source):
        self.text, self.source = text, source

    def error(self, path, message):
        line = _locate(self.text, path)
        where = f"{self.source}:{line}" if line else self.source
        field = _field_name(path)
        raise SceneError(f"{where}: {field}: {message}" if field else f"{where}: {message}")

    def keys(self, table, path, allowed, required=()):
        for k in table:
            if k not in allowed:
                self.error(path + (k,), f"unknown key; expected one of {', '.join(sorted(allowed))}")
        for k in required:
            if k not in table:
                self.error(path, f"missing required key {k!r}")

    def number(self, table, path, key, default=None, positive=False, nonnegative=False, endless=False):
        if key not in table:
            if default is None:
                self.error(path, f"missing required key {key!r}")
            return default
        v = table[key]
        if isinstance(v, str) and v in ("inf", "+inf"):
            v = float("inf")
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            self.error(path + (key,), f"must be a number, got {v!r}")
        v = float(v)
        if np.isnan(v):
            self.error(path + (key,), "must be a number, got nan")
        if not np.isfinite(v) and not (endless and v > 0):
            self.error(path + (key,), f"must be finite, got {getattr(table[key], 'text', v)}")
        if np.isfinite(v) and abs(v) > LARGEST:
            self.error(path + (key,), f"{v:g} is out of range (|x| <= {LARGEST:g})")
        if positive and not v > 0:
            self.error(path + (key,), f"must be > 0, got {v:g}")
        if nonnegative and not v >= 0:
            self.error(path + (key,), f"must be >= 0, got {v:g}")
        return v

    def vector(self, table, path, key, size, default=None):
        if key not in table:
            if default is None:
                self.error(path, f"missing required key {key!r}")
            return np.asarray(default, dtype=float)
        v = table[key]
        if not isinstance(v, list) or len(v) != size or not all(
                isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
            self.error(path + (key,), f"must be a list of {size} numbers, got {v!r}")
        a = np.asarray(v, dtype=float)
        if not np.all(np.isfinite(a)):
            self.error(path + (key,), f"must be finite, got {v!r}")
        if np.any(np.abs(a) > LARGEST):
            self.error(path + (key,), f"out of range (|x| <= {LARGEST:g}), got {v!r}")
        return a

    def choice(self, table, path, key, options, default=None):
        v = table.get(key, default)
        if v is None:
            self.error(path, f"missing required key {key!r}")
        if v not in options:
            self.error(path + (key,), f"must be one of {', '.join(options)}, got {v!r}")
        return v

    def table(self, table, path, key, required=True):
        v = table.get(key)
        if v is None:
            if required:
                self.error(path, f"missing required table {key!r}")
            return None
        if not isinstance(v, dict):
            self.error(path + (key,), f"must be a table, got {v!r}")
        return v

    def tables(self, table, path, key, required=True):
        v = table.get(key)
        if v is None:
            if required:
                self.error(path, f"missing required array of tables [[{key}]]")
            return []
        if not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
            self.error(path + (key,), "must be an array of tables")
        return v


# -- the parts of a scene ------------------------------------------------------

_URDF_ORDER = ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")


def _inertia_matrix(r, table, path, key):
    """(3x3 inertia, its six entries as written in URDF order or None) from [ixx, iyy, izz, ixy, iyz, ixz], a 3x3
    list, or a table of those names."""
    v = table[key]
    if isinstance(v, dict):
        r.keys(v, path + (key,), set(_URDF_ORDER), required=("ixx", "iyy", "izz"))
        vals = [r.number(v, path + (key,), k, default=0.0) for k in _URDF_ORDER]
        return urdf_inertia(*vals), tuple(_text(v[k]) if k in v else "0" for k in _URDF_ORDER)
    if isinstance(v, list) and len(v) == 3 and all(isinstance(row, list) for row in v):
        rows = [r.vector({"row": row}, path + (key,), "row", 3) for row in v]
        a = np.array(rows)
        if not np.allclose(a, a.T, rtol=0, atol=1e-12 * max(1.0, np.abs(a).max())):
            r.error(path + (key,), f"inertia matrix is not symmetric: {v!r}")
        written = None if not np.array_equal(a, a.T) else tuple(
            _text(v[i][j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)))
        return 0.5 * (a + a.T), written
    return urdf_inertia(*r.vector(table, path, key, 6)), tuple(_text(x) for x in v)


def _body_phi(r, table, path, extra_keys=()):
    """Phi from exactly one of: mass + com + inertia (about the CoM) [+ rpy], phi, or solid."""
    allowed = {"name", "mass", "com", "inertia", "rpy", "phi", "solid"} | set(extra_keys)
    r.keys(table, path, allowed)
    given = [k for k in ("inertia", "phi", "solid") if k in table]
    if len(given) != 1:
        r.error(path, "give exactly one of 'inertia' (with mass and com), 'phi' or 'solid'")
    if "phi" in table:
        phi = r.vector(table, path, "phi", 10)
        if not phi[0] > 0:
            r.error(path + ("phi",), f"mass (first entry) must be > 0, got {phi[0]:g}")
        judged, written = phi, tuple(_text(x) for x in table["phi"])
    elif "solid" in table:
        s = r.table(table, path, "solid")
        sp = path + ("solid",)
        r.keys(s, sp, {"shape", "dims", "rpy", "position"}, required=("shape", "dims"))
        shape = r.choice(s, sp, "shape", solids.SHAPES)
        size = {"sphere": 1, "cylinder": 2, "cone": 2, "tetrahedron": 12}.get(shape, 3)
        dims = r.vector(s, sp, "dims", size)
        if shape != "tetrahedron" and not np.all(dims > 0):
            r.error(sp + ("dims",), f"dimensions must be > 0, got {dims.tolist()}")
        mass = r.number(table, path, "mass", positive=True)
        try:
            phi = solids.solid(shape, mass, dims, rotation_rpy(r.vector(s, sp, "rpy", 3, (0, 0, 0))),
                               r.vector(s, sp, "position", 3, (0, 0, 0)))
        except ValueError as exc:
            r.error(sp + ("dims",), str(exc))
        judged, written = phi, None
    else:
        mass = r.number(table, path, "mass", positive=True)
        com = r.vector(table, path, "com", 3, (0, 0, 0))
        inertia, inertia_text = _inertia_matrix(r, table, path, "inertia")
        rpy = r.vector(table, path, "rpy", 3, (0, 0, 0))
        phi = from_urdf(mass, com, inertia, rotation_rpy(rpy))
        # judged about the CoM as written: consistency does not depend on the frame, and moving it rounds
        judged = pack(mass, np.zeros(3), inertia)
        written = None if inertia_text is None else (_text(table["mass"]), "0", "0", "0", *inertia_text)
    verdict = physical_consistency(judged, written=written)
    if verdict.verdict in (INCONSISTENT, INVALID):
        r.error(path + (given[0],), f"not a physical body: {verdict.reason(0)}")
    return phi


def _profile(r, table, path):
    if "profile" not in table:
        r.error(path, "missing required table 'profile'")
    p = r.table(table, path, "profile")
    pp = path + ("profile",)
    r.keys(p, pp, {"shape", "start", "duration", "rate"}, required=("shape",))
    shape = r.choice(p, pp, "shape", Profile.SHAPES)
    return Profile(shape=shape, start=r.number(p, pp, "start", 0.0),
                   duration=r.number(p, pp, "duration", 1.0, positive=shape not in ("constant", "exp")),
                   rate=r.number(p, pp, "rate", 0.0))


def _joint(r, table, path, convention, index):
    common = {"type", "limits", "coordinate", "name"}
    if convention == "joints":
        r.keys(table, path, common | {"axis", "xyz", "rpy"}, required=("type",))
    else:
        r.keys(table, path, common | {"a", "alpha", "d", "theta"}, required=("type",))
    kind = r.choice(table, path, "type", ("revolute", "prismatic"))
    coordinate = r.choice(table, path, "coordinate", tuple(COORDINATE_MAPS), default="identity")
    limits = None
    if "limits" in table:
        lo, hi = r.vector(table, path, "limits", 2)
        if not lo < hi:
            r.error(path + ("limits",), f"lower limit must be below the upper, got [{lo:g}, {hi:g}]")
        limits = (lo, hi)
    name = table.get("name", f"joint{index + 1}")
    if convention == "joints":
        axis = r.vector(table, path, "axis", 3, (0, 0, 1))
        if not np.linalg.norm(axis) > 0:
            r.error(path + ("axis",), "must be a nonzero vector")
        written = Origin.of(r.vector(table, path, "xyz", 3, (0, 0, 0)), r.vector(table, path, "rpy", 3, (0, 0, 0)))
        return Joint(kind, tuple(axis), before=written.matrix(), coordinate=Coordinate(coordinate), limits=limits,
                     name=name, written=Written((written,), (), tuple(map(decimal, axis)),
                                                None if limits is None else tuple(map(decimal, limits))))
    row = [r.number(table, path, k, 0.0) for k in ("a", "alpha", "d", "theta")]
    proto = Chain.from_dh([row], convention=convention, kinds="R" if kind == "revolute" else "P").joints[0]
    return Joint(kind, proto.axis, proto.before, proto.after, Coordinate(coordinate), limits, name, proto.written)


def _load(r, table, path, bodies):
    kind = r.choice(table, path, "kind", ("payload", "scaling", "moving_mass"))
    body = r.number(table, path, "body")
    if body != int(body) or not 1 <= body <= bodies:
        r.error(path + ("body",), f"must be a body number from 1 to {bodies}, got {body:g}")
    body = int(body) - 1
    if kind == "scaling":
        r.keys(table, path, {"kind", "body", "profile"})
        return Scaling(body, _profile(r, table, path))
    if kind == "payload":
        phi = _body_phi(r, table, path, extra_keys=("kind", "body", "profile"))
        return Payload(body, phi, _profile(r, table, path))
    r.keys(table, path, {"kind", "body", "mass", "inertia", "path", "profile"}, required=("mass", "path"))
    mass = r.number(table, path, "mass", positive=True)
    inertia, written = _inertia_matrix(r, table, path, "inertia") if "inertia" in table else (np.zeros((3, 3)), None)
    if "inertia" in table:
        check = physical_consistency(from_urdf(mass, np.zeros(3), inertia), written=None if written is None else (
            _text(table["mass"]), "0", "0", "0", *written))
        if check.verdict in (INCONSISTENT, INVALID):
            r.error(path + ("inertia",), f"not a physical body: {check.reason(0)}")
    p = r.table(table, path, "path")
    pp = path + ("path",)
    shape = r.choice(p, pp, "shape", ("line", "circle"))
    if shape == "line":
        r.keys(p, pp, {"shape", "from", "to"}, required=("from", "to"))
        lp = LoadPath("line", _profile(r, table, path), start=tuple(r.vector(p, pp, "from", 3)),
                      end=tuple(r.vector(p, pp, "to", 3)))
    else:
        r.keys(p, pp, {"shape", "center", "radius", "normal"}, required=("radius",))
        lp = LoadPath("circle", _profile(r, table, path), center=tuple(r.vector(p, pp, "center", 3, (0, 0, 0))),
                      radius=r.number(p, pp, "radius", positive=True),
                      normal=tuple(r.vector(p, pp, "normal", 3, (0, 0, 1))))
    return MovingMass(body, mass, inertia, lp)


def parse_scene(text, source="<scene>"):
    """A :class:`Scene` from TOML text; raises :class:`SceneError`."""
    try:
        data = tomllib.loads(text, parse_float=_Written)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"line (\d+)", str(exc))
        raise SceneError(f"{source}:{m.group(1) if m else '?'}: not valid TOML: {exc}") from None
    except RecursionError:
        raise SceneError(f"{source}: not usable TOML: nested too deeply") from None
    except ValueError as exc:  # tomllib's int() of an integer beyond Python's 4300 digits
        raise SceneError(f"{source}: not usable TOML: {str(exc).split(';')[0]}") from None
    r = _Reader(text, source)
    r.keys(data, (), {"name", "description", "chain", "body", "load", "time", "control", "adaptive"},
           required=("name", "chain", "body"))
    chain_t = r.table(data, (), "chain")
    r.keys(chain_t, ("chain",), {"convention", "gravity", "joint", "name"}, required=("joint",))
    convention = r.choice(chain_t, ("chain",), "convention", ("standard", "modified", "joints"), default="standard")
    joints = [_joint(r, j, ("chain", "joint", i), convention, i)
              for i, j in enumerate(r.tables(chain_t, ("chain",), "joint"))]
    if not joints:
        r.error(("chain",), "needs at least one [[chain.joint]]")
    chain = Chain(tuple(joints), name=str(data["name"]),
                  gravity=tuple(r.vector(chain_t, ("chain",), "gravity", 3, (0, 0, -9.81))))
    bodies = r.tables(data, (), "body")
    if len(bodies) != len(joints):
        r.error(("body",), f"needs one [[body]] per joint: {len(joints)} joints, {len(bodies)} bodies")
    base = np.stack([_body_phi(r, b, ("body", i)) for i, b in enumerate(bodies)])
    loads = tuple(_load(r, t, ("load", i), len(bodies)) for i, t in enumerate(r.tables(data, (), "load", required=False)))
    time_t = r.table(data, (), "time", required=False) or {}
    r.keys(time_t, ("time",), {"start", "end"})
    t0 = r.number(time_t, ("time",), "start", 0.0)
    t1 = r.number(time_t, ("time",), "end", t0 + 5.0, endless=True)
    if not t1 > t0:
        r.error(("time", "end"), f"must be after time.start = {t0:g}, got {t1:g}")
    trajectory = ParameterTrajectory(base, loads, (t0, t1))
    _check_trajectory(r, trajectory)
    control = _control(r, r.table(data, (), "control", required=False), chain.n)
    adaptive = _adaptive(r, r.table(data, (), "adaptive", required=False) or {}, ("adaptive",), len(bodies))
    return Scene(str(data["name"]), chain, trajectory, str(data.get("description", "")), source, control=control,
                 adaptive=adaptive)


def _control(r, table, joints):
    if table is None:
        return ControlSettings()
    path = ("control",)
    r.keys(table, path, {"kind", "bandwidth", "damping", "gains", "home", "amplitude", "frequency", "horizon"})
    defaults = ControlSettings()
    home = table.get("home")
    return ControlSettings(
        kind=r.choice(table, path, "kind", ControlSettings.KINDS, default=defaults.kind),
        bandwidth=r.number(table, path, "bandwidth", defaults.bandwidth, positive=True),
        damping=r.number(table, path, "damping", defaults.damping, positive=True),
        gains=r.choice(table, path, "gains", ControlSettings.GAINS, default=defaults.gains),
        home=None if home is None else tuple(r.vector(table, path, "home", joints)),
        amplitude=r.number(table, path, "amplitude", defaults.amplitude, nonnegative=True),
        frequency=r.number(table, path, "frequency", defaults.frequency, nonnegative=True),
        horizon=r.number(table, path, "horizon", None, positive=True) if "horizon" in table else None,
    )


def _adaptive(r, table, path, bodies, defaults=AdaptiveSettings(), gains_file=False):
    r.keys(table, path, {"lambda", "kd", "gamma", "estimate", "integrator"} | (set() if gains_file else {"work"}))
    gamma = dict(defaults.gamma)
    for law in r.table(table, path, "gamma", required=False) or {}:
        gamma[law] = r.number(table["gamma"], path + ("gamma",), law, positive=True)
    estimate = defaults.estimate
    if isinstance(table.get("estimate"), list):
        estimate = tuple(r.vector(table, path, "estimate", bodies))
        if not all(e > 0 for e in estimate):
            r.error(path + ("estimate",), f"factors must be > 0, got {list(estimate)}")
    elif "estimate" in table:
        estimate = (r.number(table, path, "estimate", positive=True),)
    integrator = table.get("integrator", defaults.integrator)
    if integrator not in INTEGRATORS:
        r.error(path + ("integrator",), f"must be one of {', '.join(INTEGRATORS)}, got {integrator!r}")
    return AdaptiveSettings(lam=r.number(table, path, "lambda", defaults.lam, positive=True),
                            kd=r.number(table, path, "kd", defaults.kd, positive=True),
                            gamma=tuple(sorted(gamma.items())), estimate=estimate, integrator=integrator,
                            work=r.number(table, path, "work", defaults.work, nonnegative=True))


def load_gains(path, scene):
    """The scene's :class:`AdaptiveSettings` with the keys of a gains file (those of ``[adaptive]`` but the study's
    ``work``) replaced."""
    path = Path(path)
    try:
        text = path.read_text()
        data = tomllib.loads(text)
    except OSError as exc:
        raise SceneError(f"{path}: cannot read gains file: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML: {exc}") from None
    return _adaptive(_Reader(text, str(path)), data, (), scene.trajectory.bodies, scene.adaptive, gains_file=True)


def _check_trajectory(r, trajectory):
    """Every body must stay consistent (or degenerate) over the scene's time span; the parameters are computed in
    floats, so a body on the boundary (a plate, as written) may lie a rounding error outside it."""
    theta, _ = trajectory.theta(trajectory.times(201))
    verdicts = physical_consistency(theta, margins=False)
    rounding = (verdicts.mass > 0) & (verdicts.triangle_slack >= -RESOLUTION * EPS)
    bad = np.argwhere((verdicts.verdict == INVALID) | (verdicts.verdict == INCONSISTENT) & ~rounding)
    if bad.size:
        ti, body = bad[0]
        r.error(("load",), f"body {body + 1} becomes non-physical at t = {trajectory.times(201)[ti]:g}: "
                           f"{verdicts.reason(int(ti) * trajectory.bodies + int(body))}")


def load_scene(path):
    path = Path(path)
    try:
        text = read_text(path, "scene file")
    except InputError as exc:
        raise SceneError(str(exc)) from None
    return parse_scene(text, str(path))
