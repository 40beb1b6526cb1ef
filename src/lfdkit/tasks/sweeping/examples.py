"""The example files of the sweeping task, shipped with lfdkit (the inputs of ``lfdkit demo``).

``data/`` (beside this module) holds the sweeping task of thesis §6.4 as a
user would record it, in the file formats lfdkit reads:

``demos.csv``
    Five clean sweeps (ids ``free-1`` … ``free-5``) and eight sweeps around one
    obstacle each (``cup-1`` … ``cup-4``, ``marker-1`` … ``marker-4``), metres.
``scenes.csv``
    The obstacle of each obstacle sweep: demo id, class, position, radius.
``test_demos.csv``, ``test_scenes.csv``
    Four held-out sweeps (two per class) and their scenes, for scoring.

They are made by the synthetic demonstrator
(:func:`lfdkit.datasets.emulation.sweeping` with ``seed=0``, whose true reward
is known) and can be rebuilt with :func:`write_example_files`; a test checks
that the shipped files equal what it writes.
"""

from __future__ import annotations

import os
from pathlib import Path

from lfdkit.datasets.emulation import EmulationSet, sweeping
from lfdkit.io import save_demos
from lfdkit.io.scenes import save_scenes

__all__ = ["EXAMPLE_SEED", "example_dataset", "example_files", "write_example_files"]

#: Seed of the synthetic demonstrator that made the shipped files.
EXAMPLE_SEED = 0
_DATA = Path(__file__).with_name("data")
_FILES = ("demos.csv", "scenes.csv", "test_demos.csv", "test_scenes.csv")
#: The examples shipped, by name: the sweeping task's.
_EXAMPLES = {"sweeping": _DATA}


def example_dataset() -> EmulationSet:
    """The synthetic sweeping data set the shipped files come from (with its ground truth)."""
    return sweeping(seed=EXAMPLE_SEED)


def example_files(name: str = "sweeping") -> dict[str, Path]:
    """Paths of the shipped example files, keyed by stem (``"demos"``, ``"scenes"``, ...).

    Raises
    ------
    ValueError
        If there is no example of that name.
    """
    folder = _EXAMPLES.get(name)
    if folder is None:
        raise ValueError(f"name: no example {name!r}; available: {', '.join(sorted(_EXAMPLES))}")
    return {Path(f).stem: folder / f for f in _FILES}


def write_example_files(
    directory: str | os.PathLike[str], *, overwrite: bool = False
) -> dict[str, Path]:
    """Write the sweeping example files into ``directory`` (which must exist).

    Returns
    -------
    dict of str to Path
        The files written, keyed by stem as in :func:`example_files`.
    """
    data = example_dataset()
    folder = Path(directory)
    labels = [scene.labels[0] for scene in data.scenes]
    counter: dict[str, int] = {}
    obstacle_ids = []
    for label in labels:
        counter[label] = counter.get(label, 0) + 1
        obstacle_ids.append(f"{label}-{counter[label]}")
    free_ids = [f"free-{j + 1}" for j in range(len(data.free_demos))]
    train, test = list(data.train), list(data.test)
    paths = {stem: folder / f"{stem}.csv" for stem in (Path(f).stem for f in _FILES)}
    save_demos(
        paths["demos"],
        [*data.free_demos, *(data.demos[j] for j in train)],
        ids=[*free_ids, *(obstacle_ids[j] for j in train)],
        overwrite=overwrite,
    )
    save_scenes(
        paths["scenes"], {obstacle_ids[j]: data.scenes[j] for j in train}, overwrite=overwrite
    )
    save_demos(
        paths["test_demos"],
        [data.demos[j] for j in test],
        ids=[obstacle_ids[j] for j in test],
        overwrite=overwrite,
    )
    save_scenes(
        paths["test_scenes"], {obstacle_ids[j]: data.scenes[j] for j in test}, overwrite=overwrite
    )
    return paths
