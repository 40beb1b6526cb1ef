"""lfdkit: robot learning from a few noisy demonstrations.

The folders are the architecture, a ladder whose floors import only their own
floor and those below (``tests/test_architecture.py`` holds it)::

    core       geometry, rotations (x, y, z, w), units, validation, the estimator base,
               options, progress, threads
    model      the data records: demonstrations, Scene and the obstacle contract, motion,
               timed plans
    io         every file read or written (demonstrations, scenes, skills, recordings)
    mimic      one generalized path from noisy demonstrations (the MIMIC_METHODS registry)
    imitate    DMPs: the path carried to new starts and goals, with the learned timing
    emulate    the reward learned from demonstrations, the planner, metrics
    datasets   synthetic, emulation and LASA data sets
    execute    robot arms: kinematics, tool poses, timing, URScript, MuJoCo
    skill      the layered estimator, mimic -> imitate -> emulate (:class:`lfdkit.skill.Skill`)
    app        figures, the HTML report, batch runs, the method comparison
    tasks      complete tasks built on all of the above (the sweeping example)
    app.cli, app.teach   the ``lfdkit`` command and the teach page, on top

Each mimicking method registers itself in
:data:`lfdkit.mimic.MIMIC_METHODS` (the contract is :mod:`lfdkit.mimic.base`);
each obstacle shape is one subclass of :class:`lfdkit.model.scene.Obstacle`
(the obstacle contract) in :data:`lfdkit.model.scene.OBSTACLE_SHAPES`; each
robot arm is one :class:`lfdkit.execute.arm.Arm` description. The package
root imports nothing, so ``import lfdkit`` is instant.
"""

__version__ = "0.1.0"
