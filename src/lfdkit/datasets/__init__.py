"""Data sets: seeded synthetic generators with known ground truth, and loaders.

Every generator returns a :class:`DemoSet` (demonstrations plus the ground-truth
``nominal`` path they were generated around); :func:`load_dataset` builds one by
its short name, a key of :data:`MIMIC_DATASETS` or :data:`CLOSED_DATASETS`.
:func:`load_lasa` reads the LASA handwriting data set (real demonstrations,
optional extra ``lfdkit[lasa]``).
"""

from lfdkit.datasets import emulation, lasa, synthetic
from lfdkit.datasets.emulation import *  # noqa: F403
from lfdkit.datasets.lasa import *  # noqa: F403
from lfdkit.datasets.synthetic import *  # noqa: F403

# Each module lists what it offers; the package offers all of it.
__all__ = sorted([*emulation.__all__, *lasa.__all__, *synthetic.__all__])
