"""``python benchmarks/emulate``: run the emulation benchmark (see the package's notes)."""

import sys
from pathlib import Path

# Run as a folder, Python puts this folder first on the path; the benchmarks import
# _common and this package as ``emulate`` from the folder above instead.
_here = Path(__file__).resolve().parent
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != _here]
sys.path.insert(0, str(_here.parent))

from emulate.run import main  # noqa: E402

raise SystemExit(main())
