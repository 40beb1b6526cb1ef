"""The execute layer (thesis §6.4, a UR5): kinematics, tool poses, timing, URScript, MuJoCo models.

An arm is described once, by an :class:`lfdkit.execute.arm.Arm` (DH table, joint
position/speed/acceleration limits, link masses and radii, servo gains); every
submodule takes it as ``arm=`` and defaults to :data:`lfdkit.execute.arm.UR5`, the
arm of the thesis. :data:`lfdkit.execute.arm.UR10` is a second one. A new arm is a
new :class:`~lfdkit.execute.arm.Arm`, nothing else.

Submodules: :mod:`.arm` (the descriptions), :mod:`.ur5` (DH forward kinematics,
Jacobian, analytic inverse kinematics of UR-type arms), :mod:`.poses` (rotation
vectors, sweeping tool poses), :mod:`.timing` (time parameterisation within the
arm's joint limits), :mod:`.urscript` (programs for a UR controller),
:mod:`.mujoco` (MuJoCo bodies, servos and rendering of an arm),
:mod:`.recordings` (joint-state recordings to tool poses). Generic robot code
only: the sweeping experiment built on it is a task, :mod:`lfdkit.tasks.sweeping`.
"""
