"""Numbers and evidence values as the short text a person reads."""

from __future__ import annotations

import math

__all__ = ["is_quantity", "NON_FINITE", "number", "quantity", "ratio", "seconds", "to_float", "value"]

NON_FINITE = {"inf", "-inf", "nan"}


def is_quantity(x):
    return isinstance(x, dict) and "value" in x and isinstance(x.get("kind"), str)


def to_float(x):
    """A float for plotting, or None when x is not a finite number."""
    if is_quantity(x):
        x = x["value"]
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def number(x):
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
        if x == int(x) and abs(x) < 1e15:
            return str(int(x))
        return f"{x:.6g}"
    return str(x)


def value(x, limit=8):
    """A scalar, a short list or a matrix as text; a long list as its size and range."""
    if is_quantity(x):
        return quantity(x)
    if isinstance(x, list):
        flat = list(_flatten(x))
        if len(flat) <= limit or not all(_is_number(v) for v in flat):
            if len(flat) > limit:
                return f"{len(flat)} items: " + ", ".join(number(v) for v in flat[:limit]) + ", ..."
            return _nested(x)
        values = sorted(float(v) for v in flat)
        middle = values[len(values) // 2]
        return f"{len(values)} values: min {number(values[0])}, median {number(middle)}, max {number(values[-1])}"
    if x is None:
        return "none"
    return number(x)


def quantity(q):
    text = value(q["value"])
    return f"{text} {q['unit']}" if q.get("unit") else text


def seconds(s):
    s = to_float(s)
    if s is None:
        return "?"
    if s < 60:
        return f"{s:.2f} s"
    minutes, rest = divmod(s, 60)
    return f"{int(minutes)} min {rest:.0f} s"


def ratio(a, b):
    a, b = to_float(a), to_float(b)
    if a is None or b is None or b == 0:
        return "n/a"
    return f"{a / b:.3g}"


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _flatten(x):
    for v in x:
        if isinstance(v, list):
            yield from _flatten(v)
        else:
            yield v


def _nested(x):
    if isinstance(x, list):
        return "[" + ", ".join(_nested(v) for v in x) + "]"
    return number(x) if not isinstance(x, dict) else "{...}"
