"""Tool poses for a UR robot: rotation vectors, pose vectors and headings (thesis §6.4).

The sweeping task's own poses (a brush at a fixed height) are
:func:`lfdkit.tasks.sweeping.scenarios.sweeping_poses`.

Conventions
-----------
* A *rotation vector* ``r = θ a`` is the rotation axis ``a`` (unit) scaled by
  the angle ``θ`` in radians (thesis eq. 6.3). UR controllers take a pose as
  ``p[x, y, z, rx, ry, rz]``: position in metres and orientation as a
  rotation vector, both in the robot base frame.
* A *pose matrix* ``T`` is the ``(4, 4)`` homogeneous transform of the tool
  frame in the base frame: ``T[:3, :3]`` is the rotation (columns are the tool
  axes in base coordinates), ``T[:3, 3]`` the position, ``T[3] = [0, 0, 0, 1]``.
* Functions are vectorised: a leading axis of ``n`` poses is accepted wherever
  a single one is, and the output keeps it.

Accuracy
--------
Eq. 6.3, ``θ = arccos((tr R − 1) / 2)`` and ``ω = vee(R − Rᵀ) / (2 sin θ)``,
loses half the digits near θ = 0 and θ = π (``arccos`` has an infinite slope
at ±1) and divides by ``sin θ → 0`` there. :func:`rotvec_from_matrix` instead
goes through the unit quaternion of :func:`lfdkit.core.rotations.quaternion_from_matrix`
(``[x, y, z, w]``, the one convention of lfdkit), taking its largest component from the
diagonal (Shepperd's method, so the axis at θ ≈ π comes from the symmetric
part of ``R``), and ``θ / sin(θ/2)`` from ``atan2`` with a series expansion
for tiny angles. Both directions are accurate to about 1e-15 for any angle.

Sign at θ = π
-------------
A rotation by exactly π has two rotation vectors, ``π a`` and ``−π a``.
:func:`rotvec_from_matrix` returns the one whose first axis component with
magnitude above ``1e-9`` is positive. Angles within ``1e-14`` rad of π count
as π: closer than that the sign of ``π − θ`` is below the rounding of the
matrix entries, so both vectors are equally good readings of the input.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lfdkit.core.geometry import point_tangents
from lfdkit.core.rotations import (
    MAX_ROTATION_ANGLE,
    check_quaternions,
    heading,
    quaternion_from_matrix,
    stable_norm,
)
from lfdkit.core.validation import check_finite, check_path

__all__ = [
    "matrix_from_rotvec",
    "path_yaw",
    "pose_matrix",
    "pose_vector",
    "rotvec_from_matrix",
    "unwrap_rotvecs",
    "yaw_from_quaternions",
]

_ROTATION_TOL = 1e-6  # accepted max |RᵀR − I| and |det R − 1|
_SMALL_ANGLE = 1e-4  # below this angle (rad), series expansions replace sin θ / θ etc.
_AT_PI = 1e-14  # |π − θ| below this counts as exactly π (sign convention applies)
_AXIS_SIGN_TOL = 1e-9  # axis components smaller than this are skipped by the sign rule


# --------------------------------------------------------------------------- #
# Validation
# --------------------------------------------------------------------------- #


def _as_float_array(value: Any, name: str, shape_text: str) -> np.ndarray:
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected a numeric array of shape {shape_text}") from exc


def _check_finite(arr: np.ndarray, name: str) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0])
        kind = "NaN" if np.isnan(arr[where]) else "an infinite value"
        raise ValueError(f"{name}: contains {kind} at index {where}")


def _check_stack(value: Any, name: str, tail: tuple[int, ...]) -> tuple[np.ndarray, bool]:
    """Read an array of shape ``tail`` or ``(n,) + tail``; return it stacked and whether single."""
    text = f"{tail} or (n, {', '.join(str(t) for t in tail)})"
    arr = _as_float_array(value, name, text)
    if arr.shape == tail:
        single = True
        arr = arr[None]
    elif arr.ndim == len(tail) + 1 and arr.shape[1:] == tail:
        single = False
    else:
        raise ValueError(f"{name}: expected shape {text}, got shape {arr.shape}")
    _check_finite(arr, name)
    return arr, single


def _check_rotations(R: np.ndarray, name: str, single: bool, part: str = "") -> None:
    """Raise unless every ``R[i]`` (shape (n, 3, 3)) is orthonormal with det +1 (tol 1e-6).

    ``part`` is appended to the argument name in messages, e.g. ``"[:3, :3]"``.
    """
    err = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(R)
    for i in np.flatnonzero((err > _ROTATION_TOL) | (np.abs(det - 1.0) > _ROTATION_TOL))[:1]:
        label = (name if single else f"{name}[{i}]") + part
        if err[i] > _ROTATION_TOL:
            raise ValueError(
                f"{label}: not a rotation matrix (columns not orthonormal: "
                f"max |R^T R - I| = {err[i]:.3g} > {_ROTATION_TOL:g})"
            )
        if abs(det[i] - 1.0) > _ROTATION_TOL:
            raise ValueError(
                f"{label}: not a rotation matrix (determinant {det[i]:.6g}, expected +1; "
                "a reflection or a left-handed frame?)"
            )


# --------------------------------------------------------------------------- #
# Rotation vectors
# --------------------------------------------------------------------------- #


def _skew(r: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``[r]×`` of shape (n, 3, 3) for ``r`` of shape (n, 3)."""
    k = np.zeros((*r.shape[:-1], 3, 3))
    k[..., 0, 1], k[..., 0, 2] = -r[..., 2], r[..., 1]
    k[..., 1, 0], k[..., 1, 2] = r[..., 2], -r[..., 0]
    k[..., 2, 0], k[..., 2, 1] = -r[..., 1], r[..., 0]
    return k


def _matrix_from_rotvec(r: np.ndarray) -> np.ndarray:
    """Rodrigues' formula ``I + A [r]× + B [r]×²`` for validated ``r`` of shape (n, 3)."""
    theta = stable_norm(r, axis=1)  # no overflow: |r| up to MAX_ROTATION_ANGLE is checked
    theta2 = theta * theta
    small = theta < _SMALL_ANGLE
    safe = np.where(small, 1.0, theta)
    # A = sin θ / θ, B = (1 − cos θ) / θ² = 2 (sin(θ/2) / θ)²: the half-angle form has
    # no cancellation; the series (error < θ⁴/120) avoids 0/0 at θ = 0.
    a = np.where(small, 1.0 - theta2 / 6.0, np.sin(safe) / safe)
    half = np.sin(0.5 * safe) / safe
    b = np.where(small, 0.5 - theta2 / 24.0, 2.0 * half * half)
    k = _skew(r)
    return np.eye(3) + a[:, None, None] * k + b[:, None, None] * (k @ k)


def _rotvec_from_matrix(R: np.ndarray) -> np.ndarray:
    """Rotation vectors (n, 3) of validated rotations (n, 3, 3); see the module notes."""
    q = quaternion_from_matrix(R)  # [x, y, z, w], w >= 0
    w, v = q[:, 3], q[:, :3]
    s = stable_norm(v, axis=1)  # sin(θ/2)
    at_pi = w <= 0.5 * _AT_PI  # w = cos(θ/2) ≈ (π − θ)/2
    w = np.where(at_pi, 0.0, w)
    small = s < 1e-6
    safe = np.where(small, 1.0, s)
    # θ / sin(θ/2) = 2 atan2(s, w) / s; series 2/w (1 − s²/(3w²)) for tiny s (w ≈ 1 there).
    w_safe = np.where(small, w, 1.0)
    scale = np.where(
        small,
        2.0 / w_safe * (1.0 - s * s / (3.0 * w_safe * w_safe)),
        2.0 * np.arctan2(s, w) / safe,
    )
    r = scale[:, None] * v
    if at_pi.any():
        # Sign convention at θ = π: first axis component above the tolerance is positive.
        rp = r[at_pi]
        first = np.argmax(np.abs(rp) > _AXIS_SIGN_TOL * np.pi, axis=1)
        sign = np.where(rp[np.arange(len(rp)), first] < 0, -1.0, 1.0)
        r[at_pi] = rp * sign[:, None]
    return r


def rotvec_from_matrix(R: Any) -> np.ndarray:
    """Rotation vector (axis × angle) of a rotation matrix, thesis eq. 6.3.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (n, 3, 3)
        Rotation matrices: orthonormal with determinant +1, to within 1e-6.

    Returns
    -------
    ndarray, shape (3,) or (n, 3)
        ``θ a`` in radians with ``θ ∈ [0, π]``. At θ = π the sign follows the
        rule in the module notes (first axis component above 1e-9 positive).

    Raises
    ------
    ValueError
        If the shape is wrong, a value is NaN/inf, or a matrix is not a rotation
        (the message names which one).
    """
    arr, single = _check_stack(R, "R", (3, 3))
    _check_rotations(arr, "R", single)
    r = _rotvec_from_matrix(arr)
    return r[0] if single else r


def matrix_from_rotvec(r: Any) -> np.ndarray:
    """Rotation matrix of a rotation vector (Rodrigues' formula).

    Parameters
    ----------
    r : array_like, shape (3,) or (n, 3)
        Rotation vectors ``θ a`` in radians; any norm (``|r| > π`` and unwrapped
        vectors are fine).

    Returns
    -------
    ndarray, shape (3, 3) or (n, 3, 3)
    """
    arr, single = _check_stack(r, "r", (3,))
    angle = stable_norm(arr, axis=1)
    if np.any(angle > MAX_ROTATION_ANGLE):
        j = int(np.argmax(angle > MAX_ROTATION_ANGLE))
        where = "" if single else f" (row {j})"
        raise ValueError(
            f"r: a rotation vector of norm {angle[j]:.3g} rad{where}; beyond "
            f"{MAX_ROTATION_ANGLE:g} rad a float64 cannot resolve the angle; reduce it modulo "
            "2π first"
        )
    R = _matrix_from_rotvec(arr)
    return R[0] if single else R


def unwrap_rotvecs(r: Any) -> np.ndarray:
    """Make a sequence of rotation vectors continuous.

    Every rotation has the rotation vectors ``(θ + 2πk) a`` for any integer
    ``k``; near θ = π the two shortest, ``θ a`` and ``(θ − 2π) a = r (1 −
    2π/|r|)``, are far apart although the rotations are close. A UR controller
    interpolates linearly between the rotation vectors of consecutive pose
    targets (thesis §6.4), so such a jump makes the tool spin about a full
    turn between two nearby poses. This picks, for each vector after the first,
    the equivalent one closest to its (already unwrapped) predecessor.

    Parameters
    ----------
    r : array_like, shape (n, 3)
        Rotation vectors in radians, one row per pose.

    Returns
    -------
    ndarray, shape (n, 3)
        Same rotations; the first row is unchanged, later rows may have norm
        above π. A zero vector (identity) following a vector of norm near 2π
        becomes ``2π`` times that vector's direction.
    """
    arr = check_path(r, "r", min_points=1, n_dims=3)
    out = arr.copy()
    for i in range(1, len(out)):
        prev = out[i - 1]
        theta = float(stable_norm(arr[i]))
        if theta > 0:
            axis = arr[i] / theta
        else:
            n_prev = float(stable_norm(prev))
            if n_prev == 0:
                continue
            axis = prev / n_prev
        # |prev − t a|² is smallest for t = prev·a: take θ + 2πk nearest to it.
        k = np.round((float(prev @ axis) - theta) / (2.0 * np.pi))
        out[i] = (theta + 2.0 * np.pi * k) * axis
    return out


# --------------------------------------------------------------------------- #
# Pose vectors
# --------------------------------------------------------------------------- #


def pose_vector(T: Any) -> np.ndarray:
    """UR pose vector ``[x, y, z, rx, ry, rz]`` of a homogeneous transform.

    Parameters
    ----------
    T : array_like, shape (4, 4) or (n, 4, 4)
        Tool poses in the base frame; the last row must be ``[0, 0, 0, 1]``
        and the rotation part a rotation (tolerance 1e-6).

    Returns
    -------
    ndarray, shape (6,) or (n, 6)
        Position in the units of ``T`` (metres for a UR robot) and rotation
        vector in radians (see :func:`rotvec_from_matrix`). Apply
        :func:`unwrap_rotvecs` to ``[:, 3:]`` before sending a sequence to a
        robot.
    """
    arr, single = _check_stack(T, "T", (4, 4))
    bottom = np.abs(arr[:, 3] - np.array([0.0, 0.0, 0.0, 1.0])).max(axis=1)
    if (bottom > _ROTATION_TOL).any():
        i = int(np.argmax(bottom > _ROTATION_TOL))
        label = "T" if single else f"T[{i}]"
        raise ValueError(f"{label}: last row must be [0, 0, 0, 1], got {arr[i, 3].tolist()}")
    _check_rotations(arr[:, :3, :3], "T", single, " rotation part")
    out = np.concatenate((arr[:, :3, 3], _rotvec_from_matrix(arr[:, :3, :3])), axis=1)
    return out[0] if single else out


def pose_matrix(p: Any) -> np.ndarray:
    """Homogeneous transform of a UR pose vector; the inverse of :func:`pose_vector`.

    Parameters
    ----------
    p : array_like, shape (6,) or (n, 6)
        ``[x, y, z, rx, ry, rz]``: position and rotation vector (radians).

    Returns
    -------
    ndarray, shape (4, 4) or (n, 4, 4)
    """
    arr, single = _check_stack(p, "p", (6,))
    T = np.zeros((len(arr), 4, 4))
    T[:, :3, :3] = _matrix_from_rotvec(arr[:, 3:])
    T[:, :3, 3] = arr[:, :3]
    T[:, 3, 3] = 1.0
    return T[0] if single else T


# --------------------------------------------------------------------------- #
# Headings on a plane
# --------------------------------------------------------------------------- #


def path_yaw(path: Any, *, yaw_offset: float = 0.0) -> np.ndarray:
    """Continuous heading of a planar path: the tool's yaw while sweeping along it.

    Parameters
    ----------
    path : array_like, shape (n, 2)
        Points on the table in the base frame (metres), at least 2, not all equal.
    yaw_offset : float
        Added to every heading (rad).

    Returns
    -------
    ndarray, shape (n,)
        Angle (rad, counter-clockwise about the base +z axis from +x) of the
        path tangent at each point (:func:`lfdkit.core.geometry.point_tangents`,
        the bisector of the adjacent segments) plus ``yaw_offset``. Unwrapped:
        consecutive values differ by the turning angle between the samples,
        never by a 2π jump, so a closed loop ends about ±2π from its start.

    Raises
    ------
    ValueError
        If the path is not ``(n, 2)``, has fewer than 2 points, contains
        NaN/inf, has zero length, or turns back exactly onto itself.
    """
    arr = check_path(path, "path", n_dims=2)
    offset = check_finite(yaw_offset, "yaw_offset")
    t = point_tangents(arr)
    return np.unwrap(np.arctan2(t[:, 1], t[:, 0])) + offset


def yaw_from_quaternions(quaternions: Any) -> np.ndarray:
    """The heading of demonstrated tool orientations: the yaw to sweep with.

    Parameters
    ----------
    quaternions : array_like, shape (n, 4)
        Tool orientations in the base frame, unit quaternions ``[x, y, z, w]``
        (a demonstrations file's ``qx, qy, qz, qw``, or
        :func:`lfdkit.mimic.rotation_mean.mean_orientations` along a path).

    Returns
    -------
    ndarray, shape (n,)
        Angle (rad, about the base +z axis from +x) of the tool x axis
        projected on the table, unwrapped: the ψ of
        :func:`lfdkit.tasks.sweeping.scenarios.sweeping_poses` (tool down or
        up alike), so ``sweeping_poses(path, yaw=...)`` holds
        the tool as demonstrated instead of along the path's tangent.

    Raises
    ------
    ValueError
        If a quaternion is NaN or not unit, or a tool x axis is vertical
        (no heading).
    """
    angles = heading(check_quaternions(quaternions, "quaternions"))
    flat = np.isnan(angles)
    if flat.any():
        raise ValueError(
            f"quaternions: row {int(np.argmax(flat))} points the tool x axis vertically; "
            "it has no heading on the table"
        )
    return np.unwrap(angles)
