"""The execute layer (thesis §6.4, a UR5): kinematics, tool poses, timing, URScript, MuJoCo models.

An arm is described once, by an :class:`lfdkit.execute.arm.Arm` (DH table, joint
position/speed/acceleration limits, link masses and radii, servo gains); every
submodule takes it as ``arm=`` and defaults to :data:`lfdkit.execute.arm.UR5`, the
arm of the thesis. :data:`lfdkit.execute.arm.UR10` is a second one. A new arm is a
new :class:`~lfdkit.execute.arm.Arm`, or any arm's URDF read by
:class:`lfdkit.execute.urdf.UrdfArm` (the generic chain, :mod:`.pipeline`, takes both).

Submodules: :mod:`.arm` (the descriptions), :mod:`.urdf` (any arm from its
URDF), :mod:`.ur5` (DH forward kinematics, Jacobian, analytic inverse
kinematics of UR-type arms), :mod:`.kinematics` (forward, reach and joint
paths for any arm, numerical IK), :mod:`.poses` (rotation vectors, headings),
:mod:`.timing` (time-optimal timing within the arm's joint limits),
:mod:`.trajectory` (the person's timing kept within them), :mod:`.joint_motion`
(what the timings share), :mod:`.pipeline`
(any timed plan to an arm: poses, IK, timing, samples, programs),
:mod:`.simulation` (the MuJoCo check of any arm), :mod:`.urscript` (programs
for a UR controller),
:mod:`.mujoco` (MuJoCo bodies, servos and rendering of an arm),
:mod:`.recordings` (joint-state recordings to tool poses). Generic robot code
only: the sweeping experiment built on it is a task, :mod:`lfdkit.tasks.sweeping`.
"""
