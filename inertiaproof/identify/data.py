"""Samples of a robot's motion and torques from a CSV file (SI units: s, rad or m, rad/s or m/s, rad/s^2 or m/s^2,
N m or N).

Columns (a header row; order free): ``t``; per joint ``q_J``, ``tau_J`` and optionally ``qd_J`` and ``qdd_J``,
where J is the joint's number (1..n, the chain's order) or its name in the robot file. Either both velocities and
accelerations are given for every joint, or neither; without them they are derived by :func:`differentiate`:
q and tau pass the same zero-phase Butterworth low-pass filter (``scipy.signal.filtfilt``, order
:data:`FILTER_ORDER`, run forwards and backwards: no phase lag, a non-causal filter), then central differences
(``numpy.gradient``, second order inside) give qd from q and qdd from qd, and :func:`trim` samples are dropped at
each end, where the filter's start-up and the one-sided differences are. That needs t strictly increasing and
uniform to 1 % (every step within 1 % of the median step); given velocities need t strictly increasing only.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass

import numpy as np

from inertiaproof.errors import LARGEST, InputError, open_text

__all__ = ["FILTER_ORDER", "UNIFORM", "Samples", "differentiate", "joint_keys", "read_table", "samples"]

FILTER_ORDER = 4
UNIFORM = 0.01  # relative spread of the steps the filter accepts
KINDS = ("q", "qd", "qdd", "tau")


@dataclass(frozen=True)
class Samples:
    """Samples in the chain's joint order: t (S,), q, qd, qdd, tau (S, n); ``derived``: how qd and qdd were
    obtained (None: given), ``lines``: each sample's line in the file."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    derived: dict | None = None
    lines: np.ndarray | None = None
    path: str = ""

    @property
    def count(self):
        return len(self.t)

    def window(self, keep):
        """The samples where the boolean mask ``keep`` holds."""
        keep = np.asarray(keep, dtype=bool)
        return Samples(self.t[keep], self.q[keep], self.qd[keep], self.qdd[keep], self.tau[keep], self.derived,
                       None if self.lines is None else self.lines[keep], self.path)


def read_table(path):
    """(header, values (rows, columns), line of each row) of a CSV file of numbers; InputError naming file, line and
    column at the first cell that is not a finite number."""
    with open_text(path, "data file") as f:
        reader = csv.reader(f)
        try:
            header = [h.strip() for h in next(reader)]
        except StopIteration:
            raise InputError(f"{path}: empty file (a header row t, q_1, ..., tau_1, ... is needed)") from None
        if len(set(header)) != len(header):
            repeated = next(h for h in header if header.count(h) > 1)
            raise InputError(f"{path}: line 1: column {repeated!r} appears twice")
        rows, lines = [], []
        for row in reader:
            line = reader.line_num
            if not row or all(not cell.strip() for cell in row):
                continue
            if len(row) != len(header):
                raise InputError(f"{path}: line {line}: {len(row)} fields, the header has {len(header)}")
            try:
                values = [float(cell) for cell in row]
            except ValueError:
                k = next(k for k, cell in enumerate(row) if not _is_float(cell))
                raise InputError(f"{path}: line {line}, column {header[k]}: {row[k].strip()!r} is not a number") \
                    from None
            bad = [k for k, x in enumerate(values) if not (math.isfinite(x) and abs(x) <= LARGEST)]
            if bad:
                raise InputError(f"{path}: line {line}, column {header[bad[0]]}: {row[bad[0]].strip()} is not a "
                                 f"finite number of at most {LARGEST:g}")
            rows.append(values)
            lines.append(line)
    if not rows:
        raise InputError(f"{path}: no samples after the header")
    return header, np.array(rows), np.array(lines)


def _is_float(text):
    try:
        float(text)
    except ValueError:
        return False
    return True


def joint_keys(path, header):
    """The joints the header names, in its order: (keys, numbered) where keys are the J of its ``q_J`` columns and
    numbered says they are 1..n."""
    if "t" not in header:
        raise InputError(f"{path}: line 1: no column t (time, s)")
    keys = [h[2:] for h in header if h.startswith("q_")]
    if not keys:
        raise InputError(f"{path}: line 1: no columns q_1 ... (or q_<joint name>)")
    numbered = all(k.isdigit() for k in keys)
    if numbered and sorted(int(k) for k in keys) != list(range(1, len(keys) + 1)):
        raise InputError(f"{path}: line 1: numbered joints must be q_1 .. q_{len(keys)}")
    if numbered:
        keys = sorted(keys, key=int)
    for k in keys:
        if f"tau_{k}" not in header:
            raise InputError(f"{path}: line 1: column q_{k} has no tau_{k}")
    other = [h for h in header if h != "t" and h.partition("_")[0] not in KINDS]
    extra = [h for h in header if h.partition("_")[0] in KINDS and h.partition("_")[2] not in keys]
    if other or extra:
        raise InputError(f"{path}: line 1: column {(other + extra)[0]!r} is not t, q_J, qd_J, qdd_J or tau_J of a "
                         "joint J of the q columns")
    return keys, numbered


def trim(fs, cutoff):
    """Samples dropped at each end after filtering: two periods of the cut-off frequency, at least 2."""
    return max(2, math.ceil(2.0 * fs / cutoff))


def differentiate(t, q, tau, cutoff, path="", lines=None):
    """(t, q, qd, qdd, tau, keep, info) with qd, qdd from q by the module docstring's filter and differences, q and
    tau filtered alike, and ``keep`` the samples kept (the ends trimmed); ``info`` says what was done."""
    from scipy.signal import butter, filtfilt

    dt = np.diff(t)
    step = float(np.median(dt))
    off = np.abs(dt - step) > UNIFORM * step
    if np.any(off):
        k = int(np.argmax(off))
        where = f"line {lines[k + 1]}" if lines is not None else f"sample {k + 2}"
        raise InputError(f"{path}: {where}, column t: time step {dt[k]:.6g} s is not within {UNIFORM:.0%} of the median "
                         f"step {step:.6g} s (velocities and accelerations are derived only from uniform samples; "
                         "give qd_J and qdd_J columns otherwise)")
    fs = 1.0 / step
    if not 0 < cutoff < fs / 2:
        raise InputError(f"--cutoff {cutoff:g} Hz: must lie between 0 and the Nyquist frequency {fs / 2:.6g} Hz")
    edge = trim(fs, cutoff)
    if len(t) <= 2 * edge + 3 * (FILTER_ORDER + 1):
        raise InputError(f"{path}: {len(t)} samples are too few to filter at {cutoff:g} Hz ({edge} are dropped at "
                         "each end)")
    b, a = butter(FILTER_ORDER, cutoff / (fs / 2))
    qf = filtfilt(b, a, q, axis=0)
    tauf = filtfilt(b, a, tau, axis=0)
    qd = np.gradient(qf, t, axis=0)
    qdd = np.gradient(qd, t, axis=0)
    keep = np.zeros(len(t), dtype=bool)
    keep[edge:len(t) - edge] = True
    info = {"filter": f"zero-phase Butterworth low-pass of order {FILTER_ORDER} (scipy.signal.filtfilt) on q and "
                      "tau, then central differences (numpy.gradient)",
            "cutoff_hz": float(cutoff), "sampling_hz": fs, "trimmed_each_end": edge}
    return qf, qd, qdd, tauf, keep, info


def samples(path, header, values, lines, keys, cutoff=10.0):
    """The :class:`Samples` of a table whose joints ``keys`` are in the chain's order."""
    col = {h: values[:, k] for k, h in enumerate(header)}
    t = col["t"]
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        k = int(back[0]) + 1
        raise InputError(f"{path}: line {lines[k]}, column t: {t[k]:g} does not increase (previous {t[k - 1]:g})")
    q = np.stack([col[f"q_{k}"] for k in keys], -1)
    tau = np.stack([col[f"tau_{k}"] for k in keys], -1)
    given = [f"{kind}_{k}" in col for kind in ("qd", "qdd") for k in keys]
    if all(given):
        qd = np.stack([col[f"qd_{k}"] for k in keys], -1)
        qdd = np.stack([col[f"qdd_{k}"] for k in keys], -1)
        return Samples(t, q, qd, qdd, tau, None, lines, str(path))
    if any(given):
        missing = next(f"{kind}_{k}" for kind in ("qd", "qdd") for k in keys if f"{kind}_{k}" not in col)
        raise InputError(f"{path}: line 1: no column {missing}: give qd and qdd for every joint or for none")
    q, qd, qdd, tau, keep, info = differentiate(t, q, tau, cutoff, path, lines)
    return Samples(t[keep], q[keep], qd[keep], qdd[keep], tau[keep], info, lines[keep], str(path))
