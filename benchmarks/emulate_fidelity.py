"""Emulation fidelity: ``python benchmarks/emulate_fidelity.py --quick`` (about 1 min).

The full run drops ``--quick`` (about 5 min). Compare variants of the
emulation layer side by side with ``--skill-option key=value`` (to
``lfdkit.Skill``), ``--plan-option key=value`` (to ``Skill.plan``),
``--fit-option key=value`` (to ``Skill.fit``), each repeatable, and ``--label``
to keep their files apart. The study, its people and its measures are
described in ``benchmarks/emulate/fidelity.py``; the people themselves in
``benchmarks/emulate/people.py``.
"""

import sys
from pathlib import Path

# The benchmarks import _common and the emulate package from this folder.
sys.path.insert(0, str(Path(__file__).resolve().parent))

from emulate.fidelity import main

if __name__ == "__main__":
    raise SystemExit(main())
