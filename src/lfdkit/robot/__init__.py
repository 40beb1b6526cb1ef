"""Execution on a UR5 (thesis §6.4): kinematics, sweeping poses, timing, URScript, simulation.

Submodules: :mod:`.ur5` (DH forward kinematics, Jacobian, analytic inverse
kinematics), :mod:`.poses` (rotation vectors, sweeping tool poses),
:mod:`.timing` (time parameterisation within the joint limits) and
:mod:`.urscript` (programs for a UR controller).
"""
