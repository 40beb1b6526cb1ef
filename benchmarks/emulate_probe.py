"""Probe the emulation with people unlike ours: ``python benchmarks/emulate_probe.py``.

Variants of the fidelity study's people (other parameters, noise, training
sizes, millimetres, a side-preferring person); ``--list`` names them,
``--variants NAME ...`` runs some. See ``benchmarks/emulate/probe.py``.
"""

import sys
from pathlib import Path

# The benchmarks import _common and the emulate package from this folder.
sys.path.insert(0, str(Path(__file__).resolve().parent))

from emulate.probe import main

if __name__ == "__main__":
    raise SystemExit(main())
