"""Mesh files (STL, OBJ, DAE, PLY, ...) read by trimesh into float64 vertices and faces, once per content hash.

The mesh is what trimesh reads: its float64 vertices (a binary STL's float32 values exactly; an OBJ's decimals
rounded to float64; a DAE's node transforms and ``<unit>`` applied by trimesh in float64) with coincident
vertices merged (``process=True``: merged vertices are some of the read ones, so their convex hull is inside the
read vertices' hull). From here on the vertices are exact dyadic rationals and every float step on a certified
side carries a stated bound. Per mesh, in its own coordinates (before the URDF ``scale``):

- fitness: ``watertight`` (every edge in exactly two faces), ``winding_consistent`` (each edge used once in each
  direction) and the signed volume V = sum_f det(a_f, b_f, c_f) / 6 with its rounding bound: each determinant in
  float64 (two products and a difference per cross-product entry, then a dot product) is within 4 u of
  sum |a_i| (|b_j c_k| + |b_k c_j|) (u = 2^-53, Higham's gamma_4 with room), the sum is ``math.fsum`` (correctly
  rounded: u |sum| more); the bound used is 2^-50 (|sum| + fsum of those terms), i.e. 8 u, over-covering both.
  A mesh is ``fit`` (a solid whose volume is V) when watertight, consistently wound and V exceeds its bound; its
  self-intersections are not checked (overlapping parts count twice: the volume is then too large, which only
  weakens the mass finding).
- for fit meshes, trimesh's uniform-density mass properties (centre, inertia per kg), for the repair.

:func:`read_mesh` caches by the SHA-256 of the file's bytes in this process (and the hash by path, size and
modification time), so a mesh named by many links and files is read once per process.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np

from .mesh_files import MeshUnread

__all__ = ["MeshSolid", "read_mesh", "signed_volume"]

U = 2.0**-53
BOUND = 2.0**-50  # 8 u: see the module
_BY_CONTENT = {}  # sha256 -> MeshSolid or MeshUnread
_BY_FILE = {}  # (path, size, mtime_ns) -> sha256


@dataclass(frozen=True)
class MeshSolid:
    """One mesh in its own coordinates (see the module)."""

    sha256: str
    vertices: np.ndarray  # (N, 3) float64, the merged vertices
    faces: int
    watertight: bool
    winding_consistent: bool
    signed_volume: float  # fsum of the determinants / 6
    volume_error: float  # bound on |signed_volume - exact signed volume of these vertices and faces|
    centre: np.ndarray | None = None  # uniform-density CoM (fit meshes)
    inertia_per_mass: np.ndarray | None = None  # uniform inertia about the centre per kg (fit meshes), (3, 3)
    hull: np.ndarray | None = None  # indices into ``vertices`` of hull vertices, hints (None: flat)

    @property
    def fit(self):
        return self.watertight and self.winding_consistent and self.signed_volume - self.volume_error > 0

    def fitness(self):
        """JSON-ready: what the mesh is fit for."""
        return {"vertices": len(self.vertices), "faces": self.faces, "watertight": self.watertight,
                "winding_consistent": self.winding_consistent, "signed_volume": self.signed_volume,
                "volume_error": self.volume_error, "fit": self.fit, "sha256": self.sha256}


def signed_volume(triangles):
    """(fsum-rounded sum_f det(a, b, c) / 6, its rounding bound) of (F, 3, 3) float64 triangles (see the module)."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    ab, bb, cb = np.abs(a), np.abs(b), np.abs(c)
    perm = ab[:, 0] * (bb[:, 1] * cb[:, 2] + bb[:, 2] * cb[:, 1]) + ab[:, 1] * (bb[:, 0] * cb[:, 2] + bb[:, 2] * cb[:, 0]) \
        + ab[:, 2] * (bb[:, 0] * cb[:, 1] + bb[:, 1] * cb[:, 0])
    total = math.fsum(det)
    error = BOUND * (abs(total) + math.fsum(perm))
    return total / 6, error / 6 * (1 + 4 * U) + 2.0**-1074


def _load(path, data):
    import trimesh

    suffix = path.suffix.lower().lstrip(".")
    try:
        import io

        mesh = trimesh.load(io.BytesIO(data), file_type=suffix, force="mesh", process=True)
    except Exception as exc:  # trimesh raises many kinds on files it cannot read
        raise MeshUnread(f"{path}: trimesh cannot read it: {type(exc).__name__}: {str(exc)[:200]}") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise MeshUnread(f"{path}: no triangles")
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    if not np.isfinite(vertices).all():
        raise MeshUnread(f"{path}: a vertex is not finite")
    faces = np.asarray(mesh.faces)
    used = vertices[np.unique(faces)]
    volume, error = signed_volume(vertices[faces])
    watertight, winding = bool(mesh.is_watertight), bool(mesh.is_winding_consistent)
    hull = _hull(used)
    solid = MeshSolid("", used, len(faces), watertight, winding, volume, error, hull=hull)
    if solid.fit:
        props = trimesh.triangles.mass_properties(vertices[faces], density=1.0)
        solid = MeshSolid("", used, len(faces), watertight, winding, volume, error,
                          np.asarray(props["center_mass"], float), np.asarray(props["inertia"], float) / props["volume"],
                          hull)
    return solid


def _hull(points):
    """A few vertices spanning the hull, as hints (every certified step uses all vertices): Qhull's hull vertices
    of the mesh, or of its extreme vertices along the 13 directions of a cube's axes, face and body diagonals and
    ``HINT_SAMPLE`` vertices drawn with a fixed seed when it has more; None when Qhull fails (flat)."""
    from scipy.spatial import ConvexHull, QhullError

    chosen = np.arange(len(points))
    if len(points) > HINT_SAMPLE:
        along = points @ DIAGONALS.T
        drawn = np.random.default_rng(0).choice(len(points), HINT_SAMPLE, replace=False)
        chosen = np.unique(np.concatenate([along.argmax(axis=0), along.argmin(axis=0), drawn]))
    try:
        return chosen[ConvexHull(points[chosen]).vertices]
    except (QhullError, ValueError):
        return None


HINT_SAMPLE = 3000
DIAGONALS = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, -1, 0], [1, 0, 1], [1, 0, -1], [0, 1, 1],
                      [0, 1, -1], [1, 1, 1], [1, 1, -1], [1, -1, 1], [-1, 1, 1]], float)


def read_mesh(path):
    """The :class:`MeshSolid` of a mesh file, read once per content (see the module); MeshUnread when it cannot be."""
    try:
        stat = path.stat()
        key = (str(path), stat.st_size, stat.st_mtime_ns)
        digest = _BY_FILE.get(key)
        if digest is None:
            data = path.read_bytes()
            digest = _BY_FILE[key] = hashlib.sha256(data + path.suffix.lower().encode()).hexdigest()
        else:
            data = None
    except OSError as exc:
        raise MeshUnread(f"{path}: cannot read: {exc.strerror}") from None
    found = _BY_CONTENT.get(digest)
    if found is None:
        try:
            found = _load(path, data if data is not None else path.read_bytes())
            found = MeshSolid(digest, *(getattr(found, f) for f in MeshSolid.__dataclass_fields__ if f != "sha256"))
        except MeshUnread as exc:
            found = exc
        _BY_CONTENT[digest] = found
    if isinstance(found, MeshUnread):
        raise found
    return found
