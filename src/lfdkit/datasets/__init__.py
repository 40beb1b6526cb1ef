"""Data sets: seeded synthetic generators with known ground truth, and loaders.

Every generator returns a :class:`DemoSet` (demonstrations plus the ground-truth
``nominal`` path they were generated around); :func:`load_dataset` builds one by
its short name, a key of :data:`MIMIC_DATASETS` or :data:`CLOSED_DATASETS`.
:func:`load_lasa` reads the LASA handwriting data set (real demonstrations,
optional extra ``lfdkit[lasa]``).
"""

from lfdkit.datasets.emulation import (
    EMULATION_DATASETS,
    EmulationSet,
    artificial_obstacles,
    da_vinci_marker,
    load_emulation_dataset,
    sweeping,
)
from lfdkit.datasets.lasa import LASA_SHAPES, LasaShape, lasa_available, load_all_lasa, load_lasa
from lfdkit.datasets.synthetic import (
    CLOSED_DATASETS,
    MIMIC_DATASETS,
    RESIDUAL_SHAPES,
    DemoSet,
    Residual,
    closed_circle,
    da_vinci_walls,
    deburring_circular,
    deburring_linear,
    different_extents,
    draw_residuals,
    figure_eight,
    letter_a,
    load_dataset,
    local_detours,
    loops,
    nearly_closed_o,
    noisy_band,
    quasi_circular_band,
    residual_profile,
    uneven_sampling,
    walking_corridor,
)

__all__ = [
    "CLOSED_DATASETS",
    "EMULATION_DATASETS",
    "LASA_SHAPES",
    "MIMIC_DATASETS",
    "RESIDUAL_SHAPES",
    "DemoSet",
    "EmulationSet",
    "LasaShape",
    "Residual",
    "artificial_obstacles",
    "closed_circle",
    "da_vinci_marker",
    "da_vinci_walls",
    "deburring_circular",
    "deburring_linear",
    "different_extents",
    "draw_residuals",
    "figure_eight",
    "lasa_available",
    "letter_a",
    "load_all_lasa",
    "load_dataset",
    "load_emulation_dataset",
    "load_lasa",
    "local_detours",
    "loops",
    "nearly_closed_o",
    "noisy_band",
    "quasi_circular_band",
    "residual_profile",
    "sweeping",
    "uneven_sampling",
    "walking_corridor",
]
