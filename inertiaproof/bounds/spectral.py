"""Spectral functions of batched matrices (lambda_min, lambda_max, sigma_min, sigma_max) and their convexity."""

from __future__ import annotations

import numpy as np

__all__ = ["CONVEX", "spectral"]




def spectral(a, kind):
    """Spectral function of a batch (..., r, s): smax/smin (SVD), lmax/lmin/absmax (symmetric)."""
    if kind in ("smax", "smin"):
        s = np.linalg.svd(a, compute_uv=False)
        return s[..., 0] if kind == "smax" else s[..., -1]
    w = np.linalg.eigvalsh(a)
    if kind == "lmax":
        return w[..., -1]
    if kind == "lmin":
        return w[..., 0]
    return np.maximum(w[..., -1], -w[..., 0])


CONVEX = {"smax", "lmax", "absmax"}

