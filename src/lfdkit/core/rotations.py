"""Unit quaternions: the orientation math every layer shares.

Quaternions are ``[x, y, z, w]`` (scalar last), the order of ROS messages and
of the ``qx, qy, qz, qw`` columns of a demonstrations file; arrays have shape
``(n, 4)``. ``q`` and ``-q`` are the same rotation: functions that compare or
average orientations pick signs themselves.

* :func:`check_quaternions`: validation (finite, unit norm within
  :data:`UNIT_NORM_TOLERANCE`, then normalised exactly);
* :func:`multiply`, :func:`conjugate`, :func:`log`, :func:`exp` (the
  logarithmic and exponential maps between unit quaternions and rotation
  vectors / 2), :func:`angle_between` (geodesic distance in radians);
* :func:`slerp`, :func:`continuous` (signs flipped so consecutive quaternions
  are on the same hemisphere);
* :func:`matrix_from_quaternion`, :func:`quaternion_from_matrix`;
* :func:`heading` (the turn about +z of the rotated x axis: a tool's heading
  on the table, a task frame's angle in a planar import);
* :func:`mean_quaternion` (Markley et al. 2007: the eigenvector of the largest
  eigenvalue of ``sum w_i q_i q_iᵀ``, the rotation minimising the weighted
  squared chordal distances) and :func:`robust_mean_quaternion` (the same,
  iteratively reweighted by the geodesic distance to the current mean with
  the redescending weight of Mean-Path's adaptive centre: 1 within 4 robust
  scales, falling smoothly to 0 at 8).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = [
    "MAX_ROTATION_ANGLE",
    "UNIT_NORM_TOLERANCE",
    "angle_between",
    "check_quaternions",
    "conjugate",
    "continuous",
    "exp",
    "heading",
    "log",
    "matrix_from_quaternion",
    "mean_quaternion",
    "multiply",
    "quaternion_from_matrix",
    "robust_mean_quaternion",
    "slerp",
    "stable_norm",
]

#: A quaternion whose norm differs from 1 by more than this is refused, not normalised
#: (it is not an orientation that was merely rounded).
UNIT_NORM_TOLERANCE = 1e-3

#: Robust mean: full weight within this many robust scales of the mean, none beyond _OUTER.
_CORE = 4.0
_OUTER = 8.0


#: Largest rotation angle (rad) accepted as a rotation vector's norm: beyond it the
#: spacing of float64 numbers exceeds 1e-7 rad, so the angle modulo 2π is noise.
MAX_ROTATION_ANGLE = 1e9


def stable_norm(x: Any, axis: int = -1, *, keepdims: bool = False) -> np.ndarray:
    """Euclidean norm along ``axis`` that neither overflows nor underflows.

    Each vector is divided by its largest absolute component before the sum of
    squares (``[1e200, 0, 0, 1e200]`` has norm ``1.41e200``, not inf; ``1e-200``
    components give ``1e-200``, not 0). Zero vectors have norm 0.
    Every quaternion and rotation vector in lfdkit is normalised with it.
    """
    x = np.asarray(x, dtype=np.float64)
    scale = np.max(np.abs(x), axis=axis, keepdims=True)
    safe = np.where(scale > 0, scale, 1.0)
    norm = safe * np.sqrt(np.sum((x / safe) ** 2, axis=axis, keepdims=True))
    norm = np.where(scale > 0, norm, 0.0)
    return norm if keepdims else np.squeeze(norm, axis=axis)


def check_quaternions(value: Any, name: str, *, n: int | None = None) -> np.ndarray:
    """Unit quaternions ``[x, y, z, w]`` as a float64 array of shape (n, 4), normalised.

    Parameters
    ----------
    value : array_like, shape (n, 4) or (4,)
        Quaternions, scalar last.
    name : str
        The argument's name, for the error message.
    n : int, optional
        The number of rows required.

    Returns
    -------
    ndarray, shape (n, 4)
        Each row divided by its norm.

    Raises
    ------
    ValueError
        If the shape is wrong, a value is NaN/inf, or a norm differs from 1 by
        more than :data:`UNIT_NORM_TOLERANCE` (the message names the row).
    """
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected numbers, shape (n, 4)") from None
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 4:
        raise ValueError(f"{name}: expected shape (n, 4) quaternions [x, y, z, w], got {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise ValueError(f"{name}: expected {n} quaternions, got {arr.shape[0]}")
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        raise ValueError(f"{name}: row {int(np.argmax(bad))} is not finite (NaN or inf)")
    norm = stable_norm(arr, axis=1)
    off = np.abs(norm - 1.0) > UNIT_NORM_TOLERANCE
    if off.any():
        j = int(np.argmax(off))
        raise ValueError(
            f"{name}: row {j} has norm {norm[j]:.6g}; a unit quaternion's norm is 1 "
            f"(within {UNIT_NORM_TOLERANCE:g})"
        )
    return arr / norm[:, None]


def multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products ``a ⊗ b`` (broadcast over leading axes), shape (..., 4)."""
    ax, ay, az, aw = np.moveaxis(np.asarray(a, dtype=np.float64), -1, 0)
    bx, by, bz, bw = np.moveaxis(np.asarray(b, dtype=np.float64), -1, 0)
    return np.stack(
        (
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ),
        axis=-1,
    )


def conjugate(q: np.ndarray) -> np.ndarray:
    """The inverse rotation of each unit quaternion, shape (..., 4)."""
    out = np.array(q, dtype=np.float64)
    out[..., :3] *= -1.0
    return out


def log(q: np.ndarray) -> np.ndarray:
    """Logarithmic map: ``θ/2 · axis`` of each unit quaternion, shape (..., 3).

    The sign is chosen with ``w >= 0``, so the result has norm at most π/2
    (the shortest rotation).
    """
    q = np.asarray(q, dtype=np.float64)
    q = np.where(q[..., 3:4] < 0.0, -q, q)
    v = q[..., :3]
    s = stable_norm(v, axis=-1)
    half = np.arctan2(s, q[..., 3])
    # half / s -> 1 as s -> 0 (series 1 + s²/6 ...): exact for the identity
    scale = np.where(s > 1e-12, half / np.where(s > 1e-12, s, 1.0), 1.0)
    return v * scale[..., None]


def exp(v: np.ndarray) -> np.ndarray:
    """Exponential map: the unit quaternion ``[sin|v| v/|v|, cos|v|]``, shape (..., 4)."""
    v = np.asarray(v, dtype=np.float64)
    n = stable_norm(v, axis=-1)
    sinc = np.where(n > 1e-12, np.sin(n) / np.where(n > 1e-12, n, 1.0), 1.0 - n * n / 6.0)
    return np.concatenate((v * sinc[..., None], np.cos(n)[..., None]), axis=-1)


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Geodesic distance between rotations (radians, 0 to π), broadcast over leading axes.

    ``4 atan2(|a − b|, |a + b|)`` with ``b``'s sign on ``a``'s hemisphere:
    accurate to rounding for tiny angles too (``2 arccos |a · b|`` loses half
    the digits there).
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    b = np.where(np.sum(a * b, axis=-1, keepdims=True) < 0.0, -b, b)
    return 4.0 * np.arctan2(np.linalg.norm(a - b, axis=-1), np.linalg.norm(a + b, axis=-1))


def continuous(q: np.ndarray) -> np.ndarray:
    """A copy with signs flipped so consecutive rows have a non-negative dot product."""
    out = np.array(q, dtype=np.float64)
    if len(out) > 1:
        flips = np.einsum("ij,ij->i", out[1:], out[:-1]) < 0.0
        sign = np.concatenate(([1.0], np.where(np.cumsum(flips) % 2 == 1, -1.0, 1.0)))
        out *= sign[:, None]
    return out


def slerp(q0: np.ndarray, q1: np.ndarray, t: Any) -> np.ndarray:
    """Spherical linear interpolation from ``q0`` (``t = 0``) to ``q1`` (``t = 1``).

    Broadcast over leading axes (``t`` of shape ``(...)``); the shorter arc is
    taken (``q1`` is flipped if ``q0 · q1 < 0``).
    """
    q0 = np.asarray(q0, dtype=np.float64)
    q1 = np.asarray(q1, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)[..., None]
    dot = np.sum(q0 * q1, axis=-1, keepdims=True)
    q1 = np.where(dot < 0.0, -q1, q1)
    dot = np.abs(dot)
    theta = np.arccos(np.clip(dot, -1.0, 1.0))
    sin = np.sin(theta)
    near = sin < 1e-9  # the same rotation: linear interpolation is exact to rounding
    safe = np.where(near, 1.0, sin)
    w0 = np.where(near, 1.0 - t, np.sin((1.0 - t) * theta) / safe)
    w1 = np.where(near, t, np.sin(t * theta) / safe)
    out = w0 * q0 + w1 * q1
    return out / stable_norm(out, axis=-1, keepdims=True)


def matrix_from_quaternion(q: np.ndarray) -> np.ndarray:
    """Rotation matrices of unit quaternions, shape (..., 3, 3)."""
    x, y, z, w = np.moveaxis(np.asarray(q, dtype=np.float64), -1, 0)
    return np.stack(
        (
            np.stack((1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)), -1),
            np.stack((2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)), -1),
            np.stack((2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)), -1),
        ),
        axis=-2,
    )


def heading(q: Any) -> np.ndarray:
    """The turn about +z of unit quaternions: where each rotation points the x axis on the xy plane.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Unit quaternions ``[x, y, z, w]``.

    Returns
    -------
    ndarray, shape (...)
        Angle (rad, in [-π, π], anticlockwise from +x) of the rotated x axis
        projected on the xy plane: a rotation about z alone by its own angle,
        in general the yaw of a z-y-x (yaw, pitch, roll) decomposition. NaN
        where that axis is within 1e-6 of vertical (it has no heading).
    """
    x, y, z, w = np.moveaxis(np.asarray(q, dtype=np.float64), -1, 0)
    # The rotation matrix's first column (matrix_from_quaternion's, to the bit).
    along, across = 1 - 2 * (y * y + z * z), 2 * (x * y + z * w)
    return np.where(np.hypot(along, across) < 1e-6, np.nan, np.arctan2(across, along))


def quaternion_from_matrix(R: np.ndarray) -> np.ndarray:
    """Unit quaternions ``[x, y, z, w]`` with ``w >= 0`` of rotation matrices (..., 3, 3).

    Each is computed from its largest component (Shepperd's method), so it is
    accurate for every rotation, including rotations by π.
    """
    R = np.asarray(R, dtype=np.float64)
    shape = R.shape[:-2]
    R = R.reshape(-1, 3, 3)
    trace = np.trace(R, axis1=1, axis2=2)
    cand = np.stack((R[:, 0, 0], R[:, 1, 1], R[:, 2, 2], trace), axis=1)
    k = np.argmax(cand, axis=1)
    q = np.empty((len(R), 4))
    for i in range(4):
        rows = k == i
        if not rows.any():
            continue
        r = R[rows]
        if i == 3:
            w = 0.5 * np.sqrt(1.0 + trace[rows])
            q[rows] = np.stack(
                (
                    (r[:, 2, 1] - r[:, 1, 2]) / (4 * w),
                    (r[:, 0, 2] - r[:, 2, 0]) / (4 * w),
                    (r[:, 1, 0] - r[:, 0, 1]) / (4 * w),
                    w,
                ),
                axis=1,
            )
        else:
            j, m = (i + 1) % 3, (i + 2) % 3
            big = 0.5 * np.sqrt(1.0 + r[:, i, i] - r[:, j, j] - r[:, m, m])
            part = np.empty((len(r), 4))
            part[:, i] = big
            part[:, j] = (r[:, j, i] + r[:, i, j]) / (4 * big)
            part[:, m] = (r[:, m, i] + r[:, i, m]) / (4 * big)
            part[:, 3] = (r[:, m, j] - r[:, j, m]) / (4 * big)
            q[rows] = part
    q = np.where(q[:, 3:4] < 0.0, -q, q)
    q /= stable_norm(q, axis=1, keepdims=True)
    return q.reshape((*shape, 4))


def mean_quaternion(q: np.ndarray, weights: Any = None, *, near: Any = None) -> np.ndarray:
    """The weighted mean rotation (Markley et al. 2007), shape (4,).

    The unit eigenvector of the largest eigenvalue of ``sum w_i q_i q_iᵀ``:
    the rotation minimising the weighted squared chordal distances
    ``||R - R_i||²``. Independent of the signs of the ``q_i``.

    Parameters
    ----------
    q : ndarray, shape (m, 4)
        Unit quaternions.
    weights : array_like, shape (m,), optional
        Non-negative weights (equal when omitted), not all zero.
    near : array_like, shape (4,), optional
        The sign of the result is chosen on ``near``'s hemisphere (else ``w >= 0``).
    """
    q = np.asarray(q, dtype=np.float64)
    w = np.ones(len(q)) if weights is None else np.asarray(weights, dtype=np.float64)
    M = np.einsum("i,ij,ik->jk", w, q, q)
    _, vectors = np.linalg.eigh(M)
    mean = vectors[:, -1]
    ref = np.array([0.0, 0.0, 0.0, 1.0]) if near is None else np.asarray(near, dtype=np.float64)
    return -mean if mean @ ref < 0.0 else mean


def robust_mean_quaternion(
    q: np.ndarray, weights: Any = None, *, near: Any = None, max_iter: int = 50
) -> tuple[np.ndarray, np.ndarray]:
    """A mean rotation that outlying rotations do not pull: iteratively reweighted Markley.

    Starts from the rotation of ``q`` with the smallest median geodesic
    distance to the others (a medoid, itself unmoved by a minority of
    outliers); each step weighs rotation ``i`` by the redescending weight of
    its geodesic distance ``d_i`` to the current mean in robust scales
    ``s = 1.4826 · median(d)`` (1 within 4 s, falling smoothly to 0 at 8 s;
    Mean-Path's adaptive centre) and takes the weighted Markley mean. Where
    no rotation is beyond 4 s this is the Markley mean. Where half the
    rotations coincide (``s = 0``) the result is that common rotation.

    Returns
    -------
    mean : ndarray, shape (4,)
    weights : ndarray, shape (m,)
        The final weights (0 for rotations given no say), times ``weights``.
    """
    q = np.asarray(q, dtype=np.float64)
    base = np.ones(len(q)) if weights is None else np.asarray(weights, dtype=np.float64)
    used = base > 0
    qs = q[used]
    if len(qs) <= 2:
        return mean_quaternion(q, base, near=near), base.copy()
    pair = angle_between(qs[:, None, :], qs[None, :, :])
    centre = qs[int(np.argmin(np.median(pair, axis=1)))]
    scale = 1.4826 * float(np.median(angle_between(qs, centre)))
    if scale <= 1e-15:  # half or more coincide: that rotation is the centre
        w = base * (angle_between(q, centre) <= 1e-12)
        return mean_quaternion(q, w, near=near if near is not None else centre), w
    w = base
    for _ in range(max_iter):
        z = angle_between(q, centre) / scale
        w = base * _redescending(z)
        new = mean_quaternion(q, w, near=centre)
        done = float(angle_between(new, centre)) < 1e-13
        centre = new
        if done:
            break
    if near is not None and centre @ np.asarray(near) < 0.0:
        centre = -centre
    return centre, w


def _redescending(z: np.ndarray) -> np.ndarray:
    """1 up to _CORE, a smooth (cosine) fall to 0 at _OUTER, 0 beyond."""
    u = np.clip((z - _CORE) / (_OUTER - _CORE), 0.0, 1.0)
    return 0.5 * (1.0 + np.cos(np.pi * u))
