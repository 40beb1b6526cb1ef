"""Arms from URDF files: a serial chain's kinematics and limits, read with the standard library.

A user's robot comes as a URDF (Franka, KUKA, xArm, UR e-Series: every vendor
ships one). :class:`UrdfArm` reads the chain from a base link to a tip link
and offers what :mod:`lfdkit.execute` needs from an arm, the same attributes as
the DH :class:`lfdkit.execute.arm.Arm` (``name``, ``n_joints``,
``joint_limits``, ``max_joint_speed``, ``max_joint_acceleration``) plus its
own kinematics (:meth:`UrdfArm.forward`, :meth:`UrdfArm.jacobian`); the
numerical inverse kinematics of :mod:`lfdkit.execute.kinematics` works on it.

Why the standard library's XML and not a kinematics library: a URDF chain is
a product of fixed transforms (``<origin xyz rpy>``) and joint motions
(rotation about, or translation along, ``<axis>``); 150 lines compute it
exactly, and lfdkit stays installable without a C++ stack. pinocchio (``pip
install pin``, the field's reference) is the independent check in the tests
when it is installed: forward kinematics agree to 1e-12 m. Meshes, inertias
and collision shapes are not read (MuJoCo reads them itself from the file).

Conventions: joint ``origin`` is ``Trans(xyz) · Rz(yaw) Ry(pitch) Rx(roll)``
as the URDF specification says; revolute and continuous joints turn (rad),
prismatic ones slide (m); fixed joints are folded into the next transform;
a continuous joint gets position limits ±2π. URDF gives joint speed limits
(``<limit velocity>``) but no acceleration limits: those are given, or
:data:`ACCELERATION_PER_SPEED` times the speed limit (the UR5's 15 rad/s² is
4.7 times its 3.2 rad/s), and :attr:`UrdfArm.guessed_acceleration` says so.
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np

from lfdkit.execute.arm import per_joint

__all__ = ["ACCELERATION_PER_SPEED", "UrdfArm"]

#: Acceleration limit per speed limit (1/s) when neither the URDF nor the caller gives one.
ACCELERATION_PER_SPEED = 5.0
_MOVING = ("revolute", "continuous", "prismatic")
_KNOWN = (*_MOVING, "fixed")


def _floats(text: str | None, n: int, where: str) -> np.ndarray:
    if text is None:
        return np.zeros(n)
    try:
        values = np.array([float(v) for v in text.split()], dtype=np.float64)
    except ValueError:
        raise ValueError(f"{where}: expected {n} numbers, got {text!r}") from None
    if values.shape != (n,) or not np.isfinite(values).all():
        raise ValueError(f"{where}: expected {n} finite numbers, got {text!r}")
    return values


def _origin(joint: ET.Element, where: str) -> np.ndarray:
    """A joint's ``<origin>`` as a 4x4 transform: Trans(xyz) Rz(y) Ry(p) Rx(r)."""
    element = joint.find("origin")
    xyz = _floats(None if element is None else element.get("xyz"), 3, f"{where} origin xyz")
    rpy = _floats(None if element is None else element.get("rpy"), 3, f"{where} origin rpy")
    cr, sr = math.cos(rpy[0]), math.sin(rpy[0])
    cp, sp = math.cos(rpy[1]), math.sin(rpy[1])
    cy, sy = math.cos(rpy[2]), math.sin(rpy[2])
    out = np.eye(4)
    out[:3, :3] = [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
    out[:3, 3] = xyz
    return out


def _rotation(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotations about a unit ``axis`` by ``angle`` (m,), shape (m, 3, 3) (Rodrigues)."""
    c, s = np.cos(angle)[:, None, None], np.sin(angle)[:, None, None]
    x, y, z = axis
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


class UrdfArm:
    """A serial chain of a URDF, base link to tip link: kinematics and joint limits.

    Parameters
    ----------
    urdf : str or os.PathLike
        A URDF file, or the XML text itself (a string starting with ``<``).
    base_link, tip_link : str, optional
        The chain's ends. Default: the root link, and the leaf link with the
        most moving joints above it (name it when two leaves tie, e.g. a
        gripper's two fingers).
    max_joint_acceleration : float or array_like, shape (n,), optional
        Joint acceleration limits (rad/s² or m/s²), > 0. Default:
        :data:`ACCELERATION_PER_SPEED` times each speed limit.
    name : str, optional
        Shown in messages; default the URDF's robot name.

    Attributes
    ----------
    name : str
    joint_names : tuple of str, shape (n,)
    joint_types : tuple of str
        ``"revolute"``, ``"continuous"`` or ``"prismatic"``, per joint.
    joint_limits : ndarray, shape (n, 2)
        ``(lower, upper)`` per joint (rad or m).
    max_joint_speed, max_joint_acceleration : ndarray, shape (n,)
    guessed_acceleration : bool
        Whether the acceleration limits are :data:`ACCELERATION_PER_SPEED` times the speed limits.
    ur_type : bool
        Always False: the analytic UR inverse kinematics needs the DH :class:`Arm`.

    Raises
    ------
    ValueError
        For XML that does not parse, a missing link, a joint type other than
        revolute/continuous/prismatic/fixed, a moving joint without speed
        limit, bad numbers; the message names the joint.
    """

    ur_type = False

    def __init__(
        self,
        urdf: str | os.PathLike[str],
        *,
        base_link: str | None = None,
        tip_link: str | None = None,
        max_joint_acceleration: Any = None,
        name: str | None = None,
    ) -> None:
        text = str(urdf)
        source = "urdf"
        if not text.lstrip().startswith("<"):
            path = Path(text)
            if not path.is_file():
                raise ValueError(f"urdf: {path} is not a file; pass a URDF file or its XML text")
            text, source = path.read_text(encoding="utf-8"), str(path)
        try:
            root = ET.fromstring(text)
        except ET.ParseError as exc:
            raise ValueError(f"{source}: not valid XML ({exc})") from None
        if root.tag != "robot":
            raise ValueError(f"{source}: the root element is <{root.tag}>, not <robot>")
        self.name = name or root.get("name") or "URDF arm"
        chain = self._chain(root, source, base_link, tip_link)
        self._read_chain(chain, source)
        n = len(self.joint_names)
        if max_joint_acceleration is None:
            acc = ACCELERATION_PER_SPEED * self.max_joint_speed
            self.guessed_acceleration = True
        else:
            acc = per_joint(
                max_joint_acceleration, "max_joint_acceleration", n, positive=True, scalar_ok=True
            )
            self.guessed_acceleration = False
        self.max_joint_acceleration = np.array(acc, dtype=np.float64)
        for arr in (self.joint_limits, self.max_joint_speed, self.max_joint_acceleration):
            arr.setflags(write=False)

    # ------------------------------------------------------------------ reading
    @staticmethod
    def _chain(
        root: ET.Element, source: str, base: str | None, tip: str | None
    ) -> list[ET.Element]:
        links = {link.get("name") for link in root.findall("link")}
        joints = root.findall("joint")
        by_child = {}
        for joint in joints:
            parent, child = joint.find("parent"), joint.find("child")
            if parent is None or child is None:
                raise ValueError(f"{source}: joint {joint.get('name')!r} lacks <parent> or <child>")
            by_child[child.get("link")] = joint
        for name, where in ((base, "base_link"), (tip, "tip_link")):
            if name is not None and name not in links:
                raise ValueError(f"{where}: no link {name!r} in {source}; links: {sorted(links)}")
        parents = {j.find("parent").get("link") for j in joints}  # type: ignore[union-attr]
        roots = sorted(links - set(by_child))
        if base is None:
            if len(roots) != 1:
                raise ValueError(f"{source}: {len(roots)} root links {roots}; name base_link")
            base = roots[0]

        def up(link: str) -> list[ET.Element]:
            out = []
            while link != base:
                if link not in by_child:
                    raise ValueError(f"tip_link: {tip!r} is not below base_link {base!r}")
                joint = by_child[link]
                out.append(joint)
                link = joint.find("parent").get("link")  # type: ignore[union-attr]
            return out[::-1]

        if tip is None:
            leaves = sorted(links - parents - {base})
            scored = []
            for leaf in leaves:
                try:
                    chain = up(leaf)
                except ValueError:
                    continue
                scored.append((sum(j.get("type") in _MOVING for j in chain), leaf))
            if not scored:
                raise ValueError(f"{source}: no link below {base!r}")
            best = max(scored)[0]
            top = [leaf for score, leaf in scored if score == best]
            if len(top) > 1:
                raise ValueError(f"{source}: leaf links {top} tie as the tip; name tip_link")
            tip = top[0]
        return up(tip)

    def _read_chain(self, chain: list[ET.Element], source: str) -> None:
        pending = np.eye(4)  # fixed transforms since the last moving joint
        origins, axes, names, types, limits, speeds = [], [], [], [], [], []
        for joint in chain:
            jname = joint.get("name") or "?"
            where = f"{source}: joint {jname!r}"
            kind = joint.get("type")
            if kind not in _KNOWN:
                raise ValueError(
                    f"{where}: type {kind!r} is not revolute, continuous, prismatic or fixed"
                )
            pending = pending @ _origin(joint, where)
            if kind == "fixed":
                continue
            element = joint.find("axis")
            axis = _floats(None if element is None else element.get("xyz"), 3, f"{where} axis")
            if element is None:
                axis = np.array([1.0, 0.0, 0.0])  # the URDF default
            norm = float(np.linalg.norm(axis))
            if norm == 0.0:
                raise ValueError(f"{where}: axis is zero")
            limit = joint.find("limit")
            if kind == "continuous":
                lower, upper = -2 * math.pi, 2 * math.pi
            else:
                if limit is None or limit.get("lower") is None or limit.get("upper") is None:
                    raise ValueError(f"{where}: a {kind} joint needs <limit lower upper>")
                lower, upper = float(limit.get("lower")), float(limit.get("upper"))  # type: ignore[arg-type]
                if not lower < upper:
                    raise ValueError(f"{where}: limit lower {lower} is not below upper {upper}")
            speed = None if limit is None else limit.get("velocity")
            if speed is None or not float(speed) > 0:
                raise ValueError(f"{where}: needs <limit velocity> > 0 (its speed limit)")
            origins.append(pending)
            pending = np.eye(4)
            axes.append(axis / norm)
            names.append(jname)
            types.append(kind)
            limits.append((lower, upper))
            speeds.append(float(speed))
        if not names:
            raise ValueError(f"{source}: the chain has no moving joint")
        self._origins = np.array(origins)  # (n, 4, 4): fixed transform before each joint
        self._axes = np.array(axes)  # (n, 3) in the joint's frame
        self._tip = pending  # after the last moving joint
        self._prismatic = np.array([t == "prismatic" for t in types])
        skews = [np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]]) for x, y, z in axes]
        self._skew = np.array(skews)  # (n, 3, 3), for one configuration's Rodrigues formula
        self._skew2 = self._skew @ self._skew
        self._eye3 = np.eye(3)
        self._links = list(
            zip(
                self._origins,
                self._prismatic.tolist(),
                self._skew,
                self._skew2,
                self._axes,
                strict=True,
            )
        )
        self.joint_names = tuple(names)
        self.joint_types = tuple(types)
        self.joint_limits = np.array(limits, dtype=np.float64)
        self.max_joint_speed = np.array(speeds)

    # ------------------------------------------------------------------ kinematics
    @property
    def n_joints(self) -> int:
        """Number of moving joints in the chain."""
        return len(self.joint_names)

    def __repr__(self) -> str:
        return f"UrdfArm({self.name!r}, {self.n_joints} joints)"

    def _check_q(self, q: Any) -> np.ndarray:
        arr = np.asarray(q, dtype=np.float64)
        if arr.ndim not in (1, 2) or arr.shape[-1] != self.n_joints:
            raise ValueError(
                f"q: expected shape ({self.n_joints},) or (m, {self.n_joints}) for the "
                f"{self.name}, got {arr.shape}"
            )
        if not np.isfinite(arr).all():
            raise ValueError("q: contains NaN or an infinite value")
        return arr

    def _frames(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint frames (m, n, 4, 4), each after its origin, before its motion; tip (m, 4, 4)."""
        m = len(q)
        frames = np.empty((m, self.n_joints, 4, 4))
        t = np.broadcast_to(np.eye(4), (m, 4, 4))
        for j in range(self.n_joints):
            t = t @ self._origins[j]
            frames[:, j] = t
            motion = np.broadcast_to(np.eye(4), (m, 4, 4)).copy()
            if self._prismatic[j]:
                motion[:, :3, 3] = q[:, j, None] * self._axes[j]
            else:
                motion[:, :3, :3] = _rotation(self._axes[j], q[:, j])
            t = t @ motion
        return frames, t @ self._tip

    def _single(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint frames (n, 4, 4) and the tip (4, 4) of one configuration: the IK's fast path."""
        frames = np.empty((self.n_joints, 4, 4))
        t = np.eye(4)
        motion = np.eye(4)
        for j, (origin, prismatic, skew, skew2, axis) in enumerate(self._links):
            t = t @ origin
            frames[j] = t
            angle = float(q[j])
            if prismatic:
                motion[:3, :3] = self._eye3
                motion[:3, 3] = angle * axis
            else:
                motion[:3, :3] = (
                    self._eye3 + math.sin(angle) * skew + (1.0 - math.cos(angle)) * skew2
                )
            t = t @ motion
        return frames, t @ self._tip

    def pose_and_jacobian(self, q: Any, tool: Any = None) -> tuple[np.ndarray, np.ndarray]:
        """Tip (or tool) pose (4, 4) and geometric Jacobian (6, n) of one configuration (n,)."""
        frames, end = self._single(np.asarray(q, dtype=np.float64))
        if tool is not None:
            end = end @ tool
        axes = np.einsum("jab,jb->ja", frames[:, :3, :3], self._axes)  # (n, 3) world axes
        r = end[:3, 3] - frames[:, :3, 3]
        cross = np.column_stack(
            (
                axes[:, 1] * r[:, 2] - axes[:, 2] * r[:, 1],
                axes[:, 2] * r[:, 0] - axes[:, 0] * r[:, 2],
                axes[:, 0] * r[:, 1] - axes[:, 1] * r[:, 0],
            )
        )
        prismatic = self._prismatic[:, None]
        jac = np.vstack((np.where(prismatic, axes, cross).T, np.where(prismatic, 0.0, axes).T))
        return end, jac

    def forward(self, q: Any, *, tool: Any = None) -> np.ndarray:
        """Tip (or tool) pose in the base link's frame.

        Parameters
        ----------
        q : array_like, shape (n,) or (m, n)
            Joint positions (rad, m for prismatic joints).
        tool : array_like, shape (4, 4), optional
            Tip→tool rigid transform appended.

        Returns
        -------
        ndarray, shape (4, 4) or (m, 4, 4)
        """
        arr = self._check_q(q)
        _, end = self._frames(np.atleast_2d(arr))
        if tool is not None:
            end = end @ np.asarray(tool, dtype=np.float64)
        return end if arr.ndim == 2 else end[0]

    def jacobian(self, q: Any, *, tool: Any = None) -> np.ndarray:
        """Geometric Jacobian at the tip (or the tool point) in the base frame.

        Returns
        -------
        ndarray, shape (6, n) or (m, 6, n)
            Rows ``(v_x, v_y, v_z, ω_x, ω_y, ω_z)`` per unit joint speed.
        """
        arr = self._check_q(q)
        frames, end = self._frames(np.atleast_2d(arr))
        if tool is not None:
            end = end @ np.asarray(tool, dtype=np.float64)
        axes = np.einsum("mjab,jb->mja", frames[:, :, :3, :3], self._axes)  # world axes
        lever = end[:, None, :3, 3] - frames[:, :, :3, 3]
        linear = np.where(self._prismatic[None, :, None], axes, np.cross(axes, lever))
        angular = np.where(self._prismatic[None, :, None], 0.0, axes)
        jac = np.concatenate((np.swapaxes(linear, 1, 2), np.swapaxes(angular, 1, 2)), axis=1)
        return jac if arr.ndim == 2 else jac[0]

    @property
    def joint_origins(self) -> np.ndarray:
        """Fixed transform before each joint's motion (fixed joints folded in), (n, 4, 4)."""
        return self._origins.copy()

    @property
    def joint_axes(self) -> np.ndarray:
        """Each joint's unit axis in its own frame, (n, 3)."""
        return self._axes.copy()

    @property
    def tip_transform(self) -> np.ndarray:
        """Fixed transform from the last joint's frame to the tip link, (4, 4)."""
        return self._tip.copy()

    def link_origins(self) -> np.ndarray:
        """Where each joint and the tip sit at zero joint positions, (n + 1, 3), m."""
        frames, end = self._frames(np.zeros((1, self.n_joints)))
        return np.vstack((frames[0, :, :3, 3], end[0, :3, 3]))
