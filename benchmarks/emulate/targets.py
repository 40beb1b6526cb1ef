"""The emulation benchmark's targets: PASS/FAIL per target, from every section's results."""

from __future__ import annotations

from .common import sci
from .spec import (
    DMP_FACTOR_TARGET,
    FIT_FULL_TARGET_S,
    FIT_STAGED_TARGET_S,
    LEARNED_VARIANTS,
    MPC_STEP_TARGET_S,
    NO_COLLISION_SCENES,
    PLAN_NAMES,
    PLAN_TARGET_S,
    PR_TARGET,
    RATIO_TARGET,
)


def check_targets(fits, test_rows, held_rows, dmp_rows, speed_result) -> list[dict]:
    checks = []
    for variant in LEARNED_VARIANTS:
        for name in dict.fromkeys(r["dataset"] for r in fits):
            rows = [r for r in fits if r["dataset"] == name and r["nominal"] == variant]
            if not rows:
                continue
            parts, ok = [], True
            for r in rows:
                if r["error"]:
                    parts.append(f"{r['mode']}: error")
                    ok = False
                    continue
                ok &= not r["failing"]
                fails = ", ".join(f"{k} {r['errors'][k] * 100:.0f}%" for k in r["failing"])
                parts.append(f"{r['mode']}: " + (f"fails {fails}" if fails else "all within"))
            checks.append(
                {
                    "target": f"recovery within 10% ({name}, nominal {variant})",
                    "pass": bool(ok),
                    "detail": "; ".join(parts),
                }
            )
        for r in (r for r in test_rows if r["nominal"] == variant):
            prs = [r.get("pr_full"), r.get("pr_mpc")]
            ratios = [r.get("ratio_full"), r.get("ratio_mpc")]

            def show(value, unit, key, r=r):
                if value is not None:
                    return f"{value:.1f}%" if unit == "%" else f"{value:.2f}x"
                return "plans refused" if f"errors_{key}" in r else "no fit"

            checks.append(
                {
                    "target": f"test Pr >= 90% ({r['dataset']}, nominal {variant})",
                    "pass": all(p is not None and p >= PR_TARGET for p in prs),
                    "detail": f"full {show(prs[0], '%', 'full')}, MPC {show(prs[1], '%', 'mpc')}",
                }
            )
            checks.append(
                {
                    "target": f"test MSE_R <= 1.5x true ({r['dataset']}, nominal {variant})",
                    "pass": all(x is not None and x <= RATIO_TARGET for x in ratios),
                    "detail": f"full {show(ratios[0], 'x', 'full')}, "
                    f"MPC {show(ratios[1], 'x', 'mpc')}",
                }
            )
        for key in ("learned_full", "learned_mpc"):
            hits, seen = [], False
            for r in held_rows:
                if r["nominal"] != variant or r["scene"] not in NO_COLLISION_SCENES.get(
                    r["dataset"], ()
                ):
                    continue
                m = r["planners"].get(key)
                if m is None:
                    continue
                seen = True
                if m["collisions"] is None or m["collisions"] > 0:
                    hits.append(f"{r['dataset']} {r['scene']}: {m['collisions']}")
            if seen:
                checks.append(
                    {
                        "target": f"no collision, cluttered + concave ({PLAN_NAMES[key]}, "
                        f"nominal {variant})",
                        "pass": not hits,
                        "detail": "; ".join(hits) or "none",
                    }
                )
        for r in dmp_rows:
            if "skipped" in r or r["nominal"] != variant:
                continue
            factor = r["factor_full"]
            checks.append(
                {
                    "target": f"MSE_R >= 3x lower than DMP+coupling ({r['dataset']}, {variant})",
                    "pass": bool(factor is not None and factor >= DMP_FACTOR_TARGET),
                    "detail": (f"{factor:.1f}x" if factor is not None else "lfdkit plans refused")
                    + f" (DMP {sci(r['test_mse'])}, lfdkit {sci(r['lfdkit_test_mse_full'])})",
                }
            )
    s = speed_result
    fits_s = s["fits"]
    checks.append(
        {
            "target": "IOC fit 8 demos x 100, 2 classes, full horizon < 2 s",
            "pass": fits_s["implicit full"]["median_s"] < FIT_FULL_TARGET_S,
            "detail": f"median {fits_s['implicit full']['median_s']:.2f} s",
        }
    )
    checks.append(
        {
            "target": "IOC fit staged with MPC H=8 < 15 s",
            "pass": fits_s["implicit staged"]["median_s"] < FIT_STAGED_TARGET_S,
            "detail": f"median {fits_s['implicit staged']['median_s']:.2f} s",
        }
    )
    sc = s["scipy"]
    for key in ("full", "staged"):
        ours = s["lfdkit_same_start"][f"lfdkit {key} (same start)"]["median_s"]
        theirs = sc[key]["seconds"] + (sc["full"]["seconds"] if key == "staged" else 0.0)
        checks.append(
            {
                "target": f"faster than the SciPy reference ({key}, same start)",
                "pass": bool(ours < theirs),
                "detail": f"lfdkit {ours:.2f} s vs SciPy {theirs:.1f} s"
                + ("" if sc[key]["finished"] else " (SciPy did not finish)"),
            }
        )
    one = s["planning"]["one cup"]
    checks.append(
        {
            "target": "MPC step H=12 < 1 ms median (sweeping, one cup)",
            "pass": bool(one["window_median_s"] < MPC_STEP_TARGET_S),
            "detail": f"window median {one['window_median_s'] * 1e3:.3f} ms, whole call "
            f"{one['mpc_step_whole_call_s'] * 1e3:.3f} ms/step, max {one['window_max_s'] * 1e3:.2f}"
            " ms",
        }
    )
    clutter = s["planning"]["cluttered (4)"]
    checks.append(
        {
            "target": "MPC step H=12 < 1 ms median (sweeping, cluttered 4)",
            "pass": bool(clutter["window_median_s"] < MPC_STEP_TARGET_S),
            "detail": f"window median {clutter['window_median_s'] * 1e3:.3f} ms, whole call "
            f"{clutter['mpc_step_whole_call_s'] * 1e3:.3f} ms/step",
        }
    )
    for label in ("one cup", "cluttered (4)"):
        p = s["planning"][label]
        checks.append(
            {
                "target": f"100-point full-horizon plan < 100 ms (sweeping, {label})",
                "pass": bool(p["full_median_s"] < PLAN_TARGET_S),
                "detail": f"median {p['full_median_s'] * 1e3:.1f} ms",
            }
        )
    return checks


def print_targets(checks: list[dict]) -> None:
    print("\nTargets")
    for c in checks:
        verdict = "PASS" if c["pass"] else "FAIL"
        print(f"  {verdict}  {c['target']:<72} {c['detail']}")
