"""Errors that reach the user as one line naming the problem (exit status 2)."""

__all__ = ["InputError", "numbers"]


class InputError(ValueError):
    """Bad input: a file, a field or an argument that cannot be used."""


def numbers(value, where, shape=None):
    """A float array of finite numbers (of ``shape`` if given), or InputError naming ``where``."""
    import numpy as np

    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: not a list of numbers: {value!r}") from None
    if shape is not None and a.shape != tuple(shape):
        raise InputError(f"{where}: needs shape {tuple(shape)}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{where}: not finite: {a.tolist()}")
    return a
