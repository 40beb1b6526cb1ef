"""Compatibility: the scene names that used to live here.

The data model moved to :mod:`lfdkit.scene` (:class:`~lfdkit.scene.Scene`,
:class:`~lfdkit.scene.Obstacle`) and the scene files to
:mod:`lfdkit.io.scenes` (:func:`~lfdkit.io.scenes.load_scenes`,
:func:`~lfdkit.io.scenes.load_scene`, :func:`~lfdkit.io.scenes.save_scenes`
and the ``SCENE_*`` constants). This module re-exports both, so that
``from lfdkit.emulate.scene import Scene`` keeps working; new code imports
from the new homes.
"""

from lfdkit.io.scenes import *  # noqa: F403
from lfdkit.io.scenes import __all__ as _files
from lfdkit.scene import *  # noqa: F403
from lfdkit.scene import __all__ as _model

__all__ = [*_model, *_files]
