"""Mean-Path: a geometric principal curve of several demonstrations (thesis chapter 4).

The Mean-Path minimises the summed squared distances to all demonstrations,
distances measured along the normals of the curve itself. It is computed by the
thesis's fixed-point iteration (Algorithm 1): intersect the normal hyperplane at
every point of a Reference-Path with every demonstration, move each point
towards the centre of its intersections, halve the step whenever the residual
grows.

Where real demonstrations differ from the thesis's clean data, this
implementation decides as follows (each is a constructor option):

* **Which intersection.** Along a normal a demonstration may be crossed several
  times (loops, hairpins, a curved task). The nearest crossing is taken, and by
  default only crossings on segments traversed in the reference's direction count
  (the thesis's "associated segments", appendix Definition 1), so the backward leg
  of a loop is never matched (``same_direction``).
* **Misses.** Near the ends a normal meets only the demonstrations that started
  before it, and those are systematically the ones offset to one side, so their
  centre is biased. While fitting, each demonstration is therefore extended by a
  straight ray along its end direction (``extend``, a fraction of its length), as
  if the demonstrator had carried on; the rays are virtual and never enter
  ``distances_``, ``support_`` or ``residual_``. Where a normal still meets fewer
  than ``min_support`` of the demonstrations (a wide gap) the point is not
  estimated from so little evidence: it continues the updated well-supported
  points (interpolated across a gap, straight along the tangent beyond the last
  one), so the path stays smooth. Missing distances are reported as NaN in
  ``distances_`` and left out of ``e1``.
* **Ends.** With ``ends="consensus"`` (default) the path starts and stops where the
  demonstrations agree: after each update its extent is set to the centre (as
  ``center``) of the arc-length positions of the demonstrations' first and last
  points, extrapolating straight past the current ends if needed. A start
  is placed on the path's first quarter only, an end on its last quarter, so a
  closed shape (an "o", a figure-eight) or a stroke that comes back beside its
  start (an "a") is never cut where it passes the start again. With
  ``ends="normal"`` the end points, like all others, move only along their
  normals (the thesis's behaviour: the ends stay where the initial path put them).
  In both cases the points are then re-spaced evenly in arc length, which keeps
  the normals well defined however unevenly the demonstrations are sampled.
* **Outliers.** ``center="adaptive"`` (default) is the mean of the
  intersections that agree: a redescending M-estimate whose weight is 1 within
  4 robust standard deviations of the centre and falls smoothly to 0 at 8
  (the loss is the square in that core, flat beyond), iterated from the
  midpoint of the shortest interval holding half the intersections (in 3-D,
  the geometric median), the scale fixed at 1.4826 times their median distance
  to it. Where no intersection lies outside the core it *is* the mean, the
  thesis's maximum-likelihood centre, and as efficient on the light-tailed
  spread of smooth offsets (where the biweight loses 12-16 %); an
  intersection beyond 8 robust standard deviations (a swerve) gets no weight;
  and where half the intersections coincide (deburring profiles, exact except
  for one-sided residuals) the scale is zero and the centre is that common
  point, even where the other half all carry residuals and the median lands
  halfway up the lowest. From a handful of values the robust scale is itself
  noisy (of five Gaussian values, one lies past the cutoff of their own scale
  14 % of the time: ``benchmarks/adaptive_thresholds.py``), so a normal met by
  fewer than 8 demonstrations (4 in 3-D) takes their mean, and no normal's
  scale goes below the median along the path, where the demonstrator's spread
  varies slowly: a normal where some values bunch by chance does not cut the
  others, and the path does not jump there. The step control then compares the
  same loss, each normal on the accepted path's scale. That rule was chosen
  on the ten synthetic sets (``benchmarks/mimic.py --sections centres``), but
  on other data it gave accuracy away: burrs only 2-8 robust scales high keep
  full weight, and on six profiles (fewer than 8 per normal: the mean) burrs
  20 times the noise high made it 2.4-2.8 times the best fixed centre's error
  (``benchmarks/mimic_centres.py``, sets drawn apart from the built-in ones).
  So the tuning is chosen per data set (``center_tuning_``, why in
  ``center_reason_``): at the initial path, each intersection's signed
  distance from the start of the *other* intersections on its normal, in
  robust scales (a running median along the path), is pooled into one sample
  of the residual distribution, and each candidate (:data:`_TUNINGS`: Huber
  cores of 2 to 0.1 scales, near the median, and cut-offs tapering from 2-4 or
  3-6 scales, near the biweight) gets its large-sample squared error
  ``t² + V / n`` on it (``t``: its offset from the starts, the bias one-sided
  burrs cause; ``V = E[ψ²] / E[ψ']²``). The default stays unless another is
  estimated below 0.95 times its error both on the data and in 90 % of 40
  resamplings of demonstrations and path stretches together (seeded, so a fit
  is deterministic): smooth demonstrations make neighbouring values one piece
  of evidence, and without that check the choice followed chance on clean
  bands. Where a tuning is suggested but not that clearly (75-90 % of the
  resamplings), a second test decides, one that assumes nothing about where
  the truth lies (the estimate above measures bias from the shortest half):
  cross-validation, each intersection predicted by both centres of the others
  on its normal, the errors scored by a square bounded at 3 robust scales so
  that a burr or a detour costs every centre alike; the tuning is taken if it
  predicts better in 75 % of the resamplings too. Short of both, on data
  not smooth along the path, a *cheap* tuning (its variance on Gaussian values
  at most :data:`_CHEAP`, 15 %, above the mean's: cores of 1 scale and more,
  or the tapers from 2-4 and 3-6) is taken where its expected gain exceeds its
  expected cost if wrong, ``w g > (1 - w) c`` (``w`` the share of resamplings
  in which it wins, at least a half, ``g`` its estimated gain, ``c`` that
  Gaussian cost): on one-sided burrs 1-2 noise levels high over 30 % of each
  profile the shortest half sits 0.20-0.24 robust scales towards the burrs,
  so the estimate sees 3-6 % of a gain that measured from the truth is 25 %
  (1/2/4 there: 0.188 against 0.250), and no fixed test threshold tells that
  from chance, while being wrong with such a tuning costs at most its
  Gaussian variance. Of the cheap tunings that pass, the most robust (largest
  Gaussian cost) is taken, not the best estimated: the estimate's blind spot
  grows with robustness, so it favoured the nearly free core of 2 scales
  where 1/2/4 was 5-15 % better (one-sided burrs 1-2 noise levels high over
  30 % of 20 profiles: 1.05-1.07 times the best fixed centre on seeds 200-204,
  300-304, 500-504, now 0.99-1.02; every burr case on seeds 0-504, 600-604 and
  800-804 within 1.045, at worst 3 % lost where burrs 2 noise levels high cover
  5 % of 6 profiles). A cheap tuning other than the best estimated must also be
  estimated 2 % better (:data:`_CHEAP_OTHER_GAIN`): each one more is one more
  chance on clean data. A confident choice (90 %) of a cheap tuning kept the
  same blind spot: on those 20 profiles, seeds 700-704, 1.076 and 1.079
  (straight, circular), the core of 2 scales or the taper from 2 to 4 taken
  with 90-98 % confidence where the cores of 1 and 0.5 scales were 5-10 %
  better on each of ten seeds (every tuning forced). Taking the most robust
  passing cheap tuning there regardless lost up to 10 % where tall burrs
  cover 5 % of 6 or 20 profiles: the tapers already cut those, and a smaller
  core buys only variance. What tells the two apart is where the asymmetry
  lies. Where it reaches into the core, a more robust tuning's pooled centre
  lies off the confident one's, 0.02-0.06 robust scales, on one side in 95-100 %
  of the resamplings; where the burrs are tall and sparse both cut them and
  their centres differ by chance (one side in 40-85 %, once 90 %). So a confident cheap choice
  gives way to the most robust cheap tuning that passes the expected-gain test
  above and whose centre lies off its own on one side in 95 % of the
  resamplings (:data:`_DRIFT_CONFIDENCE`). Measured (``--kinds burrs``, side by
  side with the rule without it, cases within 1.05 of 36): seeds 0-4, 100-104,
  200-204, 300-304, 400-404 and 500-504 36 -> 36, 700-704 34 -> 36 (worst
  1.079 -> 1.039), 900-904 35 -> 36 (1.055 -> 1.039); one-sided burrs 1-2
  noise levels high over 30 % of 20 profiles, over the eight seed blocks,
  0.995-1.079 -> 0.989-1.039, 3-6 noise levels over 15 % of 12 profiles
  0.90-0.96 -> 0.87-0.95; the price, tall sparse burrs (5 % of each profile,
  20 noise levels), at most 2 % (0.88-0.99 -> 0.90-0.99). On
  coverages, heights and counts between the box's (``--kinds sweep``, 32
  cases, seeds 0-4 and 500-504) all within 1.05 before and after (worst
  1.028 -> 1.017 and 1.033 -> 1.033); the price there, one-sided burrs 10
  noise levels high over 10 % of 16 profiles, 0.90-0.94 -> 0.93-0.96. Not
  one choice changed on the clean and detour sets (300 fits, 30 seeds), on
  white noise and smooth bands of 6-20 demonstrations (150), nor a path on the
  ten built-in sets (5 seeds each) or the speed sets. The other cheap
  tunings' resamplings are computed only on these branches, on data not
  smooth along the path. Rows with fewer than 8
  values then take the path's scale rather than the mean. Measured
  (``python benchmarks/mimic_centres.py``, 44 cases x 5 seeds): the default's
  error over the best fixed centre's is at most 1.05 on one-sided burrs and
  1.07 on two-sided ones (it was up to 2.4 and 2.8), down to 0.6 where burrs
  cover 30 % of 20 profiles; on held-out seeds 100-104 at most 1.10, on
  seeds 200-209 at most 1.09. On clean white noise it keeps the default, the
  mean's error to 1 %. On clean smooth bands it switched in 1-3 of 10 seeds
  200-209 and lost 3.5 % (6 demonstrations) and 11 % (15) against the mean:
  a few smooth curves bunch by chance all along the path, so the robust scale
  is half their standard deviation on every normal (measured) and the pooled
  values look heavy-tailed; resampling those few demonstrations keeps the
  bunching, so both tests agreed. So where the deviations are smooth along
  the path (rank correlation from one normal to the next 0.96-0.99 there,
  0.2-0.35 on white noise with burrs), a switch must also gain clearly more
  than it does on Gaussian replicas of the data as smooth and as many
  (:func:`_gaussian_advantage`: the largest of 40 replicas' gains plus 0.1):
  then the clean bands keep the default (1.000 and 1.012 times the mean on
  seeds 200-209), and so do most detour sets, which on these sets the mean
  serves as well (default / mean 0.99-1.00, was up to 1.06). That check
  alone let a band of 15 through (seeds 300-304 of the benchmark: two
  demonstrations lie to one side all along the path and the rest bunch, a
  gain of 61 % against the replicas' 36 %; 2.2 times the mean's error on
  that seed), so on smooth data a switch also needs the cross-validation
  below, whatever its confidence (there 65 %: not confirmed): that case
  1.243 -> 1.001 times the mean, the other clean and detour sets on seeds
  0-4, 100-104, 200-204 and 900-904 the same. Local detours of
  the band's size taken by a minority are where it falls short: up to 1.22 times
  the median's or biweight's error (1.29 before the second test). Five seeds
  hardly resolve 1.05 there (a 90 % interval over seeds spans about 0.2), and
  no centre reaches the issue's 0.5 times soft-DTW's error: the band's own
  spread dominates, so even the mean with the detours erased is 0.91-0.95
  times it. Pooled over ten seeds (0-4 and 100-104,
  ``benchmarks/mimic_centres_choice.py``) the default is at most 1.06 times
  the best fixed centre on burrs while the best of its own candidates is
  within 0.99: the choice loses, not the candidates. About 25 variants of
  this rule (thresholds, confidence, cross-validation alone or as the
  selector, fewer candidates) replayed on that evidence each gained on one
  seed set and lost on the other or on clean data (a clean smooth band's seed
  at up to 1.64 times the mean's error), so the rule stands.
  ``center="mean"`` is the thesis's centre; ``center="median"`` the median
  along each normal (in 3-D, the geometric median in the normal plane), with
  the step control then minimising the summed distances; ``center="biweight"``
  Tukey's biweight (tuning constant 4.685, scale from the median absolute
  deviation, reweighted from the median). The consensus ends use the same
  centre on the ends' arc-length positions.
* **Runs.** Burrs and detours are local: contiguous along the path, in a few
  demonstrations. After the adaptive centre has converged, each demonstration's
  residuals from it are averaged over stretches of the path (one normal, 2, 5
  and 12 % of its length) and measured in robust scales of such averages across
  the demonstrations (:func:`_run_weights`). White noise averages out, so a burr
  two or three noise levels high stands out over its width where on its own
  normal it does not. The threshold for each stretch is the largest distance
  seen in 20 replicas of white Gaussian noise on the same normals (at least 4
  scales; 5.7-8.7 measured), the weight falls to 0 at 1.5 times it, stretches
  are taken from the shortest up, each on what the shorter ones kept (so a
  narrow burr is erased over its own width, not over 12 % of the path), and a
  flagged run is grown to where the demonstration comes back within 2.5 scales.
  Where any weight falls, the path is fitted again from there with those
  weights multiplying the centre's own (``center_weights_``; why in
  ``center_reason_``); on Gaussian data none falls and the path is the first
  pass's. Where the deviations are smooth along the path (a band: rank
  correlation from one normal to the next at least 0.7) this rule is not
  used: averaging does not shrink smooth deviations, so a stretch tells no run
  from the spread (calibrated on Gaussian replicas as smooth, it flagged
  clean bands of 15 demonstrations, 2-4 % worse than the mean, and gained
  nothing on detours); runs are found there as the next point says. Measured
  (``python benchmarks/mimic_centres.py --kinds burrs --first-seed 200``, 36
  burr cases x 5 seeds, the seeds it was developed on), the default over the
  best fixed centre, worst per kind, one pass -> two: one-sided burrs 1.079 ->
  1.073 (straight) and 1.087 -> 1.081 (circular), two-sided 1.081 -> 1.018 and
  1.096 -> 1.001; cases within 1.05: 30 -> 34 of 36; where burrs 20 noise
  levels high cover 30 % of 20 profiles 0.62 -> 0.40; on held-out seeds
  100-104 worst 1.072, 1.063, 1.071, 1.061 (one pass: 1.075, 1.091, 1.074,
  1.104), 32 of 36 within 1.05. One-sided burrs 1-2 noise levels high on 30 %
  of each profile were left at 1.07-1.08 (the median or biweight best there);
  with the cheap tunings above (``--kinds burrs``, the same minutes): seeds
  100-104 32 -> 34 of 36 within 1.05 (those cases, straight and circular,
  1.072 and 1.071 -> 1.022 and 1.022), seeds 200-204 34 -> 35 (1.073 and
  1.081 -> 1.034 and 1.061), seeds 0-4 36 of 36 both (1.038 and 1.039 ->
  1.022 and 1.022); clean white noise (seeds 200-209) keeps within 0.4 % of the mean
  (a 2/4/8 tuning, 1 % on Gaussian values, taken by chance in 4-5 of 10); smooth
  sets are not affected. Left: two-sided burrs 15 % x 6 noise levels x 12
  profiles on seeds 100-104 (1.06): there the best estimate is the near-median
  core 0.1, whose variance is estimated from the few per cent of values within
  0.1 scale of the centre and so is the noisiest (its estimates lie below both
  neighbouring cores'); a kernel estimate of that share fixed it but lost where
  the peak is real (two-sided burrs 20 noise levels high over 30 % of 6
  profiles, 0.96 -> 1.07-1.11). Where the near-median core 0.1 was chosen
  and the run pass then flags runs (not detours), the tuning is chosen again
  on the values outside them (``center_reason_`` says so): on tall narrow burrs
  over few profiles the runs take the burrs, and the rest is near-Gaussian,
  where the near-median core is the least efficient. Measured
  (``--kinds burrs``, side by side, cases within 1.05 of 36 per seed block):
  seeds 0-4 36 -> 36 (worst 1.039 -> 1.022), 100-104 34 -> 35 (1.064 ->
  1.051), 200-204 35 -> 35, 300-304 34 -> 35, held out 400-404 36 -> 36 and
  500-504 33 -> 34 (1.102 -> 1.072); e.g. circular one-sided burrs 5 % x 20
  noise levels x 6 profiles 1.051 -> 0.917 (seeds 300-304). Only some 10 of
  180 fits per block change; the price is dense two-sided burrs (30 % x 20
  noise levels x 6 profiles), 0.82-0.93 -> 0.91-1.01. Left: one-sided burrs
  1-2 noise levels high over 30 % of 20 profiles (1.05-1.07 on 300-304 and
  500-504), where the default or a cheap tuning is kept and the median-like
  cores would be 5-13 % better (with the confident choice giving way, above:
  1.006 and 1.012 on 300-304). Choosing again after the runs in every case
  lost: dense burrs' flanks, left in, make the kept values look clean (seeds
  0-4: 36 -> 32 within 1.05). Tried and not kept:
  the choice's bias measured from the pooled values' mode (the
  shortest quarter) instead of zero (that mode lies within 0.1 scale of zero
  there, so nothing changed; each normal's shortest third, not half, lies
  nearer the burrs, not farther: burrs this low overlap the noise, and the
  densest values are where they do); and the tuning chosen again without the runs
  this pass flags (at least 8 kept per normal): two-sided burrs 15 % x 6
  noise levels x 12 profiles went 1.064 -> 1.023 on seeds 100-104, but dense
  burrs lost on both seed sets (30 % x 20 x 20 profiles 0.45 -> 0.53 one-sided,
  0.86 -> 0.94 two-sided; the tests' 12 one-sided profiles 0.62 -> 0.68): the
  burrs' flanks left in make the kept values look clean. The cross-validation
  cannot confirm a smaller bias either: held-out values carry the same
  one-sided burrs, so a squared prediction error favours the mean they pull
  (seed 100 of the failing case: suggested in 75 %, confirmed in 52 %). Cost: the replicas are
  white noise in robust scales, so they depend only on the shape and which
  intersections were found; they are drawn in a fixed order until every
  stretch's maximum so far reaches the data's (more draws only raise the
  thresholds, so no weight could fall: clean data take 1-3 draws), and kept
  per shape and mask for later fits; medians of rows with NaN are taken by
  sorting (:func:`_nanmedian`, equal to NumPy's bit for bit, 7 times faster on
  1000 rows of 100). Weights and paths are those of all 20 draws, bit for bit.
  On a line (2-D demonstrations) a stretch's distances come from each row's
  sorted averages alone (:func:`_line_run`: the shortest half's ends give the
  median distance in closed form; one sort, not three), a replica keeps only
  its largest (:func:`_run_maxima`), and the running median of the scales is
  SciPy's median filter inside the path: a replica costs a third of what it
  did, the numbers are the same to the bit (tested against the general start
  and scale). Further, with the same numbers: the stretches' sums are
  differences of slices of one running sum (:func:`_window_sums`, no gathered
  copies), the rows are grouped by their count of values once per mask
  (:func:`_count_groups`) and the shortest half found on views of all rows:
  20 replicas of 100 x 1000 cost 0.16-0.17 s against 0.20-0.28 s.
* **Detours.** In a smooth band a minority of demonstrations may take a local
  detour (around an obstacle that was there once): on each normal three of ten
  values lie to one side, a few band widths out at the detour's peak, less on
  its flanks, and a centre per normal keeps most of it (the default's error
  was 1.18 times the best fixed centre's and 0.72 times soft-DTW's where
  detours 12 band sds high are taken by 3 of 10). What tells a detour from the
  band's spread is that it is local: each demonstration's distance from its
  normal's robust start, in robust scales (the running median along the path,
  as above), minus its own running median over :data:`_DETOUR_WINDOW` (30 %)
  of the path (its slow offset, which a band's spread is and a detour over
  10-20 % of the path is not), is at most 4.2 scales on clean smooth bands of
  15 demonstrations (seeds 0-9) and 7-20 at detours 12 band sds high. Beyond
  5 scales (on normals met by at least 8 demonstrations, in 3-D too: with
  the 4 of ``da_vinci`` the scale is too noisy) the weight falls, to
  0 at 7.5; a flagged run is grown to where the demonstration comes back
  within 2 scales of its slow offset, and where half a normal's values would
  lose weight none does (a detour is a minority's). Where any does, the
  tuning is chosen again on the rest (the detours made it pick a near-median
  core that the band without them does not want: one seed 0.54 against 0.24
  for the mean without the detours) and the path fitted again from the first
  pass with those weights (``center_weights_``). Measured (``python
  benchmarks/mimic_centres.py --kinds detours detours-dominant clean``),
  detours 12 band sds high taken by 3 of 10, default / soft-DTW 0.72 -> 0.63
  on seeds 0-4 and 0.68 -> 0.62 on seeds 100-104, where the mean of the same
  demonstrations with the detours erased is 0.62 on both (no centre can do
  better than that mean, so the issue's 0.5 is out of reach on these sets);
  default / best fixed centre 1.18 -> 1.02 and 1.03 -> 0.94; on seeds
  200-204 0.72 -> 0.64 (the floor 0.63). Detours the size of the band (2-4
  sds) are mostly below the threshold and stay about as they were (1.00-1.25
  times the best fixed centre before, 1.00-1.22 after, on the three seed
  sets; the interval over five seeds spans about 0.3); the largest loss, 2
  of 8 demonstrations 4 sds out on seeds 200-204, 1.13 -> 1.16, is one seed
  where erasing the two detours moved the path off the truth (their mean
  without the detours is worse there than with them). Clean bands, white
  noise and the burr sets (360 fits, seeds 100-104 and 300-304) lose no
  weight: the same paths. Against the best of four peers (the arc-length
  average, soft-DTW, DBA, GMR) and an oracle that drops each detour's stretch
  from its demonstration (``detour_band(dropped=True)`` in that benchmark):
  at 2-4 band sds the oracle is 0.83-0.95 times the best peer (seeds 0-4 and
  100-104) and the default 0.96-1.02, and a lower threshold does not close
  that gap without a loss on clean bands (there such a detour's peak, 1-4.4
  scales, is no larger than a clean demonstration's); at 12 sds the default
  equals the oracle (0.69 and 0.62), at 20 sds it reaches the issue's 0.5
  (0.49, oracle 0.47). In 3-D each axis of the normal plane is measured on its own (a
  distance in the plane has a larger median, and the threshold sat 1.75
  times higher). The running
  median is taken on every ``window / 15``-th normal and interpolated (a
  window of 300 normals filtered at every one cost 1-3 s on 100 x 1000).
* **Direction.** Demonstrations recorded against the majority's direction are
  reversed (``orient="auto"``, :func:`lfdkit.mimic.orient_demos`, shared by every
  mimicking method); which ones is recorded in ``reversed_``. A path much
  shorter than the demonstrations is refused
  (:func:`lfdkit.mimic.check_one_motion`).
* **Start.** The iteration starts from the point-wise average of the
  demonstrations resampled by arc length (``init="average"``), from one
  demonstration (``init=j``, as in the thesis) or from a given path. The result
  does not depend materially on the choice (tested).
* **Speed.** Against the thesis's Mean-Path done plainly (every normal
  intersected with every demonstration at every iteration,
  ``benchmarks/mimic_speed.py``), 100 demonstrations x 1000 points, CPU s in
  the same run (loaded machine): white noise 0.62 s against 46.3 s (75x; a
  first fit, which draws the Gaussian replicas of the second pass, 0.87 s:
  53x); burrs in 10 of them 1.13 s against 50.9 s (45x; a first fit 2.22 s:
  23x, the 20 replicas' cost; with the line shortcut above, two machine
  states side by side with the unchanged code: 1.09 s against 45.6 s, 42x,
  where the old code's took 2.02 s, 27x; and 1.11 s, 41x, with load 16
  where the old code's was 28x); a smooth band 0.69 s. What keeps it there: the
  tuning choice's Gaussian replicas are drawn only where the deviations are
  smooth (elsewhere they cannot change the choice; they were 40 % of a burred
  fit), the adaptive centre reweights only the normals still moving, a path
  evaluated again unchanged reuses its intersections, and the run distances of
  all stretches share one set of running sums. Burred data cost 3.6-5.3 s before
  (the same minutes: 1.3 and 1.9-2.4 s now, warm and first fit). Then, every
  result the same to the bit (paths, distances, weights and reasons on 170
  fits; ``benchmarks/mimic.py --sections centres`` unchanged): the replicas'
  shortcuts under runs above, the tuning chosen from the first intersections
  before the path is evaluated (once, not twice, where it changes), the
  adaptive weights' taper computed beyond ``lo`` only, and the final
  intersections with the demonstrations themselves taken from the extended
  ones where these lie on a demonstration's own segment (:func:`_real_hits`).
  A burred fit of 100 x 1000, fresh processes alternating with the unchanged
  code (load 8-15 on 2 cores): first fit 1.02-1.12 s against 1.16-1.27 s
  (median of two each, 7 pairs; 0.87 times), later fits 0.84-0.91 s against
  0.93-1.04 s (0.88 times); in ``benchmarks/mimic_speed.py --sets burrs``,
  two pairs of runs in the same minutes, 37.6x and 39.8x (first fit 25.6x and
  29.9x) against 33.5x and 38.5x (25.2x and 26.3x) before, the plain
  Mean-Path at 25.7-28.7 s beside each: one first fit per run follows the load
  as much as the code, and with load 8-15 neither reached the 40x target for
  the first fit. No compiled kernel was added: ``import lfdkit.mimic``
  0.16-0.18 s of CPU and a fresh process's first burred fit 1.90-1.97 s
  against 2.10-2.16 s. Then, the same numbers again (94 fits compared bit for
  bit, 2-D and 3-D): the adaptive centre's distances in a plane from the two
  coordinates' contiguous copies, squared lengths as two products added
  (:func:`_squared_norms`, einsum's numbers in a third of its time), and the
  intersections' sub-chunk balls (:class:`lfdkit.core.geometry.PolylineSet`,
  38 ms against 56 per 100 x 1000 evaluation); ``benchmarks/mimic_speed.py
  --sets burrs``, four pairs of runs beside the unchanged code (load 4-17 on
  2 cores): 45.1x, 41.5x, 37.1x, 46.7x (first fit 31.0x, 30.4x, 28.1x, 38.2x)
  against 34.5x, 35.6x, 32.2x, 42.9x (27.7x, 28.5x, 26.9x, 26.3x), CPU
  0.76-0.99 times (first fit 0.75-0.95). The first fit's 20 Gaussian
  replicas (0.15 s) keep it below 40x on a loaded machine. Then compiled
  (numba, :mod:`lfdkit.mimic._mean_path_kernels`) where NumPy made a dozen
  passes over (m, n) temporaries, every number the same to the bit (166 fits
  of the built-in sets, the centre cases and the speed sets, 2-D and 3-D,
  compared with the unchanged code; tests replace the compiled steps by
  NumPy's and compare whole fits): the adaptive centre's reweighting step in
  2-D (NumPy's pairwise and einsum sums reproduced; 0.6 ms a step against
  3.4), each row's shortest half and median distance after NumPy's sort, the
  running median's cut-short end windows, and, in
  :class:`~lfdkit.core.geometry.PolylineSet`, the chunks' balls and groups of
  chunks under one ball. ``benchmarks/mimic_speed.py --sets burrs``, three
  pairs of runs beside the unchanged code (load 2-6 on 2 cores): 50.0x, 47.5x,
  48.5x (first fit 42.8x, 40.1x, 37.9x) against 38.6x, 37.5x, 38.3x (34.9x,
  28.3x, 28.2x); CPU 0.82 times (first fit 0.75-0.88). The kernels compile
  once per installation (about 5 s more, cached after). Then, the same numbers
  again (166 fits compared bit for bit), compiled where NumPy made (m, n, 2)
  temporaries: a line's direction and projections and the distances from each
  row's start (robust starts and scales, 3 ms against 0.2 per 1000 x 100
  call, and the loss's distances), the run replicas' stretch averages, and
  orientation's all-pairs distances (25 ms against 2), with its 100 x 100
  matrix products on one BLAS thread (15 ms of CPU against 2 where threads
  spin on busy cores). A burred fit of 100 x 1000, fresh processes
  alternating with the unchanged code (five pairs, load 13-20 on 2 cores):
  CPU 0.90 times for a first fit (0.87-0.96), 0.87 times later (0.78-0.89);
  ``benchmarks/mimic_speed.py --sets burrs``, three pairs of runs: 49.7x,
  69.3x, 53.3x (first fit 41.5x, 55.1x, 46.2x) against 55.9x, 55.9x, 52.7x
  (40.8x, 41.2x, 36.5x), the load deciding as much as the code. The four
  kernels add about 2 s to the one-time compilation on a loaded machine.
"""

from __future__ import annotations

import hashlib
import threading
import warnings
from collections import OrderedDict
from typing import Any, ClassVar, Literal

import numpy as np

from lfdkit.core.constraints import Integer, OneOf, Real
from lfdkit.core.estimator import Estimator
from lfdkit.core.geometry import (
    FoldedPathError,
    NormalHits,
    PolylineSet,
    arc_length,
    normal_frames,
    point_tangents,
    project_onto_polyline,
    resample,
    resample_between,
)
from lfdkit.core.validation import check_demos, check_path
from lfdkit.mimic.base import MimicMethod, register
from lfdkit.mimic.orientation import check_one_motion, orient_demos

#: Consensus ends: a demonstration's start (end) is placed on this first (last)
#: fraction of the path's length; far enough in for starts that vary, short of
#: the middle, where a closed or self-approaching path returns near its start.
_END_WINDOW = 0.25
#: Warn when more than this fraction of the final path's normals is under-supported.
_UNSUPPORTED_WARNING = 0.1
#: ``center="adaptive"``: full weight within ``_CORE`` robust scales of the centre,
#: falling smoothly to none at ``_CUTOFF`` (see the module notes).
_CORE, _CUTOFF = 4.0, 8.0
#: ``center="adaptive"``: with fewer intersections than this on a normal (on a normal
#: line, q <= 2; in a normal plane, q = 3) their robust scale is too noisy to tell a
#: swerve from spread, and the centre there is their mean. From five Gaussian values
#: on a line, 14 % of the time one lies past the cutoff of the scale estimated from
#: them; from eight, 2 % (``benchmarks/adaptive_thresholds.py``).
_FEWEST_TO_CUT = {"line": 8, "plane": 4}
_NO_CUT = 1e6
#: ``center="adaptive"``: the cores it chooses from, in robust scales (the first
#: is the default: the mean within 4 scales), and how much lower a smaller core's
#: estimated error must be to replace it (:func:`_choose_tuning`).
Tuning = tuple[float, float, float]
_DEFAULT: Tuning = (_CORE, _CORE, _CUTOFF)
_TUNINGS: tuple[Tuning, ...] = (
    _DEFAULT,
    (2.0, _CORE, _CUTOFF),
    (1.0, _CORE, _CUTOFF),
    (0.5, _CORE, _CUTOFF),
    (0.25, _CORE, _CUTOFF),
    (0.1, _CORE, _CUTOFF),
    (_CORE, 2.0, 4.0),
    (_CORE, 3.0, 6.0),
    (1.0, 2.0, 4.0),
    (0.5, 2.0, 4.0),
)
_SWITCH = 0.95
#: The near-median core: its estimated variance rests on the few per cent of values
#: within 0.1 robust scales of the centre, the noisiest of all (chosen again once the
#: runs are known: see the module notes).
_NOISIEST: Tuning = (0.1, _CORE, _CUTOFF)
#: Short of that, a tuning whose variance on Gaussian values is at most this much above
#: the mean's is taken where its expected gain exceeds its expected cost if wrong.
_CHEAP = 0.15
#: A cheap tuning other than the best estimated must be estimated this much better than
#: the default (a fraction) to be considered: each one more is one more chance on clean
#: data (ten Gaussian profiles: the core of 2 scales estimated 1.3 % better, 55 % of the
#: resamplings, and 4 % worse than the mean measured from the truth).
_CHEAP_OTHER_GAIN = 0.02
#: A confident cheap choice gives way to a more robust cheap tuning only where that one's
#: pooled centre lies off its own on one side in at least this share of the resamplings.
_DRIFT_CONFIDENCE = 0.95
#: Normals (evenly spread along the path) and intersections the choice pools, at most.
_CHOICE_ROWS, _CHOICE_VALUES = 200, 4000
#: The choice's bootstrap: resamplings, stretches of the path, confidence to switch, seed.
_CHOICE_DRAWS, _CHOICE_BLOCKS, _CHOICE_CONFIDENCE, _CHOICE_SEED = 40, 8, 0.9, 20261127
#: Below that confidence, a tuning suggested in this fraction of the resamplings is
#: taken if cross-validation agrees as often (:func:`_cross_validate`).
_CHOICE_SUGGESTED = 0.75
#: The cross-validation: normals at most, demonstrations predicted on each, values
#: their predictions use in all, and the bound on an error (robust scales).
_CV_ROWS, _CV_HELD, _CV_VALUES, _CLIP = 100, 10, 12000, 3.0
#: The Gaussian check (:func:`_gaussian_advantage`): replicas drawn, the quantile of
#: their best tuning's advantage (here their largest) and by how much the data's must
#: exceed it (the band's generator is mildly heavy-tailed itself; a margin for that).
_NULL_DRAWS, _NULL_QUANTILE, _NULL_MARGIN = 40, 1.0, 0.1
#: ... applied where the deviations are smooth along the path: their rank correlation
#: from one normal to the next at least this (clean smooth bands 0.9 and more; white
#: noise with burrs, whose gains are modest but real, far less).
_SMOOTH = 0.7
#: ``center="adaptive"``, second pass (:func:`_run_weights`): the stretches of path over
#: which a demonstration's residuals are averaged (one normal, then fractions of the
#: path: a burr spans 1-6 % of a profile, a detour 10-20 %), the least threshold in
#: robust scales of those averages (the weight of a run falls from 1 there to 0 at twice
#: it) and the Gaussian replicas that may raise it.
_RUN_WINDOWS = (0.0, 0.02, 0.05, 0.12)
_RUN_LO, _RUN_TAPER, _RUN_DRAWS, _RUN_GROW = 4.0, 1.5, 20, 2.5
#: ... where the deviations are smooth (:func:`_detour_weights`): the stretch of path
#: over which a demonstration's own slow offset is its running median (a detour spans
#: 10-20 % of it, a smooth band's deviations change over more), the distance from it
#: in robust scales where a detour's peak is cut, and where its flanks end.
_DETOUR_WINDOW, _DETOUR_LO, _DETOUR_GROW = 0.3, 5.0, 2.0
#: How :func:`_detour_weights` says it erased detours (the tuning is then chosen again).
_DETOURS = "take a local detour"
#: Spreads below this fraction of the coordinates' magnitude count as zero.
_TINY = 1e-12

__all__ = ["MeanPath"]

Center = Literal["adaptive", "mean", "median", "biweight"]


class MeanPath(Estimator):
    """Mean-Path estimator of a generalized path from demonstrations of any length.

    Parameters
    ----------
    n_points : int, default 100
        Number of points of the estimated path (evenly spaced in arc length),
        2 to 1,000,000.
    center : {"adaptive", "mean", "median", "biweight"}, default "adaptive"
        Centre of the intersections along each normal: the mean of those that
        agree (the mean without outliers; see the module notes), the thesis's
        mean, the robust median, or Tukey's biweight.
    tol : float, default 1e-4
        Stop when the residual changes by less than ``tol`` times its value.
    max_iter : int, default 100
        Most accepted iterations.
    init : "average", int or array_like of shape (n, q), default "average"
        Initial Reference-Path: the arc-length point-wise average of the
        demonstrations, demonstration number ``init``, or a given path.
    ends : {"consensus", "normal"}, default "consensus"
        How the path's extent is decided (see the module notes).
    same_direction : bool, default True
        Match only demonstration segments traversed in the reference's direction.
    extend : float, default 0.05
        Length of the straight virtual extension added before the start and after
        the end of each demonstration while fitting, as a fraction of its length
        (see the module notes on misses). Short, because a straight ray departs
        from a curved task; 0 disables it.
    min_support : float, default 0.5
        Fraction of the demonstrations a normal must meet for its point to be
        estimated on its own (at least one demonstration in any case).
    orient : {"auto", "as_given"}, default "auto"
        Reverse demonstrations recorded against the majority's direction (or
        against ``init`` when it is a path), or trust them.
    max_halvings : int, default 5
        Step halvings tried before the iteration is declared stationary.

    Attributes
    ----------
    path_ : ndarray, shape (n_points, q)
        The Mean-Path, in the demonstrations' units.
    distances_ : ndarray, shape (n_demos, n_points, q - 1)
        The Distance-Space: each demonstration's intersection with each normal in
        the local normal frame of the path (in 2-D, signed distance along the left
        normal). NaN where a normal misses a demonstration.
    residual_history_ : ndarray, shape (n_iter_ + 1,)
        e1 = sum of squared normal distances (thesis's tr(ZᵀZ)) for the initial
        path and after every accepted iteration, in units² (virtual extensions
        included).
    residual_ : float
        e1 of the final path to the demonstrations themselves, in units².
    innovation_history_ : ndarray, shape (n_iter_ + 1,)
        e3 = sum over points of the update length |I_i| computed at each of those
        paths, in units; goes to zero at convergence.
    support_ : ndarray of int, shape (n_points,)
        Number of demonstrations each final normal meets.
    reversed_ : ndarray of bool, shape (n_demos,)
        Which demonstrations were reversed before fitting.
    length_ratio_ : float
        The path's length over the median demonstration length (both measured
        through 17 samples, so recording noise does not count); outside 0.8 to
        1.25 a :class:`~lfdkit.mimic.PathLengthWarning` says why
        (:func:`lfdkit.mimic.check_one_motion`).
    center_tuning_ : tuple of float
        ``center="adaptive"``: the chosen ``(core, lo, hi)`` in robust scales:
        Huber's loss within ``core`` (the square throughout when ``core >= lo``),
        the weight tapering from ``lo`` to none at ``hi``; ``(4, 4, 8)`` is the
        default, the mean of the agreeing intersections (see the module notes).
    center_reason_ : str
        Why that tuning: its estimated error against the default's and how
        often a resampling agreed.
    center_weights_ : ndarray, shape (n_demos, n_points)
        ``center="adaptive"``: the weight each demonstration's intersection
        with each normal got in the second pass (0: a run erased; see the
        module notes on runs); all ones where there was none or for the
        other centres.
    center_estimates_ : dict
        Each candidate tuning's estimated squared error at one normal, in squared
        robust scales (empty unless ``center="adaptive"``).
    n_iter_ : int
        Accepted iterations.
    converged_ : bool
        True unless ``max_iter`` was reached.
    stop_reason_ : {"tolerance", "stationary", "max_iter"}
        Why the iteration stopped ("stationary": no step length lowered the residual).

    Examples
    --------
    >>> import numpy as np
    >>> from lfdkit.mimic import MeanPath
    >>> s = np.linspace(0, np.pi, 50)
    >>> demos = [np.column_stack((s, np.sin(s) + d)) for d in (-0.1, 0.0, 0.1)]
    >>> mp = MeanPath(n_points=50).fit(demos)
    >>> bool(np.abs(mp.path_[:, 1] - np.sin(mp.path_[:, 0])).max() < 1e-2)
    True
    """

    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "n_points": Integer(minimum=2),  # at most MAX_POINTS
        "center": OneOf(("adaptive", "mean", "median", "biweight")),
        "ends": OneOf(("consensus", "normal")),
        "orient": OneOf(("auto", "as_given")),
        "tol": Real(allow_zero=True),
        "max_iter": Integer(minimum=0),
        "max_halvings": Integer(minimum=0),
        "extend": Real(allow_zero=True),
        "min_support": Real(allow_zero=True, maximum=1.0, meaning="a fraction"),
    }

    def __init__(
        self,
        n_points: int = 100,
        *,
        center: Center = "adaptive",
        tol: float = 1e-4,
        max_iter: int = 100,
        init: str | int | np.ndarray = "average",
        ends: Literal["consensus", "normal"] = "consensus",
        same_direction: bool = True,
        extend: float = 0.05,
        min_support: float = 0.5,
        orient: Literal["auto", "as_given"] = "auto",
        max_halvings: int = 5,
    ) -> None:
        self.n_points = n_points
        self.center = center
        self.tol = tol
        self.max_iter = max_iter
        self.init = init
        self.ends = ends
        self.same_direction = same_direction
        self.extend = extend
        self.min_support = min_support
        self.orient = orient
        self.max_halvings = max_halvings

    # ------------------------------------------------------------------ fit
    def fit(self, demos: list[np.ndarray], y: None = None, *, check_input: bool = True) -> MeanPath:
        """Compute the Mean-Path of the demonstrations.

        Parameters
        ----------
        demos : list of array_like, each shape (n_points_j, q)
            Demonstrations, q >= 2, lengths may differ.
        y : None
            Ignored (scikit-learn convention).
        check_input : bool
            False: ``demos`` are already validated (finite float64 arrays of one
            dimension ``q >= 2``), e.g. by :meth:`lfdkit.skill.Skill.fit_path`, and
            are not checked again.

        Returns
        -------
        self
        """
        self._validate_params()
        demos = check_demos(demos, "demos") if check_input else list(demos)
        for j, demo in enumerate(demos):
            if not np.any(np.diff(demo, axis=0)):
                raise ValueError(f"demos[{j}]: has zero length (all points coincide)")
        self.reversed_ = np.zeros(len(demos), dtype=bool)
        if self.orient == "auto":
            # A given initial path sets the direction; otherwise the majority does.
            given = (
                None if isinstance(self.init, (str, int, np.integer)) else self._initial_path(demos)
            )
            demos, self.reversed_ = orient_demos(demos, reference=given, method="MeanPath")
        ref = self._initial_path(demos)
        polylines = PolylineSet([_extend(d, self.extend) for d in demos])
        starts = np.array([d[0] for d in demos])
        stops = np.array([d[-1] for d in demos])
        needed = max(1, int(np.ceil(self.min_support * len(demos))))

        ref = self._reparametrise(ref, starts, stops)
        tuning = _DEFAULT
        if self.center == "adaptive":
            # The tuning from the intersections alone; the path evaluated once, with it.
            crossings = polylines.intersect(
                ref, point_tangents(ref), same_direction=self.same_direction
            )
            tuning, estimates, self.center_reason_ = _choose_tuning(
                ref, crossings.points, crossings.found
            )
            self.center_estimates_ = estimates
            state = self._evaluate(ref, polylines, needed, tuning=tuning, known=crossings)
        else:
            state = self._evaluate(ref, polylines, needed)
            self.center_estimates_ = {}
            self.center_reason_ = f"center={self.center!r} as given"
        self.center_tuning_ = tuning
        ref, state, residuals, innovations, n_iter, stop_reason = self._iterate(
            ref, state, polylines, starts, stops, needed, tuning
        )
        self.center_weights_ = np.ones((len(demos), len(ref)))
        if self.center == "adaptive":
            weights, why = _run_weights(ref, state.hits, state.found)
            self.center_reason_ += f"; then {why}"
            if (weights < 1.0).any() and _DETOURS not in why and tuning == _NOISIEST:
                # The near-median core was chosen on the noisiest estimate, with the burrs
                # in; where the runs take the burrs, it is chosen again on the rest.
                rest = state.found & (weights >= 0.99)
                tuning, estimates, again = _choose_tuning(ref, state.hits, rest)
                self.center_estimates_ = estimates
                self.center_tuning_ = tuning
                self.center_reason_ += f"; the near-median core chosen again without them: {again}"
            if (weights < 1.0).any() and _DETOURS in why:
                # The first tuning was chosen with the detours in: on the rest, again.
                rest = state.found & (weights >= 0.99)
                tuning, estimates, again = _choose_tuning(ref, state.hits, rest)
                self.center_estimates_ = estimates
                self.center_tuning_ = tuning
                self.center_reason_ += f"; without them {again}"
            if (weights < 1.0).any():
                # A second pass from the first centre with those runs down-weighted.
                state = self._evaluate(
                    ref, polylines, needed, tuning=tuning, prior=weights, known=state.crossings
                )
                ref, state, more_res, more_inn, more_iter, stop_reason = self._iterate(
                    ref, state, polylines, starts, stops, needed, tuning, weights
                )
                residuals += more_res[1:]
                innovations += more_inn[1:]
                n_iter += more_iter
                self.center_weights_ = weights.T.copy()

        self.path_ = ref
        self.residual_history_ = np.array(residuals)
        self.innovation_history_ = np.array(innovations)
        # Report the real demonstrations only, without their virtual extensions.
        tangents = point_tangents(ref)
        real = _real_hits(state.crossings, polylines, demos, ref, tangents, self.same_direction)
        self.support_ = real.found.sum(axis=1)
        unsupported = int(np.count_nonzero(self.support_ < needed))
        if unsupported > _UNSUPPORTED_WARNING * len(ref):
            warnings.warn(
                f"MeanPath: the normals of {unsupported} of {len(ref)} path points meet fewer "
                f"than {needed} of the {len(demos)} demonstrations; the demonstrations may not "
                "follow one common path (e.g. several distinct motions): check support_",
                RuntimeWarning,
                stacklevel=2,
            )
        self.residual_ = float(np.sum(real.distance[real.found] ** 2))
        frames = normal_frames(tangents)
        offsets = real.points - ref[:, None, :]
        self.distances_ = np.einsum("mnq,mkq->nmk", offsets, frames[:, 1:, :])
        hint = (
            "; ends='normal' keeps the ends where the initial path puts them"
            if self.ends == "consensus"
            else ""
        )
        self.length_ratio_ = check_one_motion(ref, demos, "MeanPath", hint=hint)
        self.n_iter_ = n_iter
        self.stop_reason_ = stop_reason
        self.converged_ = stop_reason != "max_iter"
        self.n_features_in_ = ref.shape[1]
        return self

    def _iterate(self, ref, state, polylines, starts, stops, needed, tuning, prior=None):
        """Thesis Algorithm 1 from ``ref``: steps halved until the loss falls.

        Returns the path, its state, the residual and innovation histories
        (the start's first), the accepted iterations and why it stopped.
        """
        residuals = [state.e1]
        innovations = [state.e3]
        step = 1.0
        n_iter = 0
        stop_reason = "max_iter"
        while n_iter < self.max_iter:
            for _ in range(self.max_halvings + 1):
                try:
                    candidate = self._reparametrise(ref + step * state.innovation, starts, stops)
                    # Scored on the accepted path's scales, so that both losses are one function.
                    new = self._evaluate(
                        candidate, polylines, needed, state.scale, tuning, prior=prior
                    )
                except FoldedPathError:
                    new = None  # the step folded the path back onto itself: a shorter one
                if new is not None and new.loss <= state.loss:
                    break
                step /= 2.0
            else:
                stop_reason = "stationary"
                break
            change = state.loss - new.loss
            if self.center == "adaptive":
                new.rescale(candidate)  # the next step's loss on the new path's own scales
            ref, state, step = candidate, new, 1.0
            n_iter += 1
            residuals.append(state.e1)
            innovations.append(state.e3)
            if change <= self.tol * state.loss or state.loss == 0.0:
                stop_reason = "tolerance"
                break
        return ref, state, residuals, innovations, n_iter, stop_reason

    # ------------------------------------------------------------- helpers
    def _initial_path(self, demos: list[np.ndarray]) -> np.ndarray:
        init = self.init
        if isinstance(init, str):
            if init != "average":
                raise ValueError(f"init: expected 'average', an int or an array, got {init!r}")
            # Imported here so that Mean-Path registers first (mimic/__init__ order).
            from lfdkit.mimic.baselines import pointwise_average

            # Already oriented by fit when asked (orient="auto").
            return pointwise_average(demos, self.n_points, orient="as_given", check_input=False)
        if isinstance(init, (int, np.integer)) and not isinstance(init, bool):
            if not -len(demos) <= init < len(demos):
                raise ValueError(f"init: demo index {init} out of range for {len(demos)} demos")
            return resample(demos[init], self.n_points)
        path = check_path(init, "init", n_dims=demos[0].shape[1])
        return resample(path, self.n_points)

    def _reparametrise(self, path: np.ndarray, starts: np.ndarray, stops: np.ndarray) -> np.ndarray:
        """Respace evenly in arc length, over the consensus extent if asked."""
        if self.ends == "normal":
            return resample(path, self.n_points)
        s_start = _centre_1d(_arc_positions(starts, path, "start"), self.center)
        s_stop = _centre_1d(_arc_positions(stops, path, "stop"), self.center)
        if not s_stop > s_start:
            raise ValueError(
                "demos: their start and end points do not follow one direction along the "
                "path; check that the demonstrations perform the same task"
            )
        return resample_between(path, s_start, s_stop, self.n_points)

    def _evaluate(
        self,
        ref: np.ndarray,
        polylines: PolylineSet,
        needed: int,
        scale: np.ndarray | None = None,
        tuning: Tuning = _DEFAULT,
        prior: np.ndarray | None = None,
        known: NormalHits | None = None,
    ) -> _State:
        """Intersections, residuals and the update direction at a Reference-Path.

        ``center="adaptive"`` measures its loss in robust scales per normal:
        the path's own (``scale=None``), or given ones (a candidate is scored
        on the accepted path's scales). ``prior`` (m, n_demos): weights of
        the intersections from a first centre (:func:`_run_weights`), fixed by
        normal and demonstration, multiplying the centre's own. ``known``: the
        intersections of this same path (with these tangents), reused.
        """
        tangents = point_tangents(ref)
        if known is None:
            hits = polylines.intersect(ref, tangents, same_direction=self.same_direction)
        else:
            hits = known
        found = hits.found
        offsets = hits.points - ref[:, None, :]  # (M, N, q), NaN where missed
        dist = hits.distance
        n_found = int(found.sum())
        if n_found == 0:
            raise ValueError(
                "demos: no normal of the path meets any demonstration; the demonstrations "
                "must follow roughly the same course in the same direction"
            )
        supported = found.sum(axis=1) >= needed
        if not supported.any():
            raise ValueError(
                f"demos: no normal meets at least {needed} demonstrations; lower min_support "
                "or check that the demonstrations follow the same course"
            )
        innovation = np.zeros_like(ref)
        if self.center == "adaptive":
            start, own_scale = _robust_start(offsets, found, tuning)
            innovation[supported] = _adaptive(
                offsets[supported],
                found[supported],
                start[supported],
                own_scale[supported],
                tuning,
                None if prior is None else prior[supported],
            )
        else:
            innovation[supported] = _centre_vectors(
                offsets[supported], found[supported], self.center
            )
        if not supported.all():
            innovation = _fill_unsupported(ref, tangents, innovation, supported)
        d = dist[found]
        e1 = float(np.sum(d**2))
        e3 = float(np.linalg.norm(innovation, axis=1).sum())
        state = _State(hits.points, found, innovation, e1, e3, 0.0, tuning=tuning, prior=prior)
        state.crossings = hits
        if self.center == "mean":
            state.loss = e1 / n_found
        elif self.center == "adaptive":
            state.own_scale = own_scale  # rescale(ref) reuses it once the path is accepted
            state.rescale(ref, own_scale if scale is None else scale)
        else:
            state.loss = float(np.sum(d)) / n_found
        return state


class _State:
    """Evaluation of one Reference-Path (internal)."""

    __slots__ = (
        "crossings",
        "dist",
        "e1",
        "e3",
        "found",
        "hits",
        "innovation",
        "loss",
        "own_scale",
        "prior",
        "scale",
        "tuning",
    )

    def __init__(
        self, hits, found, innovation, e1, e3, loss, scale=None, tuning=_DEFAULT, prior=None
    ) -> None:
        self.hits = hits
        self.found = found
        self.innovation = innovation
        self.e1 = e1
        self.e3 = e3
        self.loss = loss
        self.scale = scale
        self.tuning = tuning
        self.prior = prior
        self.own_scale = None  # the path's own robust scales, once computed
        self.crossings = None  # the NormalHits behind ``hits`` and ``found``
        self.dist = None  # distances (m, n) from the path to ``hits``, zero where not found

    def rescale(self, ref: np.ndarray, scale: np.ndarray | None = None) -> None:
        """``center="adaptive"``: its loss, on the given scales or on its own (``None``).

        The loss is the mean over intersections of ``s² ρ(d / s)``
        (:func:`_adaptive_rho`), ``d`` the distance from the path point to the
        intersection and ``s`` the robust scale of that point's intersections.
        Where half of them coincide (``s = 0``, the centre is that common point)
        it is ``λ d`` instead, the median's loss, which that point minimises;
        ``λ``, the median of the other scales, puts both in units².
        """
        if scale is None:
            if self.own_scale is None:
                offsets = self.hits - ref[:, None, :]
                self.own_scale = _robust_start(offsets, self.found, self.tuning)[1]
            scale = self.own_scale
        self.scale = scale
        if self.dist is None:  # an accepted path is scored twice: on the old scales and its own
            if ref.shape[1] == 2 and self.found.size:  # compiled: the same numbers, 1.3 ms less
                from lfdkit.mimic._mean_path_kernels import found_distances

                self.dist = np.empty(self.found.shape)
                found_distances(
                    np.ascontiguousarray(self.hits, dtype=float),
                    np.ascontiguousarray(self.found),
                    np.ascontiguousarray(ref, dtype=float),
                    0.0,
                    self.dist,
                )
            else:
                offsets = np.where(self.found[..., None], self.hits - ref[:, None, :], 0.0)
                self.dist = np.sqrt(_squared_norms(offsets))
        dist = self.dist
        spread = scale > 0.0
        s = np.where(spread, scale, 1.0)[:, None]
        weight = float(np.median(scale[spread])) if spread.any() else 1.0
        loss = np.where(spread[:, None], _adaptive_rho(dist / s, self.tuning) * s**2, weight * dist)
        if self.prior is None:
            self.loss = float(loss[self.found].sum()) / int(self.found.sum())
        else:
            total = float(self.prior[self.found].sum())
            self.loss = float((self.prior * loss)[self.found].sum()) / max(total, 1e-300)


def _extend(demo: np.ndarray, fraction: float) -> np.ndarray:
    """Demonstration with straight virtual extensions before its start and after its end.

    The end directions are the chords over the first and last 2 % of its length,
    steadier than one noisy segment. A closed or nearly closed demonstration
    (its ends closer than twice the extension) is not extended: its own other
    end already covers where the rays would go, and a ray there, nearer to
    some normals than the real stroke, would pull the path off it.
    """
    if fraction == 0:
        return demo
    s = arc_length(demo)
    ext = fraction * s[-1]
    if np.linalg.norm(demo[-1] - demo[0]) < 2.0 * ext:
        return demo
    reach = 0.02 * s[-1]
    head = demo[min(int(np.searchsorted(s, reach)), len(demo) - 1)] - demo[0]
    tail = demo[-1] - demo[max(int(np.searchsorted(s, s[-1] - reach, side="right")) - 1, 0)]
    return np.vstack(
        (
            demo[0] - ext * head / np.linalg.norm(head),
            demo,
            demo[-1] + ext * tail / np.linalg.norm(tail),
        )
    )


def _real_hits(
    hits: NormalHits,
    polylines: PolylineSet,
    demos: list[np.ndarray],
    ref: np.ndarray,
    tangents: np.ndarray,
    same_direction: bool,
) -> NormalHits:
    """The path's normals intersected with the demonstrations themselves, not their extensions.

    ``hits``: the normals (``ref``, ``tangents``) intersected with
    ``polylines``, the demonstrations as extended by :func:`_extend`. Where
    that nearest crossing lies on a demonstration's own segment, it is the
    nearest of the demonstration too, computed from the same vertices in the
    same way: it is kept. The other normals (a crossing on an extension, or
    none) and crossings within rounding of a vertex (the two sets' on-plane
    tolerances differ) are intersected again, so the result is that of
    ``PolylineSet(demos).intersect`` (up to which of two crossings at exactly
    one distance is taken); on 100 x 1000 points 0.02 s of CPU against 0.07 s.
    """
    points, segment, distance = hits.points.copy(), hits.segment.copy(), hits.distance.copy()
    n_vertices = np.array([len(d) for d in demos])
    head = np.array([len(p) for p in polylines.polylines]) - n_vertices > 0  # extended
    own = segment - head  # the demonstration's own segment
    kept = (segment >= 0) & (own >= 0) & (own < n_vertices - 1)
    # Each kept crossing's segment ends' distances from the normal hyperplane: near one
    # of them (rounding of the vertex onto the plane), intersected again.
    verts = np.concatenate(demos)
    first = np.concatenate(([0], np.cumsum(n_vertices)[:-1]))
    index = np.where(kept, first + own, 0)
    scale = max(float(np.abs(verts).max()), float(np.abs(ref).max())) + 1.0
    for k in (index, index + 1):
        side = np.einsum("mnq,mq->mn", verts[k] - ref[:, None, :], tangents)
        kept &= np.abs(side) > 1e-11 * scale
    segment[kept] = own[kept]
    again = np.flatnonzero(~kept.all(axis=1))
    if len(again):
        # With the row farthest from the origin, so that the tolerance is the same.
        rows = np.union1d(again, [int(np.argmax(np.abs(ref).max(axis=1)))])
        redo = PolylineSet(demos).intersect(
            ref[rows], tangents[rows], same_direction=same_direction
        )
        points[rows], segment[rows], distance[rows] = redo.points, redo.segment, redo.distance
    return NormalHits(points=points, segment=segment, distance=distance)


def _fill_unsupported(
    ref: np.ndarray, tangents: np.ndarray, innovation: np.ndarray, supported: np.ndarray
) -> np.ndarray:
    """Update for points whose normals meet too few demonstrations.

    Their new positions continue the updated well-supported points: linear
    interpolation in arc length across interior gaps, and straight extension
    along the reference's tangent before the first and after the last one.
    """
    s = arc_length(ref)
    idx = np.flatnonzero(supported)
    target = ref + innovation
    out = np.column_stack([np.interp(s, s[idx], target[idx, k]) for k in range(ref.shape[1])])
    for end, side in ((idx[0], s < s[idx[0]]), (idx[-1], s > s[idx[-1]])):
        out[side] = target[end] + (s[side] - s[end])[:, None] * tangents[end]
    return out - ref


def _arc_positions(
    points: np.ndarray, path: np.ndarray, end: Literal["start", "stop"]
) -> np.ndarray:
    """Arc-length position of points near one end of the path, extended past that end.

    Each point is projected onto the path's first (``end="start"``) or last
    (``"stop"``) :data:`_END_WINDOW` of its length only. A closed path passes
    its start again at its end, and a letter's stroke may come back beside
    where it began: projected onto the whole path, such a start would land
    near the end and cut the path short (or, start = end, leave nothing).
    """
    s_path = arc_length(path)
    length = s_path[-1]
    reach = _END_WINDOW * length
    if end == "start":
        last = max(int(np.searchsorted(s_path, reach, side="right")), 2)
        window, offset = path[:last], 0.0
    else:
        first = min(int(np.searchsorted(s_path, length - reach, side="left")) - 1, len(path) - 2)
        first = max(first, 0)
        window, offset = path[first:], s_path[first]
    s, _, _ = project_onto_polyline(points, window)
    s = s + offset
    tol = 1e-12 * length  # a projection clamped to an end lands there only up to rounding
    if end == "start":
        t0 = path[1] - path[0]
        before = (points - path[0]) @ (t0 / np.linalg.norm(t0))
        return np.where(s <= tol, np.minimum(before, 0.0), s)
    t1 = path[-1] - path[-2]
    after = length + (points - path[-1]) @ (t1 / np.linalg.norm(t1))
    return np.where(s >= length - tol, np.maximum(after, length), s)


def _centre_1d(values: np.ndarray, center: Center) -> float:
    if center == "mean":
        return float(np.mean(values))
    if center == "median":
        return float(np.median(values))
    robust = _adaptive if center == "adaptive" else _biweight
    return float(robust(values[None, :, None], np.ones((1, len(values)), bool))[0, 0])


def _centre_vectors(offsets: np.ndarray, found: np.ndarray, center: Center) -> np.ndarray:
    """Centre of each row's found offset vectors, shape (m, q).

    ``offsets`` has shape (m, n, q) with NaN rows where ``found`` is False.
    """
    if center == "mean":
        return np.nanmean(offsets, axis=1)
    if center == "biweight":
        return _biweight(offsets, found)
    if center == "adaptive":
        return _adaptive(offsets, found)
    q = offsets.shape[2]
    if q == 2:
        # Offsets lie on the normal line: the median of their signed lengths.
        signed, unit = _on_line(offsets, found)
        return _nanmedian(signed, axis=1)[:, None] * unit
    return _geometric_median(offsets, found)


def _on_line(offsets: np.ndarray, found: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Signed lengths (m, n) of 2-D offsets along their common line (m, 2), and the line.

    The line's direction is the found offsets' mean (any found offset where the
    mean is ~zero). Computed in one compiled pass per row
    (:func:`lfdkit.mimic._mean_path_kernels.on_line`: the same numbers as the
    NumPy below, 0.2 ms against 3 for 1000 rows of 100).
    """
    m = offsets.shape[0]
    if offsets.ndim == 3 and offsets.shape[2] == 2 and offsets.size:
        from lfdkit.mimic._mean_path_kernels import on_line  # compiled on first use

        signed, unit = np.empty(found.shape), np.empty((m, 2))
        on_line(
            np.ascontiguousarray(offsets, dtype=float), np.ascontiguousarray(found), signed, unit
        )
        return signed, unit
    any_found = np.where(found[..., None], offsets, 0.0)
    # NumPy's nanmean, the same sum and division without its NaN mask (NaN: none found).
    with np.errstate(invalid="ignore", divide="ignore"):
        direction = any_found.sum(axis=1) / found.sum(axis=1)[:, None]
    norm = np.linalg.norm(direction, axis=1, keepdims=True)
    # Any found offset gives the line's direction when the mean is ~zero.
    fallback = any_found[np.arange(m), found.argmax(axis=1)]
    direction = np.where(norm > 1e-15, direction, fallback)
    norm = np.linalg.norm(direction, axis=1, keepdims=True)
    unit = np.divide(direction, norm, out=np.zeros_like(direction), where=norm > 0)
    return np.einsum("mnq,mq->mn", offsets, unit), unit


def _shortest_half(values: np.ndarray, found: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Midpoint and width of each row's shortest interval holding half its found values.

    ``values`` has shape (m, n) (NaN where not found); the interval holds
    ``max(2, ceil(k / 2))`` of the row's ``k`` found values (one value: itself,
    width zero). Of several equally short intervals the middle one is taken.
    """
    mid, width, _, _, _ = _sorted_shortest_half(values, found)
    return mid, width


def _sorted_shortest_half(
    values: np.ndarray, found: np.ndarray, groups: tuple | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_shortest_half`, with each row's found values sorted (inf after them),
    their count and the index of the shortest half's first value (all (m,) but the
    sorted (m, n)). ``groups``: :func:`_count_groups` of ``found``, where known."""
    return _sorted_halves(values, found, groups)[:5]


def _sorted_halves(
    values: np.ndarray, found: np.ndarray, groups: tuple | None = None
) -> tuple[np.ndarray, ...]:
    """:func:`_sorted_shortest_half` and each row's median distance from the midpoint.

    The rows sorted by NumPy, the rest row by row in one compiled pass
    (:func:`lfdkit.mimic._mean_path_kernels.shortest_halves`: the arithmetic
    the vectorised version did, the same numbers bit for bit; 1000 rows of 100,
    sort and median distance included, 0.37 ms against 0.68 for the vectorised
    shortest half alone).
    """
    from lfdkit.mimic._mean_path_kernels import shortest_halves  # compiled on first use

    m, n = values.shape
    counts = found.sum(axis=1) if groups is None else groups[0]
    if m and counts.min() == n:
        ordered = np.sort(values, axis=1)  # every value found: no inf to put in
    else:
        ordered = np.where(found, values, np.inf)
        ordered.sort(axis=1)
    mid, width, median = np.empty(m), np.empty(m), np.empty(m)
    firsts = np.empty(m, dtype=np.int64)
    shortest_halves(
        np.ascontiguousarray(ordered), counts.astype(np.int64), mid, width, firsts, median
    )
    return mid, width, ordered, counts, firsts, median


def _count_groups(found: np.ndarray) -> tuple[np.ndarray, list[tuple[int, np.ndarray | None]]]:
    """Each row's count of found values (m,), and the rows of each count above zero
    (``None``: all of them), for :func:`_sorted_shortest_half`."""
    counts = found.sum(axis=1)
    groups = []
    for k in np.unique(counts):
        if k > 0:
            rows = np.flatnonzero(counts == k)
            groups.append((int(k), None if len(rows) == len(counts) else rows))
    return counts, groups


def _robust_start(
    offsets: np.ndarray, found: np.ndarray, tuning: Tuning = _DEFAULT
) -> tuple[np.ndarray, np.ndarray]:
    """Start (m, q) and robust scale (m,) of each row's found vectors for ``"adaptive"``.

    Each row's own (:func:`_own_start_and_scale`), then: the scales of rows
    with at least :data:`_FEWEST_TO_CUT` values are at least their median along
    the path. Rows with fewer values get, with the default ``core``, a scale no
    distance comes near (their centre is their mean); with a smaller core
    (chosen where the intersections are heavy-tailed, :func:`_choose_tuning`)
    the path's scale, the median of the rows' own, which many values make
    steady where each row's own is not.
    """
    start, own = _own_start_and_scale(offsets, found)
    count = found.sum(axis=1)
    few = count < _FEWEST_TO_CUT["plane" if offsets.shape[2] > 2 else "line"]
    # The demonstrator's spread varies slowly along the path: a normal where some
    # values bunch by chance would otherwise cut the others, and the path jump there.
    estimated = ~few & (own > 0.0)
    scale = own
    if estimated.sum() > 1:
        scale = np.where(estimated, np.maximum(own, np.median(own[estimated])), own)
    if tuning == _DEFAULT:
        # Weights all 1 and the loss the squared distance's: the mean.
        return start, np.where(few & (own > 0.0), _NO_CUT * own, scale)
    measured = (own > 0.0) & (count >= 2)
    if measured.any():
        path_scale = float(np.median(own[measured]))
        scale = np.where(few & (own > 0.0), np.maximum(own, path_scale), scale)
    return start, scale


def _own_start_and_scale(offsets: np.ndarray, found: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start (m, q) and robust scale (m,) of each row's found vectors, row by row.

    On a line (q <= 2) the start is the midpoint of the shortest half of the
    values; in a plane or more the geometric median. The scale is 1.4826 times
    the median distance to the start (the standard deviation for Gaussian
    values), and zero where half the values coincide (the shortest half has
    width zero).
    """
    q = offsets.shape[2]
    with warnings.catch_warnings(), np.errstate(invalid="ignore", divide="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)  # rows that met nothing
        if q <= 2:
            if q == 1:
                signed, unit = np.where(found, offsets[..., 0], np.nan), np.ones((len(offsets), 1))
            else:
                signed, unit = _on_line(offsets, found)
            mid, width = _shortest_half(signed, found)
            start = mid[:, None] * unit
        else:
            start = _geometric_median(offsets, found, n_iter=30)
            width = None
        start = np.nan_to_num(start)
        if q == 2 and found.size:  # compiled, the same numbers without the temporaries
            from lfdkit.mimic._mean_path_kernels import found_distances

            dist = np.empty(found.shape)
            largest = found_distances(
                np.ascontiguousarray(offsets, dtype=float),
                np.ascontiguousarray(found),
                start,
                np.nan,
                dist,
            )
        else:
            pts = np.where(found[..., None], offsets, 0.0)
            dist = np.where(found, np.sqrt(_squared_norms(pts - start[:, None, :])), np.nan)
            largest = np.abs(pts).max()
        scale = np.nan_to_num(1.4826 * _nanmedian(dist, axis=1))
    tiny = _TINY * (1.0 + largest)
    if width is not None:
        scale = np.where(width <= tiny, 0.0, scale)
    return start, np.where(scale <= tiny, 0.0, scale)


def _choose_tuning(
    ref: np.ndarray, hits: np.ndarray, found: np.ndarray
) -> tuple[Tuning, dict[Tuning, float], str]:
    """The adaptive centre's tuning for these intersections, each one's estimated error, and why.

    Each intersection's signed distance (per normal-frame component) from the
    robust start of the *other* intersections on its normal (the midpoint of
    their shortest half, which stays with the majority where residuals lie on
    one side), divided by the running median of the normals' robust scales, is
    pooled along the path: one sample of the residual distribution, hundreds of
    values strong where each normal holds a handful. (Measured from each
    normal's own start, the values that made the start would bunch at zero and
    Gaussian spread would look heavy-tailed.) For each core ``c`` of
    :data:`_CORES` the centre's large-sample behaviour on that sample gives its
    expected squared error at one normal, in squared robust scales:
    ``t² + V / n``, ``t`` its offset from the starts (one-sided residuals pull
    the mean, hardly the median), ``V = E[ψ²] / E[ψ']²`` its variance (Huber's
    formula) and ``n`` the mean number of intersections on a normal. The
    default core stays unless a smaller one's error is below :data:`_SWITCH`
    times its own.
    """
    offsets = hits - ref[:, None, :]
    _, own = _own_start_and_scale(offsets, found)
    count = found.sum(axis=1)
    usable = (own > 0.0) & (count >= 3)
    estimates = {c: float("nan") for c in _TUNINGS}
    if not usable.any():
        return _DEFAULT, estimates, f"{_describe(_DEFAULT)}: no spread to measure"
    # Each normal's own scale, from a handful of values, is noisy: dividing by it
    # would give Gaussian spread heavy tails. The running median along the path
    # is steady and follows a spread that changes along it.
    scale = _running_median(np.where(usable, own, np.nan), max(5, len(own) // 10))
    rows = np.flatnonzero(usable)
    limit = min(_CHOICE_ROWS, max(16, _CHOICE_VALUES // found.shape[1]))
    if len(rows) > limit:  # evenly spread normals are sample enough
        rows = rows[np.linspace(0, len(rows) - 1, limit).round().astype(int)]
    frames = normal_frames(point_tangents(ref))[rows, 1:, :]
    hit = found[rows]
    coords = np.einsum("mnq,mkq->mnk", np.where(hit[..., None], offsets[rows], 0.0), frames)
    n_hits = hit.shape[1]
    others = np.array([np.delete(np.arange(n_hits), j) for j in range(n_hits)])  # (n, n - 1)
    samples = []
    for k in range(coords.shape[2]):
        values = np.where(hit, coords[..., k], np.nan)
        mid, _ = _shortest_half(
            values[:, others].reshape(-1, n_hits - 1), hit[:, others].reshape(-1, n_hits - 1)
        )
        z = (values - mid.reshape(values.shape)) / scale[rows, None]
        samples.append(z[hit])
    n = float(count[rows].mean())
    # The default core on normals met by few demonstrations is their plain mean.
    few = n < _FEWEST_TO_CUT["plane" if ref.shape[1] > 2 else "line"]
    # Bootstrap over demonstrations and stretches of the path together: smooth
    # demonstrations make neighbouring values one piece of evidence, not many.
    rng = np.random.default_rng(_CHOICE_SEED)
    blocks = np.minimum(np.arange(len(rows)) * _CHOICE_BLOCKS // len(rows), _CHOICE_BLOCKS - 1)
    demo_counts = rng.multinomial(n_hits, np.full(n_hits, 1.0 / n_hits), _CHOICE_DRAWS)
    block_counts = rng.multinomial(
        _CHOICE_BLOCKS, np.full(_CHOICE_BLOCKS, 1.0 / _CHOICE_BLOCKS), _CHOICE_DRAWS
    )
    weight = block_counts[:, blocks, None] * demo_counts[:, None, :]  # (draws, rows, demos)
    weight = np.concatenate((np.ones((1, *hit.shape)), weight))[:, hit]  # the data first

    locations: dict[tuple[Tuning, int], np.ndarray] = {}

    def error(tuning: Tuning, weights: np.ndarray) -> np.ndarray:
        total = np.zeros(len(weights))
        where = []
        for values in samples:
            t, variance = _pooled_location(values, weights, tuning, tuning == _DEFAULT and few)
            total += t**2 + variance / n
            where.append(t)
        locations[tuning, len(weights)] = np.array(where)  # (components, weightings)
        return total

    def drifts(i: int, j: int) -> bool:
        """Whether tuning ``i``'s pooled centre lies off tuning ``j``'s on one side (that of
        the data, along their difference) in :data:`_DRIFT_CONFIDENCE` of the resamplings."""
        data = locations[_TUNINGS[i], 1][:, 0] - locations[_TUNINGS[j], 1][:, 0]
        draws = locations[_TUNINGS[i], _CHOICE_DRAWS] - locations[_TUNINGS[j], _CHOICE_DRAWS]
        if not data.any():
            return False
        return bool(np.mean(data @ draws > 0.0) >= _DRIFT_CONFIDENCE)

    # Every candidate on the data, then only the best and the default resampled.
    errors = np.full((len(_TUNINGS), len(weight)), np.nan)
    errors[:, 0] = [error(c, weight[:1])[0] for c in _TUNINGS]
    estimates = {c: float(e) for c, e in zip(_TUNINGS, errors[:, 0], strict=True)}
    best = int(np.argmin(errors[:, 0]))
    for i in {0, best}:
        errors[i, 1:] = error(_TUNINGS[i], weight[1:])
    # Another tuning must win on the data and in most resamplings of them.
    wins = float(np.mean(errors[best, 1:] < errors[0, 1:]))
    figures = (
        f"estimated error {errors[best, 0]:.3g} against {errors[0, 0]:.3g} for the default "
        f"(squared robust scales per normal), lower in {wins:.0%} of {_CHOICE_DRAWS} resamplings"
    )
    if not best:
        return _DEFAULT, estimates, f"{_describe(_DEFAULT)}: no other tuning estimated better"
    smooth = False
    if errors[best, 0] < _SWITCH * errors[0, 0] and wins >= _CHOICE_SUGGESTED:
        # Smooth demonstrations give as many independent values as there are of them, and
        # by chance a few may bunch all along the path: tails that Gaussian demonstrations
        # as smooth show too are no evidence (resampling those few keeps the bunching).
        smoothness = _smoothness(coords, hit)
        smooth = smoothness >= _SMOOTH
        if smooth:
            seen, chance = _gaussian_advantage(coords, hit, few, rng)
            if seen <= chance + _NULL_MARGIN:
                return (
                    _DEFAULT,
                    estimates,
                    (
                        f"{_describe(_DEFAULT)}: the best other, {_describe(_TUNINGS[best])}, "
                        f"gains hardly more on the data ({seen:.0%} lower estimated error) than "
                        f"on Gaussian demonstrations as smooth (up to {chance:.0%} in "
                        f"{_NULL_DRAWS} replicas; needs {_NULL_MARGIN:.0%} more)"
                    ),
                )
            figures += f"; {seen:.0%} lower, Gaussian demonstrations as smooth {chance:.0%}"
        else:
            # The replicas only matter on smooth data (they cost 40 evaluations of every
            # tuning: 40 % of a fit of 100 x 1000 burred points); their draws are taken
            # all the same, so that the generator, and the cross-validation, are unchanged.
            rng.normal(0.0, 1.0, (_NULL_DRAWS, n_hits, n_hits))
            figures += f"; deviations not smooth along the path (rank correlation {smoothness:.2f})"

    def cheap(than: int | None) -> list[tuple[float, int, float, float]]:
        """Cheap tunings whose expected gain exceeds their expected cost if wrong; with
        ``than``, only those more robust than it whose centre drifts off its own."""
        eligible = []
        for i, tuning in enumerate(_TUNINGS[1:], start=1):
            cost = _gaussian_cost(tuning)
            gain = 1.0 - errors[i, 0] / errors[0, 0]
            if cost > _CHEAP or gain < (0.0 if i == best else _CHEAP_OTHER_GAIN):
                continue
            if than is not None and (i == than or cost <= _gaussian_cost(_TUNINGS[than])):
                continue
            if np.isnan(errors[i, 1]):
                errors[i, 1:] = error(tuning, weight[1:])
            won = float(np.mean(errors[i, 1:] < errors[0, 1:]))
            if won >= 0.5 and won * gain > (1.0 - won) * cost:
                if than is None or drifts(i, than):
                    eligible.append((cost, i, won, gain))
        return eligible

    if errors[best, 0] < _SWITCH * errors[0, 0] and wins >= _CHOICE_CONFIDENCE and not smooth:
        # A confident cheap choice may still sit where one-sided residuals within its core
        # pull it: where a more robust cheap tuning's centre lies consistently off its own
        # (the residuals' asymmetry reaches into the core), the estimate, which measures
        # bias from a shortest half pulled the same way, undercounts that tuning's gain.
        if _gaussian_cost(_TUNINGS[best]) <= _CHEAP:
            eligible = cheap(best)
            if eligible:
                cost, i, won, gain = max(eligible)
                return (
                    _TUNINGS[i],
                    estimates,
                    f"{_describe(_TUNINGS[i])}: {figures}; more robust than that, its centre "
                    f"off the best's on one side in {_DRIFT_CONFIDENCE:.0%} of the resamplings "
                    f"or more (one-sided residuals within the core), and its expected gain "
                    f"{won * gain:.3f} above the expected cost if wrong {(1.0 - won) * cost:.3f} "
                    f"(estimated error {errors[i, 0]:.3g}, lower in {won:.0%} of the "
                    f"resamplings; its variance on Gaussian values {cost:.1%} above the mean's)",
                )
        return _TUNINGS[best], estimates, f"{_describe(_TUNINGS[best])}: {figures}"
    if errors[best, 0] < _SWITCH * errors[0, 0] and wins >= _CHOICE_SUGGESTED:
        # Suggested, not sure: a second, independent test decides, predicting each
        # demonstration from the others (it assumes nothing about where the truth is).
        # On smooth data it always does: where a few of the demonstrations lie to one
        # side all along the path and the rest bunch, the estimate (bias measured from
        # the bunch) and its resamplings (which keep the bunch) agree by chance, while
        # predicting each demonstration from the others does not reward the bunch.
        cv_wins, cv_figures = _cross_validate(ref, hits, found, _TUNINGS[best], rng)
        if cv_wins >= _CHOICE_SUGGESTED:
            return (
                _TUNINGS[best],
                estimates,
                f"{_describe(_TUNINGS[best])}: {figures}; confirmed by {cv_figures}",
            )
        figures = f"{figures}; not confirmed by {cv_figures}"
    if _smoothness(coords, hit) < _SMOOTH:
        # Of the cheap tunings whose expected gain exceeds their expected cost if wrong (the
        # others than the best estimated also :data:`_CHEAP_OTHER_GAIN` better), the most
        # robust: where the residuals lie on one side the estimate sees only part of
        # the gain (it measures bias from the shortest half, itself pulled towards them).
        eligible = cheap(None)
        if eligible:
            cost, i, won, gain = max(eligible)
            return (
                _TUNINGS[i],
                estimates,
                f"{_describe(_TUNINGS[i])}: {figures}; the most robust of {len(eligible)} cheap "
                f"tunings whose expected gain exceeds the expected cost if wrong: "
                f"{won * gain:.3f} against {(1.0 - won) * cost:.3f} (estimated error "
                f"{errors[i, 0]:.3g}, lower in {won:.0%} of the resamplings; its variance on "
                f"Gaussian values {cost:.1%} above the mean's)",
            )
    return (
        _DEFAULT,
        estimates,
        (
            f"{_describe(_DEFAULT)}: the best other, {_describe(_TUNINGS[best])}, not clearly "
            f"better ({figures}; needs below {_SWITCH:g} times and "
            + (
                f"{_CHOICE_SUGGESTED:.0%} in both tests, the data being smooth along the path)"
                if smooth
                else f"{_CHOICE_CONFIDENCE:.0%}, or {_CHOICE_SUGGESTED:.0%} in both tests)"
            )
        ),
    )


_GAUSSIAN_COSTS: dict[Tuning, float] = {}


def _gaussian_cost(tuning: Tuning) -> float:
    """How much larger the tuning's variance is than the mean's on Gaussian values (a fraction)."""
    if tuning not in _GAUSSIAN_COSTS:
        from scipy.special import ndtri

        values = ndtri((np.arange(20001) + 0.5) / 20001)
        ones = np.ones((1, len(values)))
        _, variance = _pooled_location(values, ones, tuning, False)
        _GAUSSIAN_COSTS[tuning] = max(0.0, float(variance[0]) / float(np.mean(values**2)) - 1.0)
    return _GAUSSIAN_COSTS[tuning]


def _pooled_errors(coords: np.ndarray, hit: np.ndarray, few: bool) -> np.ndarray:
    """Each candidate's estimated squared error (:func:`_choose_tuning`) from normal-frame values.

    ``coords`` (m, n, k) on ``m`` normals (zero where not ``hit``); the scale is
    the running median of these normals' own robust scales.
    """
    m, n_hits, _ = coords.shape
    _, own = _own_start_and_scale(coords, hit)
    usable = (own > 0.0) & (hit.sum(axis=1) >= 3)
    if usable.sum() < 2:
        return np.full(len(_TUNINGS), np.nan)
    scale = _running_median(np.where(usable, own, np.nan), max(5, m // 10))
    scale = np.where(np.isfinite(scale), scale, np.nanmedian(scale))
    others = np.array([np.delete(np.arange(n_hits), j) for j in range(n_hits)])
    samples = []
    for k in range(coords.shape[2]):
        values = np.where(hit, coords[..., k], np.nan)
        mid, _ = _shortest_half(
            values[:, others].reshape(-1, n_hits - 1), hit[:, others].reshape(-1, n_hits - 1)
        )
        z = (values - mid.reshape(values.shape)) / scale[:, None]
        samples.append(z[hit & usable[:, None]])
    n = float(hit.sum(axis=1).mean())
    ones = np.ones((1, len(samples[0])))
    errors = np.zeros(len(_TUNINGS))
    for i, tuning in enumerate(_TUNINGS):
        for values in samples:
            t, variance = _pooled_location(values, ones, tuning, tuning == _DEFAULT and few)
            errors[i] += t[0] ** 2 + variance[0] / n
    return errors


def _smoothness(coords: np.ndarray, hit: np.ndarray) -> float:
    """Rank correlation of each demonstration's deviation from one normal to the next.

    ``coords`` (m, n, k): deviations from each normal's mean, ranked along the
    path per demonstration and component, correlated at lag one, pooled.
    """
    count = np.maximum(hit.sum(axis=1), 1)[:, None, None]
    centred = np.where(hit[..., None], coords - coords.sum(axis=1, keepdims=True) / count, 0.0)
    ranks = np.argsort(np.argsort(centred, axis=0), axis=0).astype(float)
    ranks -= ranks.mean(axis=0)
    both = hit[1:] & hit[:-1]
    a, b = ranks[1:][both], ranks[:-1][both]
    denominator = np.sqrt((a**2).sum() * (b**2).sum())
    return float((a * b).sum() / denominator) if denominator > 0 else 0.0


def _gaussian_advantage(
    coords: np.ndarray, hit: np.ndarray, few: bool, rng: np.random.Generator
) -> tuple[float, float]:
    """The best other tuning's advantage on the data and on Gaussian replicas of them.

    Advantage: ``1 - error(best) / error(default)`` (:func:`_pooled_errors`).
    A replica mixes the demonstrations' deviations from each normal's mean,
    divided by their standard deviation there, with independent Gaussian
    weights, one set per replica demonstration, and multiplies them by the
    running median of that deviation along the path: along each normal its
    values are Gaussian, their spread changes as slowly as the data's, they
    are as smooth along the path as the data and as many. Returns the data's
    advantage and the :data:`_NULL_QUANTILE` quantile of the replicas'.
    """

    def advantage(values: np.ndarray) -> float:
        errors = _pooled_errors(values, hit, few)
        return float(1.0 - np.nanmin(errors[1:]) / errors[0]) if np.isfinite(errors[0]) else 0.0

    count = np.maximum(hit.sum(axis=1), 1)[:, None, None]
    centred = np.where(hit[..., None], coords - coords.sum(axis=1, keepdims=True) / count, 0.0)
    # Each normal's spread replaced by its running median along the path: the data's
    # slow changes of spread stay (they too make pooled values look heavy-tailed), a
    # burr's or a detour's local rise does not (in every replica it would look so).
    spread = np.sqrt((centred**2).sum(axis=1, keepdims=True) / np.maximum(count - 1, 1))
    centred = np.divide(centred, spread, out=np.zeros_like(centred), where=spread > 0)
    window = max(5, len(coords) // 10)
    slow = np.stack([_running_median(sd, window) for sd in spread[:, 0, :].T], axis=1)
    centred *= np.nan_to_num(slow)[:, None, :]
    n_hits = hit.shape[1]
    mixed = []
    for _ in range(_NULL_DRAWS):
        mixing = rng.normal(0.0, 1.0, (n_hits, n_hits)) / np.sqrt(max(1, n_hits - 1))
        replica = np.einsum("ij,mjk->mik", mixing, centred)
        mixed.append(advantage(np.where(hit[..., None], replica, 0.0)))
    return advantage(coords), float(np.quantile(mixed, _NULL_QUANTILE))


def _cross_validate(
    ref: np.ndarray, hits: np.ndarray, found: np.ndarray, tuning: Tuning, rng: np.random.Generator
) -> tuple[float, str]:
    """How often ``tuning`` predicts held-out intersections better than the default, and why.

    On normals spread along the path, each intersection in turn is predicted
    by both centres of the *other* intersections on its normal (as the fit
    computes them, scales included). Prediction errors, in robust scales of
    the path, are scored by a bounded square ``min(|u|, _CLIP)²``: an
    intersection of the common path scores the centre's own squared error
    plus the demonstrations' spread (the same for both), while a burr or a
    detour scores about ``_CLIP²`` whichever centre predicts it, so it cannot
    reward the centre that follows it. Returns the fraction of resamplings
    (demonstrations and path stretches together) in which ``tuning`` scores lower.
    """
    offsets = hits - ref[:, None, :]
    _, own = _own_start_and_scale(offsets, found)
    usable = (own > 0.0) & (found.sum(axis=1) >= 3)
    scale = _running_median(np.where(usable, own, np.nan), max(5, len(own) // 10))
    n_demos = found.shape[1]
    held = min(n_demos, _CV_HELD)  # demonstrations predicted on each normal
    rows = np.flatnonzero(usable)
    limit = min(_CV_ROWS, max(16, _CV_VALUES // max(1, held * (n_demos - 1))))
    if len(rows) > limit:
        rows = rows[np.linspace(0, len(rows) - 1, limit).round().astype(int)]
    frames = normal_frames(point_tangents(ref))[rows, 1:, :]
    hit = found[rows]
    coords = np.einsum("mnq,mkq->mnk", np.where(hit[..., None], offsets[rows], 0.0), frames)
    coords /= scale[rows, None, None]
    # Which demonstrations each normal predicts: all of them, or a rotating subset.
    order = (np.arange(len(rows))[:, None] * held + np.arange(held)) % n_demos  # (m, held)
    others = np.array([np.delete(np.arange(n_demos), j) for j in range(n_demos)])[order]
    row_of = np.broadcast_to(np.arange(len(rows))[:, None], order.shape)
    rest_found = hit[row_of[..., None], others]  # (m, held, n - 1)
    keep = hit[row_of, order] & (rest_found.sum(axis=2) >= 2)
    if not keep.any():
        return 0.0, "cross-validation (no intersections to predict)"
    rest = coords[row_of[..., None], others][keep]  # (P, n - 1, k)
    rest_found = rest_found[keep]
    target = coords[row_of, order][keep]  # (P, k)
    losses = []
    for candidate in (_DEFAULT, tuning):
        start, row_scale = _robust_start(rest, rest_found, candidate)
        predicted = _adaptive(rest, rest_found, start, row_scale, candidate)
        losses.append(np.minimum(np.linalg.norm(target - predicted, axis=1), _CLIP) ** 2)
    blocks = np.minimum(np.arange(len(rows)) * _CHOICE_BLOCKS // len(rows), _CHOICE_BLOCKS - 1)
    demo_counts = rng.multinomial(n_demos, np.full(n_demos, 1.0 / n_demos), _CHOICE_DRAWS)
    block_counts = rng.multinomial(
        _CHOICE_BLOCKS, np.full(_CHOICE_BLOCKS, 1.0 / _CHOICE_BLOCKS), _CHOICE_DRAWS
    )
    weight = (block_counts[:, blocks, None] * demo_counts[:, order])[:, keep]  # (draws, P)
    wins = float(np.mean(weight @ (losses[0] - losses[1]) > 0.0))
    return wins, (
        f"cross-validation (bounded squared prediction error {losses[1].mean():.3g} against "
        f"{losses[0].mean():.3g}, lower in {wins:.0%} of {_CHOICE_DRAWS} resamplings)"
    )


def _run_distance(coords: np.ndarray, found: np.ndarray, half: int) -> np.ndarray:
    """Each demonstration's residuals averaged along the path, in robust scales of such averages.

    ``coords`` (m, n, k): residuals in the normal frames (zero where not
    ``found``), averaged over the ``2 half + 1`` normals about each (those
    found). Returns (m, n): each average's distance from the robust start of
    the averages on its normal (:func:`_own_start_and_scale`) over their
    robust scale (a running median along the path); zero where not found or
    where there is no spread to measure (e.g. half the values coincide).
    """
    return _run_distances(coords, found, (half,))[0]


def _run_distances(coords: np.ndarray, found: np.ndarray, halves: tuple[int, ...]) -> list:
    """:func:`_run_distance` for several stretches, the running sums taken once."""
    m = len(coords)
    count = np.zeros((m + 1, found.shape[1]))
    count[1:] = np.cumsum(found, axis=0)
    total = np.zeros((m + 1, *coords.shape[1:]))
    total[1:] = np.cumsum(np.where(found[..., None], coords, 0.0), axis=0)
    enough = found.sum(axis=1) >= 3
    out = []
    for half in halves:
        averaged = _window_sums(total, half) / np.maximum(_window_sums(count, half), 1)[..., None]
        if averaged.shape[2] == 1:  # on a line: from the sorted values alone
            mid, scale, _, _ = _line_run(averaged[..., 0], found, enough)
            distance = np.abs(averaged[..., 0] - mid[:, None])
            out.append(np.zeros(found.shape) if scale is None else distance / scale[:, None])
            out[-1][~found] = 0.0
            continue
        start, own = _own_start_and_scale(averaged, found)
        usable = (own > 0.0) & enough
        if not usable.any():
            out.append(np.zeros(found.shape))
            continue
        scale = _running_median(np.where(usable, own, np.nan), max(5, m // 10))
        scale = np.where(np.isfinite(scale), scale, np.median(own[usable]))
        apart = averaged - start[:, None, :]
        distance = np.sqrt(_squared_norms(apart)) / scale[:, None]
        out.append(np.where(found, distance, 0.0))
    return out


def _window_sums(total: np.ndarray, half: int) -> np.ndarray:
    """Sums over the rows within ``half`` of each, cut at the ends, from running sums.

    ``total`` (m + 1, ...): running sums along the rows, zero first. Row ``r``
    of the result is ``total[min(r + half + 1, m)] - total[max(r - half, 0)]``
    (the same subtraction for every row, so the same numbers as indexing
    with those clipped rows), taken on slices: no gathered copies.
    """
    m = len(total) - 1
    width = 2 * half + 1
    if width > m:
        rows = np.arange(m)
        return total[np.minimum(rows + half + 1, m)] - total[np.maximum(rows - half, 0)]
    out = np.empty((m, *total.shape[1:]))
    np.subtract(total[width:], total[: m + 1 - width], out=out[half : m - half])
    np.subtract(total[half + 1 : width], total[0], out=out[:half])
    np.subtract(total[m], total[m - 2 * half : m - half], out=out[m - half :])
    return out


def _run_counts(found: np.ndarray, halves: tuple[int, ...]) -> list[np.ndarray]:
    """For each stretch, how many found values each (m, n) average of :func:`_run_maxima` takes
    (at least 1): the same for every replica of one mask, so taken once for all of them."""
    m = len(found)
    count = np.zeros((m + 1, found.shape[1]))
    count[1:] = np.cumsum(found, axis=0)
    return [np.maximum(_window_sums(count, half), 1) for half in halves]


def _run_maxima(
    coords: np.ndarray,
    found: np.ndarray,
    halves: tuple[int, ...],
    counts: list[np.ndarray] | None = None,
    groups: tuple | None = None,
) -> np.ndarray:
    """The largest :func:`_run_distance` of each stretch, (len(halves),).

    On a line (2-D demonstrations) from :func:`_line_run`, each row's extremes
    only, no (m, n) distances; ``counts``: :func:`_run_counts` of ``found``,
    ``groups``: :func:`_count_groups` of it (both the same for every replica).
    """
    if coords.shape[2] != 1:  # a plane: the start is a line's point, distances 2-D
        return np.array([d.max() for d in _run_distances(coords, found, halves)])
    m, n = found.shape
    if counts is None:
        counts = _run_counts(found, halves)
    if groups is None:
        groups = _count_groups(found)
    from lfdkit.mimic._mean_path_kernels import run_averages  # compiled on first use

    # The running sums and each stretch's averages in one compiled pass each: NumPy's
    # cumulative sum and window sums divided, the same numbers without temporaries.
    values = np.ascontiguousarray(coords[..., 0], dtype=float)
    found = np.ascontiguousarray(found)
    total, averaged = np.empty((m + 1, n)), np.empty((m, n))
    enough = groups[0] >= 3
    out = np.zeros(len(halves))
    for i, (half, taken) in enumerate(zip(halves, counts, strict=True)):
        run_averages(values, found, -half - 1 if i == 0 else half, taken, total, averaged)
        mid, scale, low, high = _line_run(averaged, found, enough, groups)
        if scale is not None and (low < np.inf).any():
            farthest = np.maximum(np.abs(low - mid), np.abs(high - mid)) / scale
            out[i] = max(0.0, farthest[low < np.inf].max())
    return out


def _line_run(
    averaged: np.ndarray, found: np.ndarray, enough: np.ndarray, groups: tuple | None = None
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, np.ndarray]:
    """Start, robust scale (None: no spread) and extremes (m,) of (m, n) averages on a line.

    :func:`_own_start_and_scale` and the running-median scale of
    :func:`_run_distances` for one coordinate, from each row's sorted found
    values alone: the shortest half gives the start, and its ``h = ceil(k / 2)``
    values are the ``h`` nearest to it, so the median distance is the farther
    of its ends (odd ``k``) or the mean of that and the nearest value outside
    it (even ``k``). One sort instead of two (with the running median's, three
    instead of four): the second pass's 20 Gaussian replicas cost a first fit a
    third of what they did. Equal to the full computation to the bit on every
    case tested (a difference could only come from the two ends' distances from
    the start rounding apart, one unit in the last place). Rows with no value:
    extremes inf. ``groups``: :func:`_count_groups` of ``found``, where known.
    """
    m, n = found.shape
    mid, width, ordered, k, _, median = _sorted_halves(averaged, found, groups)
    own = np.where(k <= 1, 0.0, 1.4826 * median)
    low, high = ordered[:, 0], ordered.ravel()[np.arange(m) * n + np.maximum(k - 1, 0)]
    extreme = np.where(k > 0, np.maximum(np.abs(low), np.abs(high)), 0.0)
    tiny = _TINY * (1.0 + extreme.max())
    own = np.where((width <= tiny) | (own <= tiny), 0.0, own)
    usable = (own > 0.0) & enough
    if not usable.any():
        return mid, None, low, high
    scale = _running_median(np.where(usable, own, np.nan), max(5, m // 10))
    if not usable.all():  # else every window has a value
        scale = np.where(np.isfinite(scale), scale, np.median(own[usable]))
    return mid, scale, low, high


#: :func:`_replica_maxima`'s draws by shape and mask: the replicas are white noise in
#: robust scales, so they depend on nothing else, and refits of data of one shape (a
#: batch of skills, cross-validation folds, benchmarks) reuse them. Each entry: the
#: generator where the draws stopped, each draw's maxima (at most 20 x 4 floats) and a
#: lock, so that threads fitting data of one shape draw each replica once.
_REPLICA_CACHE: OrderedDict[tuple, tuple[threading.Lock, np.random.Generator, list[np.ndarray]]] = (
    OrderedDict()
)
_REPLICA_CACHE_SIZE = 64
_REPLICA_LOCK = threading.Lock()


def _replica_maxima(
    shape: tuple[int, ...], found: np.ndarray, halves: tuple[int, ...], observed: np.ndarray
) -> np.ndarray:
    """Largest :func:`_run_distance` per stretch in :data:`_RUN_DRAWS` Gaussian replicas.

    ``shape`` (m, n, k) of the normal-frame residuals, ``found`` (m, n) their
    mask, ``halves`` the stretches' half-widths, ``observed`` the data's largest
    distance per stretch. Returns (len(halves),), at least :data:`_RUN_LO`.
    The distances are in robust scales, so white noise of any level gives the
    same values: they are drawn with a fixed seed, in order, and kept by shape,
    mask and stretches. The draws stop early once every stretch's maximum so
    far (at least :data:`_RUN_LO`) reaches the data's: the thresholds only grow
    with more draws, so no weight could fall below 1 (clean data need 1-3
    draws, not 20). The result depends on the inputs only, cached or not.
    """
    key = (tuple(shape), halves, hashlib.blake2b(np.packbits(found).tobytes()).digest())
    with _REPLICA_LOCK:
        entry = _REPLICA_CACHE.pop(key, None)
        if entry is None:
            entry = (threading.Lock(), np.random.default_rng(_CHOICE_SEED), [])
        _REPLICA_CACHE[key] = entry  # most recently used last
        while len(_REPLICA_CACHE) > _REPLICA_CACHE_SIZE:
            _REPLICA_CACHE.popitem(last=False)
    lock, rng, draws = entry
    seen = np.full(len(halves), _RUN_LO)
    counts: list[np.ndarray] = []  # the mask's, for every replica drawn here
    groups = None
    for i in range(_RUN_DRAWS):
        with lock:  # one thread draws the next replica, the others reuse it
            if i == len(draws):
                counts = counts or _run_counts(found, halves)
                groups = groups or _count_groups(found)
                replica = rng.standard_normal(shape)  # normal(0, 1): the same numbers
                draws.append(_run_maxima(replica, found, halves, counts, groups))
        seen = np.maximum(seen, draws[i])
        if (observed <= seen).all():
            break
    return seen


def _take_run_minimum(weights: np.ndarray, grown: np.ndarray) -> None:
    """Each contiguous run of True in ``grown`` takes its smallest weight, in place.

    Parameters
    ----------
    weights : ndarray, shape (m,)
        One demonstration's weights along the normals (a view is written through).
    grown : ndarray of bool, shape (m,)
        The normals of its flagged runs grown to their flanks.
    """
    edges = np.flatnonzero(np.diff(np.concatenate(([0], grown.astype(int), [0]))))
    for first, last in zip(edges[::2], edges[1::2], strict=True):
        weights[first:last] = weights[first:last].min()


def _run_weights(ref: np.ndarray, hits: np.ndarray, found: np.ndarray) -> tuple[np.ndarray, str]:
    """Weights (m, n_demos) that erase runs where one demonstration strays, and why (or "").

    Burrs and detours are local: contiguous along the path, in a few
    demonstrations. Each demonstration's residuals from the path are averaged
    over stretches of :data:`_RUN_WINDOWS` of it and measured in robust scales
    of such averages across the demonstrations (:func:`_run_distances`). White
    noise averages out, so a burr a few noise levels high stands out over its
    width where on its own normal it does not. Smooth demonstrations hardly
    average out, and a few of them may bunch by chance all along the path, so
    that the others look far: the threshold for each stretch length is
    therefore the largest distance seen in :data:`_RUN_DRAWS` Gaussian
    replicas of the data as smooth and as many (:func:`_gaussian_basis`), at
    least :data:`_RUN_LO`. A weight falls from 1 at that threshold to 0 at
    twice it and is spread over the whole stretch (the least over the
    stretches holding a point), so a run's edges go with it; the least over
    the stretch lengths is kept. Returns all ones and "" where no weight of a
    found intersection is below 0.99.
    """
    m, n_demos = found.shape
    offsets = np.where(found[..., None], hits - ref[:, None, :], 0.0)
    frames = normal_frames(point_tangents(ref))[:, 1:, :]
    coords = np.einsum("mnq,mkq->mnk", offsets, frames)
    smoothness = _smoothness(coords, found)
    if smoothness >= _SMOOTH:
        return _detour_weights(coords, found, smoothness)
    halves = [round(0.5 * fraction * m) for fraction in _RUN_WINDOWS]
    observed = _run_maxima(coords, found, tuple(halves))
    seen = np.full(len(halves), _RUN_LO)
    if (observed > _RUN_LO).any():  # else nothing stands out at all
        seen = _replica_maxima(coords.shape, found, tuple(halves), observed)
    # From the shortest stretch to the longest, each on what the shorter ones kept: a
    # narrow tall burr is erased over its own width, not smeared over a long stretch.
    weights = np.ones((m, n_demos))
    kept = found.copy()
    beyond = np.zeros((m, n_demos), dtype=bool)
    for i, (half, lo) in enumerate(zip(halves, seen, strict=True)):
        distance = _run_distance(coords, kept, half)
        if i < 2:
            beyond |= distance > _RUN_GROW
        v = np.clip((distance - lo) / ((_RUN_TAPER - 1.0) * lo), 0.0, 1.0)
        weight = np.where(kept, (1.0 - v**2) ** 2, 1.0)
        if half:  # the least weight of any stretch holding the point
            padded = np.pad(weight, ((half, half), (0, 0)), constant_values=1.0)
            window = np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1, axis=0)
            weight = window.min(axis=2)
        weights = np.minimum(weights, weight)
        kept = found & (weights >= 0.99)
    low = found & (weights < 0.99)
    if not low.any():
        return np.ones((m, n_demos)), (
            f"no demonstration strays from it in a contiguous run (residuals averaged over "
            f"{', '.join(f'{f:.0%}' for f in _RUN_WINDOWS[1:])} of the path within "
            f"{', '.join(f'{t:.1f}' for t in seen)} robust scales)"
        )
    # A run flagged at its peak is erased out to where the demonstration comes back
    # among the others (within _RUN_GROW robust scales on its own normals and the
    # shortest stretches): a detour's flanks, below the threshold, would still pull.
    for j in np.flatnonzero(low.any(axis=0)):
        _take_run_minimum(weights[:, j], beyond[:, j] | low[:, j])
        low[:, j] = found[:, j] & (weights[:, j] < 0.99)
    strays = np.flatnonzero(low.any(axis=0))
    share = low[:, strays].sum(axis=0) / np.maximum(found[:, strays].sum(axis=0), 1)
    why = (
        f"{len(strays)} of {n_demos} demonstrations stray from it in contiguous runs "
        f"({np.median(share):.0%} of their normals, median): residuals averaged over "
        f"{', '.join(f'{f:.0%}' for f in _RUN_WINDOWS[1:])} of the path beyond "
        f"{', '.join(f'{t:.1f}' for t in seen)} robust scales (the largest in "
        f"{_RUN_DRAWS} replicas of white Gaussian noise, at least {_RUN_LO:g}); those runs "
        "down-weighted (center_weights_) and the path fitted again from there"
    )
    return weights, why


def _detour_weights(
    coords: np.ndarray, found: np.ndarray, smoothness: float
) -> tuple[np.ndarray, str]:
    """:func:`_run_weights` where the deviations are smooth along the path: local detours.

    ``coords`` (m, n, k): residuals in the normal frames, ``found`` (m, n).
    Each intersection's distance from the robust start of its normal, in robust
    scales (a running median along the path), is taken per component (in 3-D
    the normal plane's two axes, the larger counts), and from
    each demonstration's the running median along :data:`_DETOUR_WINDOW` of the
    path is subtracted: its own slow offset, which a smooth band's spread is and
    a local detour (shorter than half that window) is not. What remains beyond
    :data:`_DETOUR_LO` scales on a normal met by at least
    ``_FEWEST_TO_CUT["line"]`` (8) demonstrations is a detour's peak; the weight falls
    from 1 there to 0 at :data:`_RUN_TAPER` times it and the run takes its least
    weight out to where the demonstration comes back within :data:`_DETOUR_GROW`
    scales (its flanks). A minority only: where half the demonstrations on a
    normal would lose weight, none does. Returns all ones where nothing stands
    out, with why.
    """
    m, n_demos = found.shape
    ones = np.ones((m, n_demos))
    count = found.sum(axis=1)
    plain = (
        f"deviations smooth along the path (rank correlation {smoothness:.2f} from one "
        "normal to the next)"
    )
    few = _FEWEST_TO_CUT["line"]  # each component is a line's (in 3-D too)
    enough = count >= 3
    # Component by component (in 3-D, the normal plane's two axes), each on its own
    # line's start and scale: a distance in the plane would have a larger median than
    # a component's, and its thresholds would sit higher.
    z = np.zeros(coords.shape)
    for k in range(coords.shape[2]):
        mid, scale, _, _ = _line_run(coords[..., k], found, enough)
        if scale is not None:
            z[..., k] = (coords[..., k] - mid[:, None]) / scale[:, None]
    if not z.any() or not (count >= few).any():
        return ones, f"{plain}; too few demonstrations per normal to tell a detour"
    # Each demonstration's slow offset: its running median, gaps filled from the
    # nearest found values (a missed normal neither pulls nor breaks the filter).
    rows = np.arange(m)
    filled = np.empty_like(z)
    for j in range(n_demos):
        have = np.flatnonzero(found[:, j])
        if not len(have):
            filled[:, j] = 0.0
            continue
        for k in range(z.shape[2]):
            filled[:, j, k] = np.interp(rows, have, z[have, j, k])
    from scipy.ndimage import median_filter  # imported when first needed

    # On every stride-th normal (about 15 in a window; the slow offset changes slowly),
    # interpolated between: a window of 300 normals filtered at each costs seconds.
    stride = max(1, int(_DETOUR_WINDOW * m) // 15)
    coarse = filled[::stride]
    window = max(3, int(_DETOUR_WINDOW * m / stride) | 1)
    coarse = median_filter(coarse, size=(window, 1, 1), mode="nearest")
    at = rows / stride
    below = np.minimum(at.astype(int), len(coarse) - 1)
    above = np.minimum(below + 1, len(coarse) - 1)
    frac = (at - below)[:, None, None]
    slow = (1.0 - frac) * coarse[below] + frac * coarse[above]
    apart = np.abs(z - slow).max(axis=2)
    apart = np.where(found, apart, 0.0)
    peak = np.where((count >= few)[:, None], apart, 0.0)
    v = np.clip((peak - _DETOUR_LO) / ((_RUN_TAPER - 1.0) * _DETOUR_LO), 0.0, 1.0)
    weights = np.where(found, (1.0 - v**2) ** 2, 1.0)
    flagged = peak > _DETOUR_LO
    if not flagged.any():
        return ones, (
            f"{plain}: no demonstration strays from its own slow offset by more than "
            f"{_DETOUR_LO:g} robust scales (its running median over {_DETOUR_WINDOW:.0%} "
            "of the path subtracted)"
        )
    near = apart > _DETOUR_GROW
    for j in np.flatnonzero(flagged.any(axis=0)):
        _take_run_minimum(weights[:, j], near[:, j] | flagged[:, j])
    low = found & (weights < 0.99)
    majority = low.sum(axis=1) >= 0.5 * count
    weights[majority] = 1.0
    low[majority] = False
    if not low.any():
        return ones, f"{plain}: what strays from its own slow offset is no minority"
    strays = np.flatnonzero(low.any(axis=0))
    share = low[:, strays].sum(axis=0) / np.maximum(found[:, strays].sum(axis=0), 1)
    why = (
        f"{plain}: {len(strays)} of {n_demos} demonstrations {_DETOURS} "
        f"({np.median(share):.0%} of their normals, median): beyond {_DETOUR_LO:g} robust "
        f"scales from their own slow offset (running median over {_DETOUR_WINDOW:.0%} of "
        "the path); those runs down-weighted (center_weights_), the tuning chosen again "
        "on the rest and the path fitted again from there"
    )
    return weights, why


def _describe(tuning: Tuning) -> str:
    """A tuning in words."""
    core, lo, hi = tuning
    inner = "the mean" if core >= lo else f"Huber's within {core:g} robust scales"
    return f"{inner}, weight tapering from {lo:g} to 0 at {hi:g} robust scales"


def _pooled_location(
    values: np.ndarray, weight: np.ndarray, tuning: Tuning, mean: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Location ``t`` and variance ``V`` of the adaptive centre on weighted pooled values.

    ``values`` (N,) in robust scales, ``weight`` (B, N) one weighting per row;
    returns arrays of shape (B,): ``t`` solves ``Σ w ψ(v - t) = 0`` (Newton's
    steps from 0) and ``V = E[ψ²] / E[ψ']²`` (Huber's asymptotic variance).
    """
    total = weight.sum(axis=1)
    t = np.zeros(len(weight))
    for _ in range(50):
        psi, slope = _psi_and_slope(values - t[:, None], tuning, mean)
        step = (weight * psi).sum(1) / np.maximum((weight * slope).sum(1), 1e-3 * total)
        t = t + step
        if np.max(np.abs(step)) < 1e-6:
            break
    psi, slope = _psi_and_slope(values - t[:, None], tuning, mean)
    slope = (weight * slope).sum(1)
    return t, (weight * psi**2).sum(1) * total / np.maximum(slope, 1e-12 * total) ** 2


def _psi_and_slope(u: np.ndarray, tuning: Tuning, mean: bool) -> tuple[np.ndarray, np.ndarray]:
    """Influence ``ψ(u) = u w(|u|)`` of signed distances and its slope (``u`` and 1 if ``mean``)."""
    if mean:
        return u, np.ones_like(u)
    core, lo, hi = tuning
    a = np.abs(u)
    h = hi - lo
    v = np.clip((a - lo) / h, 0.0, 1.0)
    taper = (1.0 - v**2) ** 2
    taper_slope = -4.0 * v * (1.0 - v**2) / h
    if core >= lo:
        return u * taper, taper + a * taper_slope
    inner = a < core
    psi = np.where(inner, u, core * np.sign(u)) * taper
    return psi, np.where(inner, 1.0, core * taper_slope)


def _nanmedian(values: np.ndarray, axis: int = -1, keepdims: bool = False) -> np.ndarray:
    """``np.nanmedian`` along ``axis``, equal to it bit for bit, several times faster.

    NumPy takes small rows through masked arrays (7 ms for 1000 rows of 100 on
    this machine against 2 ms here). NaN sorts last, so each row's median is
    the mean of the middle two of its first ``k`` sorted values (NaN: none).
    (A partition is slower than NumPy's vectorised sort on rows this short.)
    """
    if values.shape[axis] == 0:  # no values at all: NumPy's NaN
        return np.nanmedian(values, axis=axis, keepdims=keepdims)
    ordered = np.sort(values, axis=axis)
    count = np.sum(~np.isnan(values), axis=axis, keepdims=True)
    low = np.take_along_axis(ordered, np.maximum((count - 1) // 2, 0), axis=axis)
    high = np.take_along_axis(ordered, np.maximum(count // 2, 0), axis=axis)
    median = np.where(count > 0, (low + high) / 2.0, np.nan)
    return median if keepdims else np.squeeze(median, axis=axis)


def _running_median(values: np.ndarray, window: int) -> np.ndarray:
    """Median of the non-NaN values within ``window // 2`` places of each one (NaN: none).

    Without NaN the full windows inside are SciPy's median filter (the middle
    value of an odd window: the same number, 10 times faster than sorting
    every window); the ends, where windows are cut short, each the last one
    and a value more, are kept sorted by insertion
    (:func:`lfdkit.mimic._mean_path_kernels.running_median_ends`: the same
    numbers as sorting each, 0.2 ms less per call on 1000 normals).
    """
    half = window // 2
    m = len(values)
    if values.ndim == 1 and half > 0 and m > 4 * half and not np.isnan(values).any():
        from scipy.ndimage import median_filter  # imported when first needed: 0.1 s

        from lfdkit.mimic._mean_path_kernels import running_median_ends  # compiled

        out = median_filter(values, size=2 * half + 1, mode="nearest")
        running_median_ends(np.ascontiguousarray(values, dtype=float), half, out)
        return out
    padded = np.pad(values, half, constant_values=np.nan)
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # windows with no value
        return _nanmedian(windows, axis=1)


def _squared_norms(vectors: np.ndarray) -> np.ndarray:
    """``np.einsum("...q,...q->...", v, v)``: the squared length of each vector, bit for bit.

    With two components the sum is the two squares added in order, as NumPy's
    einsum adds them (tested): on strided slices, three times faster than it.
    """
    if vectors.shape[-1] == 2:
        x, y = vectors[..., 0], vectors[..., 1]
        return x * x + y * y
    return np.einsum("...q,...q->...", vectors, vectors)


def _adaptive_weight(z: np.ndarray, tuning: Tuning = _DEFAULT) -> np.ndarray:
    """Weight of an intersection ``z`` robust scales from the centre: 1, falling to 0.

    ``tuning = (core, lo, hi)``: ``min(1, core / z)`` (Huber's; 1 everywhere
    when ``core >= lo``), tapered smoothly from ``lo`` to none at ``hi``.
    """
    core, lo, hi = tuning
    # Exactly 1 within lo (most intersections): the powers are taken beyond it only.
    beyond = ~(z <= lo)
    taper = np.ones(z.shape)
    v = np.clip((z[beyond] - lo) / (hi - lo), 0.0, 1.0)
    taper[beyond] = (1.0 - v**2) ** 2
    if core >= lo:
        return taper
    with np.errstate(divide="ignore"):
        return np.minimum(1.0, core / z) * taper


def _adaptive_rho(z: np.ndarray, tuning: Tuning = _DEFAULT) -> np.ndarray:
    """The loss whose derivative is ``z * _adaptive_weight(z, tuning)``: flat beyond ``hi``.

    ``z²/2`` within ``core``, Huber's ``core z - core²/2`` from there to
    ``lo``, then the taper's integral.
    """
    core, lo, hi = tuning
    h = hi - lo
    v = np.clip((z - lo) / h, 0.0, 1.0)
    # The taper's terms are exactly zero where v is (most intersections, within lo):
    # the powers, the costly part, are taken beyond it only. The same numbers.
    beyond = ~(v <= 0.0)
    t = v[beyond]
    ramp = np.zeros_like(v)
    if core >= lo:
        ramp[beyond] = h * (
            lo * (t - 2.0 * t**3 / 3.0 + t**5 / 5.0) + h * (1.0 - (1.0 - t**2) ** 3) / 6.0
        )
        return 0.5 * np.minimum(z, lo) ** 2 + ramp
    inner = np.minimum(z, lo)
    huber = np.where(inner <= core, 0.5 * inner**2, core * inner - 0.5 * core**2)
    ramp[beyond] = core * h * (t - 2.0 * t**3 / 3.0 + t**5 / 5.0)
    return huber + ramp


def _adaptive(
    points: np.ndarray,
    found: np.ndarray,
    start: np.ndarray | None = None,
    scale: np.ndarray | None = None,
    tuning: Tuning = _DEFAULT,
    prior: np.ndarray | None = None,
) -> np.ndarray:
    """The adaptive centre of each row's found vectors, shape (m, q) (see the module notes).

    Iteratively reweighted from :func:`_robust_start` (or the given start and
    scale) with the scale fixed, so that the loss falls at every step; rows
    whose scale is zero (half the values coincide) keep their start, that
    common value. ``core``: robust scales within which the loss is the square
    (beyond it Huber's, linear; :func:`_adaptive_weight`). ``prior`` (m, n):
    fixed weights multiplying the centre's own (:func:`_run_weights`).
    """
    if start is None or scale is None:
        start, scale = _robust_start(points, found, tuning)
    pts = np.where(found[..., None], points, 0.0)
    degenerate = scale <= 0.0
    s = np.where(degenerate, 1.0, scale)
    start = np.asarray(start, dtype=float)
    centre = start.copy()
    if pts.shape[2] == 2:
        # In a plane, the step compiled (NumPy's numbers to the bit, one pass over each
        # row, on the rows given without gathering them): 100 x 1000, 6 times faster.
        from lfdkit.mimic._mean_path_kernels import adaptive_step  # compiled on first use

        pts, found = np.ascontiguousarray(pts), np.ascontiguousarray(found)
        start = np.ascontiguousarray(start)
        fixed = np.empty((0, 0)) if prior is None else np.ascontiguousarray(prior, dtype=float)
        core, lo, hi = (float(v) for v in tuning)

        def step(rows: np.ndarray) -> np.ndarray:
            new = np.empty((len(rows), 2))
            adaptive_step(pts, found, s, fixed, start, centre, rows, core, lo, hi, new)
            return new

    else:  # on a line or in 3-D, NumPy's sums differ from a loop's in the last place

        def step(rows: np.ndarray) -> np.ndarray:
            every = len(rows) == len(pts)
            at, on = (pts, found) if every else (pts[rows], found[rows])
            z = np.sqrt(_squared_norms(at - centre[rows][:, None, :])) / s[rows, None]
            w = np.where(on, _adaptive_weight(z, tuning), 0.0)
            if prior is not None:
                w = w * (prior if every else prior[rows])
            total = w.sum(axis=1, keepdims=True)
            weighted = np.einsum("mn,mnq->mq", w, at)
            return np.where(total > 0, weighted / np.maximum(total, 1e-300), start[rows])

    # Only rows still moving are reweighted: most settle in one or two steps (all
    # their values within the core: the mean), a few near burrs take ten or more.
    rows = np.arange(len(centre))
    # A small core converges linearly, as a median's reweighting does.
    for _ in range(50 if tuning == _DEFAULT else 300):
        current = centre[rows]
        new = step(rows)
        atol = 1e-12 * (1.0 + np.abs(centre).max())
        moving = (np.abs(new - current) > atol).any(axis=1)
        centre[rows] = new
        if not moving.any():
            break
        if moving.mean() < 0.75:  # the rows that settled are left as they are
            rows = rows[moving]
    return np.where(degenerate[:, None], start, centre)


def _biweight(
    points: np.ndarray, found: np.ndarray, c: float = 4.685, n_iter: int = 10
) -> np.ndarray:
    """Tukey's biweight location of each row's found vectors, shape (m, q).

    Iteratively reweighted from the (geometric) median, with the scale fixed at
    1.4826 times the median distance to it. Where more than half the points
    coincide the scale is zero and the result is that common point.
    """
    pts = np.where(found[..., None], points, 0.0)
    median = _centre_vectors(points, found, "median")
    dist = np.linalg.norm(pts - median[:, None, :], axis=2)
    scale = 1.4826 * _nanmedian(np.where(found, dist, np.nan), axis=1, keepdims=True)
    # Zero spread (most points coincide, up to rounding): the median is the answer.
    degenerate = scale[:, 0] <= 1e-12 * (1.0 + np.abs(pts).max())
    scale = np.where(degenerate[:, None], 1.0, scale)
    centre = median
    for _ in range(n_iter):
        u = dist / (c * scale)
        w = np.where(found & (u < 1.0), (1.0 - u**2) ** 2, 0.0)
        total = w.sum(1, keepdims=True)
        new = np.where(total > 0, (pts * w[..., None]).sum(1) / np.maximum(total, 1e-300), median)
        converged = np.allclose(new, centre, rtol=0.0, atol=1e-12 * (1.0 + np.abs(centre).max()))
        centre = new
        if converged:
            break
        dist = np.linalg.norm(pts - centre[:, None, :], axis=2)
    return np.where(degenerate[:, None], median, centre)


def _geometric_median(points: np.ndarray, found: np.ndarray, n_iter: int = 100) -> np.ndarray:
    """Weiszfeld's algorithm vectorised over rows; NaN rows (not found) are ignored."""
    weights0 = found.astype(float)
    pts = np.where(found[..., None], points, 0.0)
    centre = (pts * weights0[..., None]).sum(1) / weights0.sum(1, keepdims=True)
    for _ in range(n_iter):
        dist = np.linalg.norm(pts - centre[:, None, :], axis=2)
        w = weights0 / np.maximum(dist, 1e-12)
        new = (pts * w[..., None]).sum(1) / w.sum(1, keepdims=True)
        if np.max(np.abs(new - centre)) < 1e-12 * (1.0 + np.abs(centre).max()):
            return new
        centre = new
    return centre


def _diagnostics(fitted: MeanPath) -> dict[str, object]:
    return {
        "n_iter": int(fitted.n_iter_),
        "residual": float(fitted.residual_),
        "converged": bool(fitted.converged_),
    }


for _key, _label, _center, _color in (
    ("mean_path", "Mean-Path", "adaptive", "#d62728"),
    ("mean_path_mean", "Mean-Path (mean)", "mean", "#8c564b"),
    ("mean_path_median", "Mean-Path (median)", "median", "#ff7f0e"),
    ("mean_path_biweight", "Mean-Path (biweight)", "biweight", "#bcbd22"),
):
    register(
        MimicMethod(
            key=_key,
            label=_label,
            color=_color,
            build=lambda settings, center=_center: MeanPath(
                n_points=settings.n_points, center=center
            ),
            diagnostics=_diagnostics,
            check_input=True,
        )
    )
