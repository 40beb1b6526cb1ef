"""Data sets: seeded synthetic generators with known ground truth, and loaders.

Every generator returns a :class:`DemoSet` (demonstrations plus the ground-truth
``nominal`` path they were generated around); :func:`load_dataset` builds one by
its short name, a key of :data:`MIMIC_DATASETS` or :data:`CLOSED_DATASETS`.
:func:`load_lasa` reads the LASA handwriting data set (real demonstrations,
optional extra ``lfdkit[lasa]``). :func:`catalog` lists them all (with the
emulation sets of :func:`load_emulation_dataset`) and :func:`export_dataset`
writes any as files ``lfdkit learn`` reads (``lfdkit datasets``).
:mod:`~lfdkit.datasets.robots` ships what running a skill on a robot needs
without a robot of one's own: a timed 3-D reach, a periodic wipe and three arms' URDFs.
"""

from lfdkit.datasets import builtin, emulation, lasa, robots, synthetic
from lfdkit.datasets.builtin import *  # noqa: F403
from lfdkit.datasets.emulation import *  # noqa: F403
from lfdkit.datasets.lasa import *  # noqa: F403
from lfdkit.datasets.robots import *  # noqa: F403
from lfdkit.datasets.synthetic import *  # noqa: F403

# Each module lists what it offers; the package offers all of it.
__all__ = sorted(
    [*builtin.__all__, *emulation.__all__, *lasa.__all__, *robots.__all__, *synthetic.__all__]
)
