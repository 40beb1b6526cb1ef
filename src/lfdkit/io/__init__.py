"""File I/O: every file lfdkit reads or writes.

* :mod:`.scenes`: scene files (the obstacles of each demonstration).
"""

from lfdkit.io.scenes import (
    SCENE_JSON_FORMAT,
    SCENE_JSON_VERSION,
    SCENE_SUFFIXES,
    load_scene,
    load_scenes,
    save_scenes,
)

__all__ = [
    "SCENE_JSON_FORMAT",
    "SCENE_JSON_VERSION",
    "SCENE_SUFFIXES",
    "load_scene",
    "load_scenes",
    "save_scenes",
]
