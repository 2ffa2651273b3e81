"""One memo for the prover's proofs and the values they rest on, keyed by the content of everything the value
depends on: the chain's content (:func:`inertiaproof.bounds.domain.chain_key`: every joint's kind, axis, fixed
transforms, coordinate map and limits) and every other input as its content (arrays by shape, dtype and bytes).
An earlier cache keyed without the joints' axes gave one chain another chain's sides; here two chains that differ
in any input are two keys.

Each kind of value (``"pivot"`` ladders, ``"perron"`` bounds, ``"fourier"`` coefficients) keeps its last ``SIZE``
keys; the same inputs give the same answer (each computation has its own seed), so the memo only saves work.
"""

from __future__ import annotations

import numpy as np

from .domain import chain_key

__all__ = ["SIZE", "clear", "content", "key_of", "memo", "size"]

SIZE = 32  # keys kept per kind of value: the oldest goes first
_ENTRIES = {}  # kind -> {key: value}, in insertion order


def content(x):
    """A hashable content key of one input: an array by its shape, dtype and bytes, a sequence item by item."""
    if isinstance(x, np.ndarray):
        return ("array", x.shape, x.dtype.str, np.ascontiguousarray(x).tobytes())
    if isinstance(x, (list, tuple)):
        return tuple(content(v) for v in x)
    return x


def key_of(chain, *inputs):
    """The content key of a value computed from ``chain`` and ``inputs``."""
    return (chain_key(chain),) + tuple(content(x) for x in inputs)


def memo(kind, chain, inputs, compute):
    """``compute()`` once per content of (``chain``, ``inputs``) for values of ``kind``."""
    entries = _ENTRIES.setdefault(kind, {})
    key = key_of(chain, *inputs)
    if key not in entries:
        if len(entries) >= SIZE:
            entries.pop(next(iter(entries)))
        entries[key] = compute()
    return entries[key]


def clear(kind=None):
    """Forget the values of ``kind`` (every kind when None)."""
    for k in list(_ENTRIES) if kind is None else [kind]:
        _ENTRIES.pop(k, None)


def size(kind):
    """How many values of ``kind`` are kept."""
    return len(_ENTRIES.get(kind, {}))
