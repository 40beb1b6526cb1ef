"""MuJoCo models of an arm description: nested link bodies from the DH table, servos, loading.

:func:`robot_xml` turns an :class:`lfdkit.execute.arm.Arm` into MJCF: body ``i``
turns about its ``z`` axis by ``θ_i`` (hinge ``joint{i}``, range
``arm.joint_limits``); the next body sits at the link's fixed transform
``Tz(d_i) Tx(a_i) Rx(α_i)``, i.e. at position ``(a_i, 0, d_i)`` with the
rotation ``Rx(α_i)``; a body ``flange`` with a site ``flange`` ends the chain.
MuJoCo's flange pose therefore equals :func:`lfdkit.execute.ur5.forward` to
round-off for any DH table (:func:`flange_poses` computes it with MuJoCo's own
kinematics, an independent check of the forward kinematics). Each link is a
capsule from its joint to the next body (a sphere where the two coincide) of
radius ``arm.link_radii[i]`` and mass ``arm.link_masses[i]``; links are
gravity-compensated. :func:`actuators_xml` gives one position servo per joint
with the arm's gains ``kp``/``kv``. The joint count, masses, radii, limits and
gains all come from the description; nothing here knows a particular arm.

:func:`arm_mjcf` is the arm alone on its base; a task's scene puts the same
bodies, with its tool on the flange, among its objects (the sweeping task,
:mod:`lfdkit.tasks.sweeping.sim`, a brush). :func:`render_camera` renders a
scene's camera with traces drawn in.

Collisions: robot geoms carry :data:`ROBOT_CONTACT` (``contype`` 2,
``conaffinity`` 0), so they touch only geoms whose ``conaffinity`` has bit 2
set: a scene's movable objects (:data:`OBJECT_CONTACT`), never fixed geoms
such as a table (:data:`FIXED_CONTACT`) or each other. Objects and fixed geoms
touch each other.

Loading MuJoCo
--------------
:func:`load_mujoco` imports MuJoCo on first use. Without a display and with
``MUJOCO_GL`` unset it asks for off-screen rendering (:data:`HEADLESS_GL`,
EGL); if that OpenGL backend is missing MuJoCo fails on import, and the import
is repeated with rendering disabled, so physics runs anyway.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Sequence
from html import escape
from typing import Any

import numpy as np

from lfdkit.execute.arm import UR5, Arm, check_arm

__all__ = [
    "FIXED_CONTACT",
    "HEADLESS_GL",
    "OBJECT_CONTACT",
    "ROBOT_CONTACT",
    "actuators_xml",
    "arm_mjcf",
    "flange_poses",
    "load_mujoco",
    "mjcf_numbers",
    "render_camera",
    "robot_xml",
]

#: Collision attributes of robot geoms: they hit objects, not the table or themselves.
ROBOT_CONTACT = 'contype="2" conaffinity="0"'
#: Collision attributes of a scene's movable objects: the robot, fixed geoms and each
#: other hit them.
OBJECT_CONTACT = 'contype="1" conaffinity="3"'
#: Collision attributes of fixed scene geoms (a table, walls): objects hit them, the
#: robot does not.
FIXED_CONTACT = 'contype="1" conaffinity="1"'
#: Off-screen OpenGL backend tried when there is no display and MUJOCO_GL is unset.
HEADLESS_GL = "egl"

_NO_RENDERER = False  # set when MuJoCo could not make an OpenGL context: do not try again
_ARMATURE = 0.1  # kg·m², reflected rotor inertia: keeps the stiff PD stable
_JOINT_DAMPING = 0.5  # N·m·s/rad
_INDENT = "    "


def mjcf_numbers(values: Any) -> str:
    """Numbers as an MJCF attribute value: space-separated, exact (``repr`` of each float)."""
    return " ".join(repr(float(v)) for v in np.atleast_1d(values))


def robot_xml(arm: Arm = UR5, flange: Sequence[str] = ()) -> str:
    """Nested ``<body>`` elements of the arm, for a ``<worldbody>``, base at the origin.

    Parameters
    ----------
    arm : Arm
        The description; any number of joints.
    flange : sequence of str
        MJCF lines placed in the flange body after its site (e.g. a tool's
        geoms), without indentation.

    Returns
    -------
    str
        Bodies ``link1`` … ``link{n}`` with hinges ``joint1`` … ``joint{n}``, and
        the body and site ``flange``; indented for a ``<worldbody>`` two levels deep.
    """
    arm = check_arm(arm)
    n = arm.n_joints
    opening, closing = [], []
    placement = ""  # link 1 sits at the base frame
    for i in range(n):
        pad = _INDENT * (i + 2)
        child = np.array([arm.a[i], 0.0, arm.d[i]])
        shape = (
            f'type="capsule" fromto="0 0 0 {mjcf_numbers(child)}"'
            if np.linalg.norm(child) > 0
            else 'type="sphere"'
        )
        opening += [
            f'{pad}<body name="link{i + 1}"{placement} gravcomp="1">',
            f'{pad}  <joint name="joint{i + 1}" axis="0 0 1" '
            f'range="{mjcf_numbers(arm.joint_limits[i])}" armature="{_ARMATURE}" '
            f'damping="{_JOINT_DAMPING}"/>',
            f'{pad}  <geom {shape} size="{mjcf_numbers(arm.link_radii[i])}" '
            f'mass="{mjcf_numbers(arm.link_masses[i])}" '
            f'rgba="0.6 0.65 0.7 1" {ROBOT_CONTACT}/>',
        ]
        closing.insert(0, f"{pad}</body>")
        half = 0.5 * arm.alpha[i]
        quat = mjcf_numbers([math.cos(half), math.sin(half), 0, 0])
        placement = f' pos="{mjcf_numbers(child)}" quat="{quat}"'
    pad = _INDENT * (n + 2)
    body = [
        f'{pad}<body name="flange"{placement} gravcomp="1">',
        f'{pad}  <site name="flange" size="0.005" rgba="1 0 0 1"/>',
        *(f"{pad}  {line}" for line in flange),
        f"{pad}</body>",
    ]
    return "\n".join(opening + body + closing)


def actuators_xml(arm: Arm = UR5) -> str:
    """One ``<position>`` servo per joint with the arm's ``kp`` and ``kv``, for ``<actuator>``."""
    arm = check_arm(arm)
    return "\n".join(
        f'    <position name="joint{i + 1}" joint="joint{i + 1}" '
        f'kp="{mjcf_numbers(arm.kp[i])}" kv="{mjcf_numbers(arm.kv[i])}"/>'
        for i in range(arm.n_joints)
    )


def arm_mjcf(arm: Arm = UR5) -> str:
    """The MJCF of the arm alone: its bodies on the origin and its position servos."""
    arm = check_arm(arm)
    return f"""<mujoco model="lfdkit {escape(arm.name)}">
  <compiler angle="radian" autolimits="true"/>
  <option integrator="implicitfast"/>
  <worldbody>
{robot_xml(arm)}
  </worldbody>
  <actuator>
{actuators_xml(arm)}
  </actuator>
</mujoco>
"""


def load_mujoco() -> Any:
    """Import MuJoCo; headless, try EGL for rendering, and simulate without it if it is missing."""
    if "mujoco" in sys.modules:
        return sys.modules["mujoco"]
    chosen = "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY")
    if chosen:
        # No display: render off-screen (GLFW would need a window system).
        os.environ["MUJOCO_GL"] = HEADLESS_GL
    try:
        import mujoco
    except ImportError as exc:  # declared dependency; a broken install is worth a clear word
        raise ImportError("lfdkit.execute needs MuJoCo: python -m pip install mujoco") from exc
    except Exception:
        if not chosen:
            raise
        # The OpenGL library is not there (MuJoCo fails on import): no rendering, physics only.
        for name in [m for m in sys.modules if m.split(".")[0] in ("mujoco", "OpenGL")]:
            del sys.modules[name]
        os.environ["MUJOCO_GL"] = "disable"
        import mujoco
    return mujoco


def render_camera(
    model: Any,
    data: Any,
    camera: str,
    traces: Sequence[tuple[np.ndarray, Sequence[float]]] = (),
    *,
    size: tuple[int, int] = (720, 960),
    frame: bool = False,
) -> np.ndarray | None:
    """An RGB image of a camera's view, with traces drawn as dots; None without OpenGL.

    Parameters
    ----------
    model, data
        ``mujoco.MjModel`` and ``mujoco.MjData`` (the state to show). The model's
        off-screen buffer (``<visual><global offwidth offheight>``) must hold ``size``.
    camera : str
        Name of a camera of the model.
    traces : sequence of (points, rgba)
        Points (m, 3) drawn as 4 mm dots (at most about 150 per trace) in the colour
        ``rgba`` (4 numbers in [0, 1]).
    size : (int, int)
        Height and width of the image, pixels.
    frame : bool
        Look in the camera's direction but from where everything drawn (every
        geom but planes, and the traces) just fills the image, 5 % spare: a fixed
        camera crops a larger arm (the UR10) and misses objects far from it.

    Returns
    -------
    ndarray, shape (height, width, 3) or None
        None when MuJoCo has no OpenGL context (no EGL, OSMesa or display;
        found out once per process) or cannot show the camera: rendering is
        optional.
    """
    global _NO_RENDERER
    if _NO_RENDERER:
        return None
    mujoco = load_mujoco()
    try:
        renderer = mujoco.Renderer(model, *size)
    except Exception:  # no EGL/OSMesa/GLFW context: rendering is optional
        # A second try would not find one either, and with GLFW it aborts the process.
        _NO_RENDERER = True
        return None
    try:
        with renderer:
            view = _framing_camera(mujoco, model, data, camera, traces, size) if frame else camera
            renderer.update_scene(data, camera=view)
            scene = renderer.scene
            for points, rgba in traces:
                for point in points[:: max(1, len(points) // 150)]:
                    if scene.ngeom >= scene.maxgeom:
                        break
                    mujoco.mjv_initGeom(
                        scene.geoms[scene.ngeom],
                        mujoco.mjtGeom.mjGEOM_SPHERE,
                        np.array([0.004, 0.0, 0.0]),
                        np.asarray(point, dtype=np.float64),
                        np.eye(3).ravel(),
                        np.asarray(rgba, dtype=np.float32),
                    )
                    scene.ngeom += 1
            return renderer.render().copy()
    except Exception:  # e.g. no such camera: no image, as without a context
        return None


def _framing_camera(
    mujoco: Any,
    model: Any,
    data: Any,
    camera: str,
    traces: Sequence[tuple[np.ndarray, Sequence[float]]],
    size: tuple[int, int],
) -> Any:
    """A free camera in the named camera's direction, framing every geom and trace."""
    mujoco.mj_kinematics(model, data)
    mujoco.mj_camlight(model, data)
    cam = model.camera(camera).id
    forward = -data.cam_xmat[cam].reshape(3, 3)[:, 2]
    up = data.cam_xmat[cam].reshape(3, 3)[:, 1]
    elevation = float(np.degrees(np.arcsin(np.clip(forward[2], -1.0, 1.0))))
    # Straight down, the heading is where the camera's up points.
    heading = up if abs(forward[2]) > 0.99 else forward
    azimuth = float(np.degrees(np.arctan2(heading[1], heading[0])))
    elevation = float(np.clip(elevation, -89.0, 89.0))  # a free camera turns about world z
    az, el = np.radians(azimuth), np.radians(elevation)
    forward = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    solid = model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE
    points = [data.geom_xpos[solid]]
    radii = [model.geom_rbound[solid]]
    for trace, _ in traces:
        trace = np.asarray(trace, dtype=np.float64).reshape(-1, 3)
        points.append(trace)
        radii.append(np.zeros(len(trace)))
    pts, rad = np.vstack(points), np.concatenate(radii)
    lookat = 0.5 * ((pts - rad[:, None]).min(axis=0) + (pts + rad[:, None]).max(axis=0))
    rel = pts - lookat
    height, width = size
    tan_y = np.tan(np.radians(model.vis.global_.fovy) / 2.0)
    tan_x = tan_y * width / height
    # Each point (a sphere of its bounding radius) inside the view cone: distance along
    # the view axis at least |lateral| / tan(half angle) behind it.
    depth = rel @ forward
    need = (
        np.maximum((np.abs(rel @ right) + rad) / tan_x, (np.abs(rel @ up) + rad) / tan_y)
        - depth
        + rad
    )
    view = mujoco.MjvCamera()
    view.type = mujoco.mjtCamera.mjCAMERA_FREE
    view.lookat[:] = lookat
    view.distance = 1.05 * float(need.max())
    view.azimuth, view.elevation = azimuth, elevation
    return view


def flange_poses(q: Any, *, arm: Arm = UR5) -> np.ndarray:
    """Flange poses computed by MuJoCo's own kinematics (independent of ``ur5.forward``).

    Parameters
    ----------
    q : array_like, shape (n_joints,) or (n, n_joints)
        Joint angles, rad.
    arm : Arm
        The arm, modelled by :func:`arm_mjcf`.

    Returns
    -------
    ndarray, shape (4, 4) or (n, 4, 4)
    """
    arm = check_arm(arm)
    arr = np.asarray(q, dtype=np.float64)
    single = arr.ndim == 1
    arr = np.atleast_2d(arr)
    n = arm.n_joints
    if arr.ndim != 2 or arr.shape[1] != n or not np.all(np.isfinite(arr)):
        raise ValueError(
            f"q: expected finite joint angles of shape ({n},) or (m, {n}) for the {arm.name}, "
            f"got {np.shape(q)}"
        )
    mujoco = load_mujoco()
    model = mujoco.MjModel.from_xml_string(arm_mjcf(arm))
    data = mujoco.MjData(model)
    site = model.site("flange").id
    out = np.tile(np.eye(4), (arr.shape[0], 1, 1))
    for i, config in enumerate(arr):
        data.qpos[:n] = config
        mujoco.mj_kinematics(model, data)
        out[i, :3, :3] = data.site_xmat[site].reshape(3, 3)
        out[i, :3, 3] = data.site_xpos[site]
    return out[0] if single else out
