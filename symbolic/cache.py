"""The on-disk cache of derivations, keyed by a hash of their inputs and of the code that derives them.

Entries live in ``cache_dir()/symbolic/<key>.pickle``. Polynomials of a jet
ring are stored as plain sparse term lists (SymPy's ring elements do not
pickle); SymPy expressions pickle as they are. A change to any module listed in
:data:`CODE` or to SymPy's version gives new keys, so stale entries are never read.
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import json
import pickle
from pathlib import Path

import sympy
from sympy.polys.domains import QQ
from sympy.polys.rings import PolyElement

from inertiaproof.suite.paths import cache_dir, cache_unwritable

__all__ = ["CODE", "code_version", "decode", "encode", "FORMAT", "key", "load", "store"]

FORMAT = 1
CODE = (  # the modules a derivation's result depends on
    "inertiaproof.symbolic.jets",
    "inertiaproof.symbolic.functions_of_time",
    "inertiaproof.symbolic.kinematics",
    "inertiaproof.symbolic.lagrangian",
    "inertiaproof.symbolic.robotics_equation",
    "inertiaproof.symbolic.properties",
    "inertiaproof.symbolic.systems",
    "inertiaproof.symbolic.derivations",
    "inertiaproof.symbolic.cache",
)


@functools.cache
def code_version():
    """sha256 of the source of every module in CODE, SymPy's version and the cache format.

    Read once per process, right after the derivation modules are imported, so
    that a process never files results of the code it runs under another version.
    """
    digest = hashlib.sha256(f"{FORMAT}:{sympy.__version__}".encode())
    for name in CODE:
        module = importlib.import_module(name)
        digest.update(name.encode())
        digest.update(Path(module.__file__).read_bytes())
    return digest.hexdigest()


def key(inputs):
    text = json.dumps({"inputs": inputs, "code": code_version()}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def _path(k):
    return cache_dir() / "symbolic" / f"{k}.pickle"


def encode(obj):
    if isinstance(obj, PolyElement):
        return ("jet", tuple((tuple((i, e) for i, e in enumerate(m) if e), int(c.numerator), int(c.denominator))
                             for m, c in obj.items()))
    if isinstance(obj, (tuple, list)):
        return ("seq", tuple(encode(x) for x in obj))
    if isinstance(obj, dict):
        return ("map", tuple((k, encode(v)) for k, v in obj.items()))
    return ("raw", obj)


def decode(obj, ring=None):
    tag, body = obj
    if tag == "jet":
        ngens = len(ring.gens)
        terms = {}
        for sparse, num, den in body:
            monom = [0] * ngens
            for i, e in sparse:
                monom[i] = e
            terms[tuple(monom)] = QQ(num, den)
        return ring.from_dict(terms) if terms else ring.zero
    if tag == "seq":
        return tuple(decode(x, ring) for x in body)
    if tag == "map":
        return {k: decode(v, ring) for k, v in body}
    return body


def load(k, ring=None):
    """The cached object under key k, or None (missing or unreadable entries count as missing)."""
    path = _path(k)
    try:
        return decode(pickle.loads(path.read_bytes()), ring)
    except (OSError, pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError, IndexError):
        return None


def store(k, obj):
    """File obj under key k; returns its path, or None when the cache cannot be written (said once on stderr: a
    read-only cache is read, never a reason for a check to fail)."""
    path = _path(k)
    tmp = path.with_suffix(f".{id(obj)}.tmp")
    data = pickle.dumps(encode(obj), protocol=pickle.HIGHEST_PROTOCOL)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp.write_bytes(data)
        tmp.replace(path)
    except OSError as exc:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        cache_unwritable(path.parent, exc)
        return None
    return path
