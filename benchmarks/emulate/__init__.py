"""Emulation benchmark: inverse optimal control, MPC planning, baselines and speed.

Run ``python benchmarks/emulate`` (``--help`` for options; ``--quick`` for a
smoke run of a few minutes); ``lfdkit bench emulate`` runs the same. Prints
one table per section and a final targets table (PASS/FAIL), writes
``emulate.json`` and the figures ``emulate_reward_<set>.png``,
``emulate_heldout.png``, ``emulate_transfer.png`` and ``emulate_baseline.png``
to ``--output`` (``benchmarks/results/emulate`` by default). Exits 0 even when
a target fails. All work runs under ``threadpoolctl.threadpool_limits(1)``
(one BLAS thread: the machine has two cores and may be shared).

Data: ``load_emulation_dataset(name, seed)`` for ``artificial`` (thesis §5.5,
2-D), ``da_vinci_marker`` (§6.3, 3-D) and ``sweeping`` (§6.4, 2-D, classes cup
and marker); every set has a known true reward and a train/test split.

Nominal paths
-------------
The reward is relative to a nominal path. Each set is learned with each of:

* ``train``: ``MeanPath(center="biweight").fit(train_demos).path_``, the
  generalized path of the TRAINING demonstrations (the obstacle demonstrations
  themselves), as in the thesis's pipeline;
* ``free``: ``MeanPath().fit(free_demos).path_``, the generalized path of the
  set's obstacle-free demonstrations (``EmulationSet.free_demos``; skipped
  when the set has none);
* ``true``: the true nominal (a reference row: what a perfect mimicking layer
  would give).

Each table row says which. ``--figure-nominal`` (default ``free``, else
``train``) picks the nominal of sections 5 and of the figures.

1. Fit and recovery
-------------------
``IOC()`` (full horizon) and ``IOC(horizon=8)`` (staged: full horizon, then
MPC) on the training demonstrations in their scenes. Reported: fitted and
true ``Q`` and diagonal precisions, ``lfdkit.emulate.metrics.parameter_errors``
(target: every parameter within 10 % of the truth), seconds of the initial
grid (the fit's total time minus its stages), of each stage, L-BFGS
iterations, training loss (mean squared lateral distance, m²). For reference
(not with ``--quick``), ``IOC()`` along the true nominal on the noise-free
demonstrator's data (``noise=0``, same seed): the estimator without the
demonstration noise.

2. Evaluation
-------------
Test demonstrations (their scenes are not seen in training):

* MSE_R (``mse_paths``, m²) of the plans of the learned full-horizon reward
  (full horizon), of the staged reward (MPC H=8), of the true reward along the
  true nominal (full horizon: ``true_plan``; and MPC H=8), and MSE_Mp of
  replaying the nominal;
* Pr = ``improvement(MSE_Mp, MSE_R)`` (target ≥ 90 %) and the ratio
  MSE_R(learned)/MSE_R(true) with the same planner (target ≤ 1.5);
* for the thesis's figures: sweeping Pr per class (thesis 96.5 % cup, 92.7 %
  marker) and da Vinci train/test MSE_R (thesis 0.175/0.091 in its units).

Held-out scenes (``held_out_scenes``: cluttered, concave pocket, mixed cup and
marker, unseen marker positions) have no demonstrations: every plan is compared
with the true-parameter full-horizon plan (``true_plan``). Reported per
planner: collisions (``collisions``), minimum clearance (``clearance``, m) and
the MSE to ``true_plan``. Target: no collision in the cluttered and concave
scenes with the learned reward, judged for full horizon and MPC separately.

3. Baseline: DMP with obstacle-avoidance coupling
--------------------------------------------------
movement_primitives ``DMP(n_dims=2, execution_time=1, dt=0.01,
n_weights_per_dim=30)`` imitating the nominal (the minimum-jerk motion along
it sampled at 1000 uniform times, as the ``m_p dense`` row of
``benchmarks/imitate.py``: with 100 unevenly timed samples the peer's finite
differences make it overshoot), ``configure`` to the nominal's start and
goal, ``open_loop(coupling_term=...)`` with one
``CouplingTermObstacleAvoidance2D(obstacle, gamma, beta, fast=True)`` per
obstacle, summed by :class:`ObstacleCoupling`. γ and β tuned by grid search
(γ = 0 included: the plain DMP) on the TRAINING demonstrations (min MSE_R);
the best grid point is then scored on the test demonstrations. 2-D sets only:
the package's coupling term is 2-D (``CouplingTermObstacleAvoidance3D``
exists, but the brief scopes the baseline to the 2-D sets), so da Vinci is
skipped. Target: lfdkit's test MSE_R (full horizon) at least 3× lower.

4. Speed
--------
``load_emulation_dataset("sweeping", 0, n_cup=4, n_marker=4, n_points=100)``:
8 demonstrations × 100 points, two classes, all used for training, along the
true nominal. Times are medians of interleaved rounds (each method once per
round, so each sees the same machine load); a ratio is the median of the
per-round ratios.

(a) ``IOC().fit`` (target < 2 s) and ``IOC(horizon=8).fit`` (target < 15 s).
(b) The same with ``gradient="finite_difference"`` (the staged FD fit runs once,
    after the rounds: it takes minutes; skipped with ``--quick``).
(c) A straightforward SciPy implementation (:func:`scipy_ioc`): each inner plan
    by ``scipy.optimize.minimize(method="L-BFGS-B")`` over the actions with
    their bounds, cost and gradient from the planner's own
    ``Problem.from_scene(...).derivatives``, started from the demonstration (MPC: each
    window from the previous one shifted, the first from the demonstration);
    the outer loop ``minimize(L-BFGS-B)`` on the same scaled loss with
    SciPy's finite-difference gradient (step 1e-4 in log-parameters), a time
    limit per stage (``--scipy-limit``, 120 s), "did not finish" recorded with
    the best point evaluated. Both SciPy and lfdkit start from the same reward
    (lfdkit's former default: ``Q = 10 / extent²``, widths 5 % of the extent),
    lfdkit via ``IOC(init=...)``; the SciPy stage 2 starts from its stage 1.
(d) MPC H=12 in a sweeping scene (one cup) and the cluttered held-out scene:
    the whole ``plan_path(..., horizon=12)`` call divided by its 99 MPC steps
    (median over calls), and each window's ``planner.best_window`` timed
    directly (median, 90th percentile and max over all windows of several
    plans; the replayed loop is checked to reproduce the plan). Target
    < 1 ms median (the per-window median in the one-cup scene).
(e) A 100-point full-horizon ``plan_path`` (target < 100 ms median), same
    scenes; for information also a 3-D da Vinci held-out scene.

5. Composition and transfer (thesis §6.3.3, Figs 6.12-6.13)
-----------------------------------------------------------
Composition: on sweeping, ``IOC()`` on the cup-only training scenes and on the
marker-only ones, joined by ``Reward.combined`` (Q of the cup fit), planned in
the mixed and cluttered held-out scenes; compared with the jointly learned
reward and the true-parameter plan. Transfer: the reward learned on the
artificial task planned along other nominals (the straight 0.8 m sweeping
nominal and a quarter circle of radius 0.5 m) in a one-obstacle and a
four-obstacle cluttered scene; deviation (MSE) from the true-parameter plan
along the same nominal, collisions and clearance.

Layout
------
A package, one module per part: :mod:`.spec` (data sets, planners, targets'
thresholds, the thesis's values), :mod:`.common` (helpers), the sections
:mod:`.recovery` (1), :mod:`.evaluation` (2), :mod:`.baseline` (3),
:mod:`.speed` (4) with the SciPy reference solver :mod:`.reference`, and
:mod:`.transfer` (5), then :mod:`.figures`, :mod:`.targets` and the runner
:mod:`.run` (``__main__`` calls its ``main``). The names below are what the
other benchmarks use (``import emulate`` from ``benchmarks/``):
``benchmarks/robot.py`` the DMP baseline, ``benchmarks/emulate_robustness.py``
the SciPy reference. The fidelity study (does a learned skill move round new
obstacles as its person would?) is a separate command,
``python benchmarks/emulate_fidelity.py``: :mod:`.fidelity`, with its
demonstrators in :mod:`.people`.
"""

from .baseline import dmp_rollout, dmp_score, peer_dmp
from .reference import default_start, scipy_ioc
from .spec import DMP_BETAS, DMP_GAMMAS, QUICK_BETAS, QUICK_GAMMAS

__all__ = [
    "DMP_BETAS",
    "DMP_GAMMAS",
    "QUICK_BETAS",
    "QUICK_GAMMAS",
    "default_start",
    "dmp_rollout",
    "dmp_score",
    "peer_dmp",
    "scipy_ioc",
]
