"""UR-type arm kinematics (thesis §6.4, Table 6.3, eq. 6.1–6.2): forward, Jacobian, analytic IK.

Conventions
-----------
* The arm is an :class:`lfdkit.execute.arm.Arm` passed as ``arm=`` (default
  :data:`lfdkit.execute.arm.UR5`, the thesis's); this module holds no arm's numbers.
  Standard Denavit–Hartenberg parameters (``arm.d``, ``arm.a``, ``arm.alpha``); the
  link transform is ``T_{i-1}^i = Rot_z(θ_i) Trans_z(d_i) Trans_x(a_i) Rot_x(α_i)``
  and the flange pose is ``T_0^6 = T_0^1 … T_5^6``. Lengths are in metres, angles in
  radians.
* :func:`forward`, :func:`link_frames` and :func:`jacobian` take any DH table (``n``
  joints); the closed-form :func:`inverse` and everything built on it
  (:func:`nearest_solution`, :func:`inverse_path`, :func:`singularity`,
  :func:`branch`) need the UR joint structure (:attr:`~lfdkit.execute.arm.Arm.ur_type`:
  6 joints, the UR5's twists and zero entries), whatever its lengths: the UR10's
  table works as the UR5's does.
* Every function takes one configuration ``q`` of shape ``(6,)`` or a batch of shape
  ``(n, 6)`` (one pose ``(4, 4)`` or a batch ``(n, 4, 4)``) and answers with the same
  leading shape.
* An optional ``tool`` is the ``(4, 4)`` flange→tool transform (e.g. a brush's tool
  centre point); poses given to :func:`inverse` are then tool poses.
* Inputs are checked once, by the public function they enter; the arm only for its
  kind (:class:`~lfdkit.execute.arm.Arm` checked its own numbers when it was made).
  The default joint limits are ``arm.joint_limits``.

Inverse kinematics
------------------
:func:`inverse` returns all eight branches of the closed-form solution, ``(8, 6)`` per
pose, with a NaN row where a branch does not exist. The row index packs three bits,
``index = 4 * shoulder + 2 * wrist + elbow``:

* **shoulder** (bit 2): 0 when the wrist point ``o5`` (origin of frame 5) lies on the
  positive ``x1`` side of the plane spanned by the base axis ``z0`` and the shoulder
  axis ``z1``, i.e. ``a2 cos q2 + a3 cos(q2+q3) + d5 sin(q2+q3+q4) >= 0``; 1 otherwise.
* **wrist** (bit 1): 0 for ``sin q5 >= 0``, 1 for ``sin q5 < 0``.
* **elbow** (bit 0): 0 for ``sin q3 >= 0``, 1 for ``sin q3 < 0``.

:func:`branch` gives the index of a configuration, so ``inverse(forward(q))[branch(q)]``
is ``q`` (modulo 2π). Angles are wrapped to ``(-π, π]``; :func:`nearest_solution` adds
the ``±2π`` equivalents allowed by the joint limits.

Singularities
-------------
The Jacobian determinant of this geometry factors as
``det J = a2 a3 sin q3 sin q5 (a2 cos q2 + a3 cos(q2+q3) + d5 sin(q2+q3+q4))``, giving
three singularities, each measured by a number in ``[0, 1]`` that is 0 on it:

* **wrist**: ``|sin q5|`` — axes 4 and 6 parallel; only ``q4 ± q6`` is determined.
* **elbow**: ``|sin q3|`` — arm fully stretched or folded; the two elbow branches meet.
* **shoulder**: ``|x| / r``, with ``x`` the signed distance of the wrist point ``o5`` from
  the plane of ``z0`` and ``z1`` and ``r`` its distance from the base axis ``z0``
  (``r² = x² + d4²``). Because of the shoulder offset ``d4`` the wrist point
  can never lie *on* ``z0`` (as it would for an arm with a spherical wrist); the UR
  analogue is ``o5`` in the plane of ``z0`` and ``z1`` (``r = d4``), where the two
  shoulder branches meet.

At singular poses :func:`inverse` still returns the (coinciding) branches: at a shoulder
or elbow singularity pairs of rows are equal; at a wrist singularity ``q6`` is set to
``q6_hint`` (default 0) and ``q4`` absorbs the rest of the rotation. Call
:func:`singularity` on a configuration to learn which singularities it is near and the
Jacobian's smallest singular value; :func:`inverse_path` refuses to pass within its
tolerance of one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from lfdkit.execute.arm import UR5, Arm, check_arm

__all__ = [
    "SINGULARITY_TOL",
    "JointLimitError",
    "KinematicsError",
    "SingularityError",
    "SingularityReport",
    "UnreachableError",
    "branch",
    "forward",
    "inverse",
    "inverse_path",
    "jacobian",
    "link_frames",
    "nearest_solution",
    "singularity",
]


#: Default tolerance on the singularity measures (see :func:`singularity`).
SINGULARITY_TOL = 1e-2

_ORTHO_TOL = 1e-6  # accepted |R^T R - I| of an input rotation
_DOMAIN_EPS = 1e-10  # slack on asin/acos arguments, so stretched poses round-trip
_WRIST_EPS = 1e-12  # |sin q5| below which q6 is undetermined and set to the hint


# ------------------------------------------------------------------ errors
class KinematicsError(ValueError):
    """A pose or path the arm cannot follow.

    Attributes
    ----------
    index : int or None
        Index of the offending pose in a batch or path, ``None`` for a single pose.
    """

    def __init__(self, message: str, index: int | None = None) -> None:
        super().__init__(message)
        self.index = index


class UnreachableError(KinematicsError):
    """No joint configuration reaches the pose."""


class JointLimitError(KinematicsError):
    """Solutions exist but none lies within the joint limits."""


class SingularityError(KinematicsError):
    """A joint path passes (near) a singularity or flips branch.

    Attributes
    ----------
    index : int
        Index of the first offending pose of the path.
    kinds : tuple of str
        Singularities met (``"wrist"``, ``"shoulder"``, ``"elbow"``), empty for a jump.
    """

    def __init__(self, message: str, index: int, kinds: tuple[str, ...] = ()) -> None:
        super().__init__(message, index)
        self.kinds = kinds


# ------------------------------------------------------------------ input checks
def _as_float_array(value: Any, name: str, what: str) -> np.ndarray:
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected a numeric array of shape {what}") from exc


def _check_finite(arr: np.ndarray, name: str, batch: bool) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        where = f"{name}[{int(np.argwhere(bad)[0, 0])}]" if batch else name
        raise ValueError(f"{where}: contains NaN or an infinite value")


def _check_arm(arm: Any, *, analytic: bool = False) -> Arm:
    """Return ``arm`` after checking it is an :class:`Arm` (of UR type if ``analytic``).

    The description checked itself when it was made; only its kind is checked here.
    """
    arm = check_arm(arm)
    if analytic and not arm.ur_type:
        raise ValueError(
            f"arm: the analytic inverse kinematics needs a UR-type arm (6 joints, "
            f"a1 = a4 = a5 = a6 = 0, d2 = d3 = 0, alpha = (pi/2, 0, 0, pi/2, -pi/2, 0), "
            f"a2, a3 != 0, d4 > 0); {arm.name} is not one"
        )
    return arm


def _check_q(q: Any, arm: Arm, name: str = "q") -> np.ndarray:
    """Return ``q`` as float64 of shape (n_joints,) or (n, n_joints)."""
    j = arm.n_joints
    arr = _as_float_array(q, name, f"({j},) or (n, {j})")
    if arr.ndim not in (1, 2) or arr.shape[-1] != j:
        raise ValueError(f"{name}: expected shape ({j},) or (n, {j}) in radians, got {arr.shape}")
    _check_finite(arr, name, arr.ndim == 2)
    return arr


def _check_transform(pose: Any, name: str, *, allow_batch: bool = True) -> np.ndarray:
    """Return a rigid transform (4, 4) or batch (n, 4, 4) after checking it is one."""
    expected = "(4, 4) or (n, 4, 4)" if allow_batch else "(4, 4)"
    arr = _as_float_array(pose, name, expected)
    if arr.shape[-2:] != (4, 4) or arr.ndim not in ((2, 3) if allow_batch else (2,)):
        raise ValueError(f"{name}: expected shape {expected}, got {arr.shape}")
    batch = arr.ndim == 3
    flat = arr.reshape(-1, 4, 4)
    _check_finite(flat.reshape(len(flat), 16), name, batch)

    def label(i: int) -> str:
        return f"{name}[{i}]" if batch else name

    bottom = np.abs(flat[:, 3] - [0.0, 0.0, 0.0, 1.0]).max(axis=1, initial=0.0)
    if (bottom > _ORTHO_TOL).any():
        i = int(np.argmax(bottom > _ORTHO_TOL))
        raise ValueError(f"{label(i)}: bottom row must be [0, 0, 0, 1], got {flat[i, 3]}")
    rot = flat[:, :3, :3]
    err = np.abs(np.swapaxes(rot, 1, 2) @ rot - np.eye(3)).max(axis=(1, 2), initial=0.0)
    if (err > _ORTHO_TOL).any():
        i = int(np.argmax(err > _ORTHO_TOL))
        raise ValueError(
            f"{label(i)}: rotation part is not orthonormal "
            f"(max |R^T R - I| = {err[i]:.3g} > {_ORTHO_TOL:g})"
        )
    det = np.linalg.det(rot) if len(rot) else np.ones(0)
    if (det < 0).any():
        i = int(np.argmax(det < 0))
        raise ValueError(f"{label(i)}: rotation part is a reflection (determinant -1)")
    return arr


def _check_tool(tool: Any) -> np.ndarray | None:
    return None if tool is None else _check_transform(tool, "tool", allow_batch=False)


def _check_limits(limits: Any, arm: Arm) -> np.ndarray:
    """``limits`` as an array (n_joints, 2); ``None`` means the arm's joint limits."""
    if limits is None:
        return arm.joint_limits
    j = arm.n_joints
    arr = _as_float_array(limits, "limits", f"({j}, 2)")
    if arr.shape != (j, 2):
        raise ValueError(f"limits: expected shape ({j}, 2) of (lower, upper) rad, got {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError("limits: contains NaN or an infinite value")
    if (arr[:, 0] > arr[:, 1]).any():
        j = int(np.argmax(arr[:, 0] > arr[:, 1]))
        raise ValueError(f"limits: joint {j + 1} has lower {arr[j, 0]} > upper {arr[j, 1]}")
    return arr


# ------------------------------------------------------------------ helpers
def _wrap(angle: np.ndarray) -> np.ndarray:
    """Wrap angles to (-π, π]."""
    return np.pi - np.mod(np.pi - angle, 2 * np.pi)


def _rigid_inv(t: np.ndarray) -> np.ndarray:
    """Inverse of rigid transforms (..., 4, 4) without a general matrix inverse."""
    out = np.zeros_like(t)
    rt = np.swapaxes(t[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", rt, t[..., :3, 3])
    out[..., 3, 3] = 1.0
    return out


def _link(theta: np.ndarray, i: int, arm: Arm) -> np.ndarray:
    """Link transforms T_{i}^{i+1} (eq. 6.1) for joint ``i`` (0-based), shape (..., 4, 4)."""
    ct, st = np.cos(theta), np.sin(theta)
    ca, sa, a, d = arm.cos_alpha[i], arm.sin_alpha[i], arm.a[i], arm.d[i]
    t = np.zeros((*np.shape(theta), 4, 4))
    t[..., 0, 0], t[..., 0, 1], t[..., 0, 2], t[..., 0, 3] = ct, -ca * st, sa * st, a * ct
    t[..., 1, 0], t[..., 1, 1], t[..., 1, 2], t[..., 1, 3] = st, ca * ct, -sa * ct, a * st
    t[..., 2, 1], t[..., 2, 2], t[..., 2, 3] = sa, ca, d
    t[..., 3, 3] = 1.0
    return t


def _frames(q: np.ndarray, arm: Arm) -> np.ndarray:
    """T_0^0 … T_0^n for q (..., n), shape (..., n + 1, 4, 4)."""
    n = arm.n_joints
    out = np.empty((*q.shape[:-1], n + 1, 4, 4))
    out[..., 0, :, :] = np.eye(4)
    for i in range(n):
        out[..., i + 1, :, :] = out[..., i, :, :] @ _link(q[..., i], i, arm)
    return out


def _shoulder_x(q: np.ndarray, arm: Arm) -> np.ndarray:
    """Signed x1-coordinate of the wrist point o5 in frame 1, metres (UR-type arms)."""
    q2, q23, q234 = q[..., 1], q[..., 1] + q[..., 2], q[..., 1] + q[..., 2] + q[..., 3]
    return arm.a[1] * np.cos(q2) + arm.a[2] * np.cos(q23) + arm.d[4] * np.sin(q234)


# ------------------------------------------------------------------ forward kinematics
def forward(q: Any, *, tool: Any = None, arm: Arm = UR5) -> np.ndarray:
    """Flange (or tool) pose in the base frame (eq. 6.2).

    Parameters
    ----------
    q : array_like, shape (n_joints,) or (n, n_joints)
        Joint angles, radians (``arm.n_joints`` per configuration; 6 for a UR arm).
    tool : array_like, shape (4, 4), optional
        Flange→tool rigid transform (metres) appended to the flange pose.
    arm : Arm
        The arm; any DH table.

    Returns
    -------
    ndarray, shape (4, 4) or (n, 4, 4)
        Homogeneous transform base→flange (or base→tool); translation in metres.
    """
    arm = _check_arm(arm)
    q = _check_q(q, arm)
    tool = _check_tool(tool)
    t = _link(q[..., 0], 0, arm)
    for i in range(1, arm.n_joints):
        t = t @ _link(q[..., i], i, arm)
    return t if tool is None else t @ tool


def link_frames(q: Any, *, arm: Arm = UR5) -> np.ndarray:
    """Poses of all DH frames, ``T_0^0 = I``, ``T_0^1``, …, ``T_0^6`` (a UR arm).

    ``q`` and ``arm`` as in :func:`forward`.

    Returns
    -------
    ndarray, shape (7, 4, 4) or (n, 7, 4, 4)
        Frame ``k`` is the pose of DH frame ``k`` in the base frame (metres); joint
        ``k + 1`` turns about the ``z`` axis of frame ``k``. ``n_joints + 1`` frames.
    """
    arm = _check_arm(arm)
    return _frames(_check_q(q, arm), arm)


def jacobian(q: Any, *, tool: Any = None, arm: Arm = UR5) -> np.ndarray:
    """Geometric Jacobian at the flange (or the tool point), in the base frame.

    ``q``, ``tool`` and ``arm`` as in :func:`forward`; the tool's origin is the
    reference point of the linear rows.

    Returns
    -------
    ndarray, shape (6, 6) or (n, 6, 6)
        Rows ``(v_x, v_y, v_z, ω_x, ω_y, ω_z)``: linear velocity (m/s) of the reference
        point and angular velocity (rad/s) per unit joint speed (rad/s); columns are the
        joints (``arm.n_joints`` of them).
    """
    arm = _check_arm(arm)
    q = _check_q(q, arm)
    tool = _check_tool(tool)
    return _jacobian(q, tool, arm)


def _jacobian(q: np.ndarray, tool: np.ndarray | None, arm: Arm) -> np.ndarray:
    n = arm.n_joints
    frames = _frames(q, arm)
    end = frames[..., n, :, :] if tool is None else frames[..., n, :, :] @ tool
    z = frames[..., :n, :3, 2]  # joint axes, (..., n, 3)
    o = frames[..., :n, :3, 3]
    jv = np.cross(z, end[..., None, :3, 3] - o)
    return np.concatenate((np.swapaxes(jv, -1, -2), np.swapaxes(z, -1, -2)), axis=-2)


# ------------------------------------------------------------------ singularities
@dataclass(frozen=True)
class SingularityReport:
    """How close configurations are to the singularities of a UR-type arm.

    For one configuration every field is a Python ``bool``/``float``; for a batch of
    ``n`` it is an array of shape ``(n,)``.

    Attributes
    ----------
    wrist, shoulder, elbow : bool or ndarray of bool
        Whether the matching measure is below the tolerance.
    wrist_measure : float or ndarray
        ``|sin q5|`` (dimensionless); 0 when axes 4 and 6 are parallel.
    shoulder_measure : float or ndarray
        ``|x| / r``: distance of the wrist point ``o5`` from the plane of ``z0`` and
        ``z1`` over its distance from ``z0`` (dimensionless). It is ``cos ψ`` with
        ``sin ψ = d4 / r``; the shoulder solutions ``q1 = φ + ψ`` and ``φ + π - ψ``
        meet when it is 0.
    elbow_measure : float or ndarray
        ``|sin q3|`` (dimensionless); 0 with the arm stretched or folded.
    sigma_min : float or ndarray
        Smallest singular value of :func:`jacobian` (mixed units: m/rad for the linear
        rows, 1 for the angular rows); 0 exactly at a singularity.
    tol : float
        Tolerance the flags were computed with.
    """

    wrist: Any
    shoulder: Any
    elbow: Any
    wrist_measure: Any
    shoulder_measure: Any
    elbow_measure: Any
    sigma_min: Any
    tol: float

    @property
    def any(self) -> Any:
        """Whether any singularity is near (bool, or ndarray of bool for a batch)."""
        return self.wrist | self.shoulder | self.elbow

    @property
    def kinds(self) -> tuple[str, ...] | list[tuple[str, ...]]:
        """Names of the near singularities, a subset of ``("wrist", "shoulder", "elbow")``.

        A tuple for one configuration, a list of tuples for a batch.
        """
        flags = np.broadcast_arrays(self.wrist, self.shoulder, self.elbow)
        names = ("wrist", "shoulder", "elbow")
        rows = [
            tuple(n for n, f in zip(names, fs, strict=True) if f)
            for fs in zip(*(np.atleast_1d(f) for f in flags), strict=True)
        ]
        return rows[0] if np.ndim(self.wrist) == 0 else rows


def singularity(
    q: Any, *, tol: float = SINGULARITY_TOL, tool: Any = None, arm: Arm = UR5
) -> SingularityReport:
    """Report which of the wrist, shoulder and elbow singularities ``q`` is near.

    Parameters
    ----------
    q : array_like, shape (6,) or (n, 6)
        Joint angles, radians.
    tol : float
        A singularity is "near" when its measure (see :class:`SingularityReport`) is
        below ``tol``; ``1e-2`` is about 0.6° from it for the wrist and elbow.
    tool : array_like, shape (4, 4), optional
        Reference point for ``sigma_min`` (the flags do not depend on it).
    arm : Arm
        A UR-type arm (:attr:`lfdkit.execute.arm.Arm.ur_type`).

    Returns
    -------
    SingularityReport
    """
    arm = _check_arm(arm, analytic=True)
    q = _check_q(q, arm)
    tool = _check_tool(tool)
    if not (np.isfinite(tol) and tol >= 0):
        raise ValueError(f"tol: must be finite and >= 0, got {tol!r}")
    return _singularity(q, float(tol), tool, arm)


def _measures(q: np.ndarray, arm: Arm) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    x = _shoulder_x(q, arm)
    # r = distance of o5 from z0 is hypot(x, d4) >= d4 > 0, so this never divides by 0.
    shoulder = np.abs(x) / np.hypot(x, arm.d[3])
    return np.abs(np.sin(q[..., 4])), shoulder, np.abs(np.sin(q[..., 2]))


def _singularity(q: np.ndarray, tol: float, tool: np.ndarray | None, arm: Arm) -> SingularityReport:
    wm, sm, em = _measures(q, arm)
    sigma = np.linalg.svd(_jacobian(q, tool, arm), compute_uv=False)[..., -1]

    def out(v: np.ndarray) -> Any:
        return v.item() if v.ndim == 0 else v

    return SingularityReport(
        wrist=out(wm < tol),
        shoulder=out(sm < tol),
        elbow=out(em < tol),
        wrist_measure=out(wm),
        shoulder_measure=out(sm),
        elbow_measure=out(em),
        sigma_min=out(sigma),
        tol=tol,
    )


def branch(q: Any, *, arm: Arm = UR5) -> int | np.ndarray:
    """Branch index of configurations, as used for the rows of :func:`inverse`.

    Parameters
    ----------
    q : array_like, shape (6,) or (n, 6)
        Joint angles, radians.
    arm : Arm
        A UR-type arm.

    Returns
    -------
    int or ndarray of int, shape (n,)
        ``4 * shoulder + 2 * wrist + elbow`` with ``shoulder = x < 0`` (``x`` the
        signed x1-coordinate of the wrist point, see the module notes),
        ``wrist = sin q5 < 0`` and ``elbow = sin q3 < 0``.
    """
    arm = _check_arm(arm, analytic=True)
    q = _check_q(q, arm)
    shoulder = _shoulder_x(q, arm) < 0
    idx = (4 * shoulder + 2 * (np.sin(q[..., 4]) < 0) + (np.sin(q[..., 2]) < 0)).astype(int)
    return int(idx) if idx.ndim == 0 else idx


# ------------------------------------------------------------------ inverse kinematics
def _ik(
    flange: np.ndarray, q6_hint: np.ndarray, arm: Arm
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """All eight IK branches of flange poses (n, 4, 4) of a UR-type arm.

    Returns the solutions (n, 8, 6) with NaN rows, the distance ``r`` (n,) of the wrist
    point from the base axis and the elbow spans ``L`` (n, 2, 2) per shoulder/wrist
    branch (NaN where the shoulder branch does not exist).
    """
    n = len(flange)
    d4, d6, a2, a3 = arm.d[3], arm.d[5], arm.a[1], arm.a[2]
    rot, p = flange[:, :3, :3], flange[:, :3, 3]
    p5 = p - d6 * rot[:, :, 2]  # wrist point: origin of frame 5
    r = np.hypot(p5[:, 0], p5[:, 1])
    phi = np.arctan2(p5[:, 1], p5[:, 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        # o5 lies d4 along z1 = (sin q1, -cos q1, 0) from the plane of z0 and x1:
        # r sin(q1 - phi) = d4, two roots when r > d4.
        ratio = d4 / r
        psi = np.arcsin(np.minimum(ratio, 1.0))
        q1 = np.stack((phi + psi, phi + np.pi - psi), axis=1)  # (n, 2)
        q1[ratio > 1.0 + _DOMAIN_EPS] = np.nan

        # z1 seen from the flange is (s5 c6, -s5 s6, c5).
        z1 = np.stack((np.sin(q1), -np.cos(q1), np.zeros_like(q1)), axis=-1)  # (n, 2, 3)
        u = np.einsum("nji,nsj->nsi", rot, z1)
        s5 = np.hypot(u[..., 0], u[..., 1])  # |sin q5|, accurate near 0 unlike acos
        q5p = np.arctan2(s5, u[..., 2])
        q5 = np.stack((q5p, -q5p), axis=2)  # (n, 2 shoulder, 2 wrist)
        q6 = np.stack((np.arctan2(-u[..., 1], u[..., 0]), np.arctan2(u[..., 1], -u[..., 0])), 2)
        free = np.broadcast_to((s5 < _WRIST_EPS)[..., None], q6.shape)
        q6 = np.where(free, np.broadcast_to(q6_hint[:, None, None], q6.shape), q6)

        # Planar 3R problem for joints 2-4 in frame 1: T_1^4 = (T_0^1)^-1 T_0^6 (T_4^6)^-1.
        t46 = _link(q5, 4, arm) @ _link(q6, 5, arm)
        t14 = _rigid_inv(_link(q1, 0, arm))[:, :, None] @ flange[:, None, None] @ _rigid_inv(t46)
        px, py = t14[..., 0, 3], t14[..., 1, 3]
        q234 = np.arctan2(t14[..., 1, 0], t14[..., 0, 0])
        span2 = px**2 + py**2
        c3 = (span2 - a2**2 - a3**2) / (2 * a2 * a3)
        q3p = np.arccos(np.clip(c3, -1.0, 1.0))
        q3p[np.abs(c3) > 1.0 + _DOMAIN_EPS] = np.nan
        q3 = np.stack((q3p, -q3p), axis=-1)  # (n, 2, 2, 2 elbow)
        q2 = np.arctan2(py, px)[..., None] - np.arctan2(a3 * np.sin(q3), a2 + a3 * np.cos(q3))
        q4 = q234[..., None] - q2 - q3

    shape = (n, 2, 2, 2)
    sols = np.stack(
        [
            np.broadcast_to(q1[:, :, None, None], shape),
            q2,
            q3,
            q4,
            np.broadcast_to(q5[..., None], shape),
            np.broadcast_to(q6[..., None], shape),
        ],
        axis=-1,
    ).reshape(n, 8, 6)
    sols = _wrap(sols)
    sols[np.isnan(sols).any(axis=-1)] = np.nan
    return sols, r, np.sqrt(span2)


def _unreachable_reason(pose: np.ndarray, r: float, spans: np.ndarray, arm: Arm) -> str:
    pos = ", ".join(f"{v:.4g}" for v in pose[:3, 3])
    head = f"unreachable (position ({pos}) m)"
    d4 = arm.d[3]
    if not r >= d4 * (1.0 - _DOMAIN_EPS):
        return (
            f"{head}: too close to the base axis; the wrist point (flange minus d6 along "
            f"the tool z-axis) is {r:.4g} m from z0, inside the shoulder offset "
            f"d4 = {d4} m"
        )
    a2, a3 = abs(arm.a[1]), abs(arm.a[2])
    lo, hi = abs(a2 - a3), a2 + a3  # the elbow's span, metres
    spans = spans[np.isfinite(spans)]
    if (spans > hi).all():
        return (
            f"{head}: too far; the elbow would have to span at least {spans.min():.4g} m "
            f"between shoulder and wrist, more than |a2| + |a3| = {hi:.5g} m"
        )
    if (spans < lo).all():
        return (
            f"{head}: too close to the shoulder; the elbow would have to span at most "
            f"{spans.max():.4g} m, less than ||a2| - |a3|| = {lo:.5g} m"
        )
    listed = ", ".join(f"{s:.4g}" for s in spans)
    return (
        f"{head}: for no shoulder/wrist branch can the elbow span the shoulder-to-wrist "
        f"distance ({listed} m; the elbow spans [{lo:.5g}, {hi:.5g}] m)"
    )


def _flange_poses(pose: Any, name: str, tool: np.ndarray | None) -> np.ndarray:
    pose = _check_transform(pose, name)
    flat = pose.reshape(-1, 4, 4)
    return flat if tool is None else flat @ _rigid_inv(tool)


def _hint(q6_hint: Any, n: int) -> np.ndarray:
    hint = _as_float_array(q6_hint, "q6_hint", "() or (n,)")
    if hint.ndim > 1 or (hint.ndim == 1 and hint.shape != (n,)):
        raise ValueError(f"q6_hint: expected a scalar or shape ({n},), got {hint.shape}")
    if not np.isfinite(hint).all():
        raise ValueError("q6_hint: contains NaN or an infinite value")
    return np.broadcast_to(hint, (n,))


def inverse(
    pose: Any, *, tool: Any = None, q6_hint: Any = 0.0, strict: bool = True, arm: Arm = UR5
) -> np.ndarray:
    """All closed-form inverse kinematics solutions of a flange (or tool) pose.

    Parameters
    ----------
    pose : array_like, shape (4, 4) or (n, 4, 4)
        Target pose(s) in the base frame; translation in metres. The rotation part must
        be orthonormal to 1e-6.
    tool : array_like, shape (4, 4), optional
        Flange→tool transform; ``pose`` is then the tool pose.
    q6_hint : float or array_like, shape (n,)
        Value of ``q6`` (rad) at a wrist singularity, where only ``q4 + q6`` (or
        ``q4 - q6``) is determined; ``q4`` takes the rest.
    strict : bool
        Raise :class:`UnreachableError` for a pose with no solution (the first one, for
        a batch). With ``False`` such a pose gets eight NaN rows.
    arm : Arm
        A UR-type arm (:attr:`lfdkit.execute.arm.Arm.ur_type`).

    Returns
    -------
    ndarray, shape (8, 6) or (n, 8, 6)
        Joint angles (rad) wrapped to ``(-π, π]``; row ``4 * shoulder + 2 * wrist +
        elbow`` (see the module notes and :func:`branch`), NaN where that branch does
        not exist. At a shoulder or elbow singularity pairs of rows coincide.

    Raises
    ------
    UnreachableError
        If ``strict`` and no branch reaches a pose: the wrist point is within ``d4`` of
        the base axis, or the elbow cannot span the shoulder-to-wrist distance. (The
        wrist can always orient the flange once the position is reached.)
    """
    arm = _check_arm(arm, analytic=True)
    tool = _check_tool(tool)
    flange = _flange_poses(pose, "pose", tool)
    batch = np.ndim(pose) == 3
    sols = _solve(flange, _hint(q6_hint, len(flange)), batch, strict, arm)
    return sols if batch else sols[0]


def _solve(flange: np.ndarray, hint: np.ndarray, batch: bool, strict: bool, arm: Arm) -> np.ndarray:
    """:func:`_ik` raising :class:`UnreachableError` (if ``strict``) for argument ``pose``."""
    sols, r, spans = _ik(flange, hint, arm)
    if strict:
        none = np.isnan(sols).all(axis=(1, 2))
        if none.any():
            i = int(np.argmax(none))
            where = f"pose[{i}]" if batch else "pose"
            raise UnreachableError(
                f"{where}: {_unreachable_reason(flange[i], r[i], spans[i], arm)}",
                i if batch else None,
            )
    return sols


def _nearest(
    cands: np.ndarray, q_ref: np.ndarray, limits: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Nearest limit-respecting equivalents of candidate solutions.

    cands (..., k, 6) wrapped angles (NaN rows allowed), q_ref (..., 6). Returns the best
    (..., 6) (NaN if none) and a flag (...,) saying whether any solution existed at all.
    """
    two_pi = 2 * np.pi
    lo, hi = limits[:, 0], limits[:, 1]
    with np.errstate(invalid="ignore"):
        # Per joint the ±2π shift can be chosen independently: the distance is monotone
        # in each joint's difference.
        k_lo, k_hi = np.ceil((lo - cands) / two_pi), np.floor((hi - cands) / two_pi)
        k = np.clip(np.round((q_ref[..., None, :] - cands) / two_pi), k_lo, k_hi)
        shifted = cands + two_pi * k
        ok = (k_lo <= k_hi).all(axis=-1) & ~np.isnan(cands).any(axis=-1)
        diff = np.abs(shifted - q_ref[..., None, :])
        max_abs = np.where(ok, diff.max(axis=-1), np.inf)
        eucl = np.where(ok, np.sqrt((diff**2).sum(axis=-1)), np.inf)
    # Max-abs distance first, Euclidean distance to break ties.
    best = np.lexsort((eucl, max_abs), axis=-1)[..., 0]
    chosen = np.take_along_axis(shifted, best[..., None, None], axis=-2)[..., 0, :]
    found = np.take_along_axis(ok, best[..., None], axis=-1)[..., 0]
    chosen[~found] = np.nan
    return chosen, ~np.isnan(cands).all(axis=(-1, -2))


def nearest_solution(
    pose: Any, q_ref: Any, *, limits: Any = None, tool: Any = None, arm: Arm = UR5
) -> np.ndarray:
    """The inverse kinematics solution closest to a reference configuration.

    Every branch of :func:`inverse` and every ``±2π`` equivalent of its joints inside
    ``limits`` is a candidate; the winner minimises the largest single-joint move
    ``max_j |q_j - q_ref_j|`` (ties broken by the Euclidean joint distance). At a wrist
    singularity ``q6`` is taken from ``q_ref``.

    Parameters
    ----------
    pose : array_like, shape (4, 4) or (n, 4, 4)
        Target pose(s) in the base frame, metres.
    q_ref : array_like, shape (6,) or (n, 6)
        Reference configuration(s), radians (e.g. the current robot configuration).
    limits : array_like, shape (6, 2), optional
        ``(lower, upper)`` per joint, radians; by default ``arm.joint_limits``.
    tool : array_like, shape (4, 4), optional
        Flange→tool transform; ``pose`` is then the tool pose.
    arm : Arm
        A UR-type arm (:attr:`lfdkit.execute.arm.Arm.ur_type`).

    Returns
    -------
    ndarray, shape (6,) or (n, 6)
        Joint angles, radians, inside ``limits`` (not wrapped).

    Raises
    ------
    UnreachableError
        If no branch reaches a pose.
    JointLimitError
        If solutions exist but none lies within ``limits``.
    """
    arm = _check_arm(arm, analytic=True)
    tool = _check_tool(tool)
    limits = _check_limits(limits, arm)
    flange = _flange_poses(pose, "pose", tool)
    batch = np.ndim(pose) == 3
    q_ref = _check_q(q_ref, arm, "q_ref")
    if (q_ref.ndim == 2) != batch or (batch and len(q_ref) != len(flange)):
        raise ValueError(
            f"q_ref: expected shape {(len(flange), 6) if batch else (6,)} to match pose, "
            f"got {q_ref.shape}"
        )
    q_ref2 = q_ref.reshape(-1, 6)
    sols = _solve(flange, _wrap(q_ref2[:, 5]), batch, True, arm)
    best, _ = _nearest(sols, q_ref2, limits)
    bad = np.isnan(best).any(axis=-1)
    if bad.any():
        i = int(np.argmax(bad))
        where = f"pose[{i}]" if batch else "pose"
        raise JointLimitError(
            f"{where}: none of the {int((~np.isnan(sols[i, :, 0])).sum())} inverse "
            "kinematics solutions lies within limits",
            i if batch else None,
        )
    return best if batch else best[0]


def _raise_if_limits_cause_jump(
    cands: np.ndarray, q_prev: np.ndarray, limits: np.ndarray, max_step: float, i: int
) -> None:
    """Raise :class:`JointLimitError` if the jump at pose ``i`` is forced by the limits."""
    # Limits of ±π about q_prev hold each joint's nearest 2π equivalent: no real limit.
    free, _ = _nearest(cands, q_prev, q_prev[:, None] + np.array([-np.pi, np.pi]))
    if np.abs(free - q_prev).max() <= max_step:
        out = (free < limits[:, 0]) | (free > limits[:, 1])
        joints = ", ".join(str(j + 1) for j in np.flatnonzero(out))
        raise JointLimitError(
            f"poses[{i}]: the continuous branch leaves the joint limits (joint {joints}); "
            "the nearest solution within limits is a jump",
            i,
        )


def inverse_path(
    poses: Any,
    q_start: Any,
    *,
    max_step: float = 0.5,
    tol: float = SINGULARITY_TOL,
    limits: Any = None,
    tool: Any = None,
    arm: Arm = UR5,
) -> np.ndarray:
    """Joint path following a pose path on one continuous branch.

    Pose ``i`` gets the solution nearest (as in :func:`nearest_solution`) to the
    configuration of pose ``i - 1``; pose 0 gets the one nearest to ``q_start``, which
    thereby selects the branch (the move from ``q_start`` is not limited by
    ``max_step``).

    Parameters
    ----------
    poses : array_like, shape (n, 4, 4)
        Pose path in the base frame, metres.
    q_start : array_like, shape (6,)
        Configuration at (or near) the first pose, radians.
    max_step : float
        Largest accepted change of any joint between consecutive poses, radians. Set it
        from the sampling, e.g. ``arm.max_joint_speed.max() * dt``; a larger jump means a branch
        flip or a pass close to a singularity.
    tol : float
        Singularity tolerance, as in :func:`singularity`.
    limits : array_like, shape (6, 2), optional
        ``(lower, upper)`` per joint, radians; by default ``arm.joint_limits``.
    tool : array_like, shape (4, 4), optional
        Flange→tool transform; ``poses`` are then tool poses.
    arm : Arm
        A UR-type arm (:attr:`lfdkit.execute.arm.Arm.ur_type`).

    Returns
    -------
    ndarray, shape (n, 6)
        Joint angles, radians, inside ``limits`` (continuous, not wrapped).

    Raises
    ------
    UnreachableError
        Naming the index of the first pose no branch reaches.
    JointLimitError
        Naming the index of the first pose without a solution within ``limits``, or at
        which the continuous branch leaves them (so that staying inside would jump).
    SingularityError
        Naming the index of the first configuration within ``tol`` of a singularity or
        the first step in which a joint moves more than ``max_step``.
    """
    arm = _check_arm(arm, analytic=True)
    tool = _check_tool(tool)
    limits = _check_limits(limits, arm)
    poses_arr = _check_transform(poses, "poses")
    if poses_arr.ndim != 3 or len(poses_arr) == 0:
        raise ValueError(f"poses: expected shape (n, 4, 4) with n >= 1, got {poses_arr.shape}")
    q_prev = _check_q(q_start, arm, "q_start")
    if q_prev.ndim != 1:
        raise ValueError(f"q_start: expected shape (6,), got {q_prev.shape}")
    if not (np.isfinite(max_step) and max_step > 0):
        raise ValueError(f"max_step: must be finite and > 0, got {max_step!r}")
    if not (np.isfinite(tol) and tol >= 0):
        raise ValueError(f"tol: must be finite and >= 0, got {tol!r}")

    flange = poses_arr if tool is None else poses_arr @ _rigid_inv(tool)
    sols, r, spans = _ik(flange, np.zeros(len(flange)), arm)
    out = np.empty((len(flange), 6))
    names = ("wrist", "shoulder", "elbow")
    for i in range(len(flange)):
        q, exists = _nearest(sols[i], q_prev, limits)
        if not exists:
            raise UnreachableError(
                f"poses[{i}]: {_unreachable_reason(flange[i], r[i], spans[i], arm)}", i
            )
        if np.isnan(q).any():
            raise JointLimitError(
                f"poses[{i}]: no inverse kinematics solution lies within limits", i
            )
        measures = _measures(q, arm)
        kinds = tuple(nm for nm, m in zip(names, measures, strict=True) if m < tol)
        if kinds:
            detail = ", ".join(
                f"{nm} measure {m:.3g}" for nm, m in zip(names, measures, strict=True) if m < tol
            )
            raise SingularityError(
                f"poses[{i}]: the path passes within tol = {tol:g} of a "
                f"{'/'.join(kinds)} singularity ({detail})",
                i,
                kinds,
            )
        if i > 0:
            step = np.abs(q - q_prev)
            j = int(np.argmax(step))
            if step[j] > max_step:
                _raise_if_limits_cause_jump(sols[i], q_prev, limits, max_step, i)
                raise SingularityError(
                    f"poses[{i}]: joint {j + 1} jumps by {step[j]:.3g} rad from poses[{i - 1}], "
                    f"more than max_step = {max_step:g} (a branch flip: the path passes close "
                    "to a singularity or is sampled too coarsely)",
                    i,
                )
        out[i] = q
        q_prev = q
    return out
