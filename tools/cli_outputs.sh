#!/bin/bash
# Write every output of a fixed set of lfdkit commands, for tools/compare_outputs.py.
#
#   tools/cli_outputs.sh CHECKOUT OUTDIR     (CHECKOUT: a source checkout, e.g. a `git worktree`)
#
# Runs, from CHECKOUT/src: lfdkit demo -q; learn/plan/plot of the README on the demo's files;
# plan --velocities and --duration; execute --no-sim; datasets export + learn --units mm + plan;
# datasets; and the --help of every command and subcommand (help.txt). Works on the layout
# before issue 28 (lfdkit.cli) and after (lfdkit.app.cli).
set -u
SRC=$(cd "$1" && pwd); OUT=$2
rm -rf "$OUT"; mkdir -p "$OUT"; cd "$OUT" || exit 1
export PYTHONPATH=$SRC/src OMP_NUM_THREADS=1 MPLBACKEND=Agg
M=lfdkit.cli; [ -e "$SRC/src/lfdkit/app" ] && M=lfdkit.app.cli
run() { echo "+ $*" >> log.txt; python -c "import sys; from $M import main; sys.exit(main())" "$@" >> log.txt 2>&1; echo "rc=$?" >> log.txt; }
run demo -o demo -q
run learn demo/data/demos.csv --scenes demo/data/scenes.csv -o skill.json
run plan skill.json --goal 0.36,0.5 --obstacle cup:-0.05,0.47,r=0.03 --obstacle marker:0.1,0.44 -o path.csv
run plot skill.json --goal 0.36,0.5 --obstacle cup:-0.05,0.47,r=0.03 --demos demo/data/test_demos.csv -o skill.png
run plan skill.json --goal 0.36,0.5 --velocities -o vel.csv
run plan skill.json --goal 0.36,0.5 --duration 8 -o path8.csv
run execute skill.json --goal 0.36,0.5 --obstacle cup:-0.05,0.49 --obstacle marker:0.15,0.455 --no-sim -o run
run datasets export deburring_circular -o deburring.csv
run learn deburring.csv --units mm -o deburring.json
run plan deburring.json -o deb_path.csv
run datasets
COLUMNS=100 python - "$M" > help.txt 2>&1 <<'PY'
import contextlib, importlib, io, sys
main = importlib.import_module(sys.argv[1]).main
for c in [[], ["learn"], ["plan"], ["plot"], ["execute"], ["demo"], ["compare"], ["import"],
          ["datasets"], ["datasets", "list"], ["datasets", "export"], ["batch"], ["batch", "learn"],
          ["batch", "evaluate"], ["teach"], ["bench"]]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main([*c, "--help"])
        except SystemExit as e:
            code = e.code
    print(f"=== {' '.join(c) or '(top)'} exit {code}\n{out.getvalue()}{err.getvalue()}")
PY
