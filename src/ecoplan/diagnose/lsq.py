"""Bounded linear least squares on RMS-scaled columns: calibration's and the effects' fits.

Every linear fit of the diagnosis keeps its coefficients within physical bounds
(:func:`bounded_lstsq`); a pull towards a prior is rows stacked under the design
(:func:`ecoplan.diagnose.calibrate.envelope_penalty`).  One solver for both: calibration's
base model and the effects' refits of it treat bounds and unexcited columns alike.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_triangular
from scipy.optimize import lsq_linear

from ecoplan._typing import FloatArray

__all__ = ["bounded_lstsq"]


@dataclass(frozen=True)
class _Normal:
    """The normal equations of a least squares on RMS-scaled columns (k is small).

    Attributes
    ----------
    scale : ndarray, shape (k,)
        RMS of each column (1 for an all-zero column).
    gram : ndarray, shape (k, k)
        ``XsᵀXs`` of the scaled columns ``Xs``.
    rhs : ndarray, shape (k,)
        ``Xsᵀy``.
    ridge : float
        The tiny ridge of the plain solve (:func:`_lstsq`).
    """

    scale: FloatArray
    gram: FloatArray
    rhs: FloatArray
    ridge: float


def _normal(X: FloatArray, y: FloatArray) -> _Normal:
    """Normal equations of ``y ≈ X c`` on RMS-scaled columns.

    Forming ``XᵀX`` costs ``O(n k²)``, far less than an SVD of ``X``.  The plain solve adds a
    tiny ridge (1e-9 of the mean diagonal), which keeps a column the log does not excite from
    blowing up (its coefficient then stays near zero).
    """
    scale = np.sqrt(np.mean(X**2, axis=0))
    scale[scale < 1e-12] = 1.0
    Xs = X / scale
    gram = Xs.T @ Xs
    ridge = 1e-9 * max(float(np.trace(gram)), 1e-300) / max(gram.shape[0], 1)
    return _Normal(scale, gram, Xs.T @ y, ridge)


def _lstsq(X: FloatArray, y: FloatArray, ne: _Normal) -> FloatArray:
    """Least squares by the normal equations ``ne`` of ``y ≈ X c`` (:func:`_normal`)."""
    try:
        coef = np.linalg.solve(ne.gram + ne.ridge * np.eye(ne.gram.shape[0]), ne.rhs)
    except np.linalg.LinAlgError:
        coef = np.linalg.lstsq(X / ne.scale, y, rcond=1e-10)[0]
    return np.asarray(coef / ne.scale, dtype=np.float64)


def bounded_lstsq(X: FloatArray, y: FloatArray, lo: FloatArray, hi: FloatArray) -> FloatArray:
    """Least squares of ``y`` on ``X`` with every coefficient in ``[lo, hi]`` [coefficients].

    A column with ``lo == hi`` is held at that value; the others come from the plain solve
    (:func:`_lstsq`) when it lies within the bounds, else from
    :func:`scipy.optimize.lsq_linear` (bounded-variable least squares) on the Cholesky factor
    of the RMS-scaled columns' normal equations: the same problem, without the plain solve's
    tiny ridge, k x k instead of n x k (on the design itself when the factor does not exist).

    Parameters
    ----------
    X : ndarray, shape (n, k)
        Design.
    y : ndarray, shape (n,)
        Target.
    lo, hi : ndarray, shape (k,)
        Bounds (``-inf`` / ``inf`` for none; ``lo <= hi``).

    Returns
    -------
    ndarray
        Coefficients within the bounds.
    """
    fixed = lo >= hi
    coef = np.where(fixed, lo, 0.0)
    free = ~fixed
    if not np.any(free) or X.shape[0] == 0:
        return np.asarray(coef, dtype=np.float64)
    Xf = X[:, free]
    yf = y - X[:, fixed] @ coef[fixed]
    lf, hf = lo[free], hi[free]
    ne = _normal(Xf, yf)
    c = _lstsq(Xf, yf, ne)
    if np.any(c < lf) or np.any(c > hf):
        # ``|Xs c - y|² = |Lᵀ c - L⁻¹ Xsᵀ y|² + const`` with ``XsᵀXs = L Lᵀ`` (Cholesky): BVLS
        # solves the same problem on the k x k factor instead of the n x k design, whose
        # active-set steps each refactor it (on the wheeled hour of
        # ``benchmarks/diagnosis_speed.py`` 3 100 calls cost 16 s of 40)
        try:
            chol = np.linalg.cholesky(ne.gram)
            a, b = chol.T, solve_triangular(chol, ne.rhs, lower=True)
        except np.linalg.LinAlgError:
            a, b = Xf / ne.scale, yf
        res = lsq_linear(a, b, bounds=(lf * ne.scale, hf * ne.scale), method="bvls")
        c = np.clip(res.x / ne.scale, lf, hf)
    coef[free] = c
    return np.asarray(coef, dtype=np.float64)
