"""File I/O: every file lfdkit reads or writes, one module per concern.

* :mod:`.atomic`: atomic writes and the checks on an output path
  (:func:`atomic_write`, :func:`write_text` for a whole text,
  :func:`check_output_path`, :class:`OutputExistsError`,
  :class:`NotRegularFileError`);
* :mod:`.text`: the strict, bounded reading primitives every reader shares
  (file size and type, UTF-8, CSV cells, demonstration ids, strict JSON);
* :mod:`.demos`: demonstration files, CSV, NPZ and JSON (:func:`load_demos`,
  :func:`save_demos`, :func:`save_path`);
* :mod:`.scenes`: scene files, CSV and JSON (:func:`load_scenes`,
  :func:`load_scene`, :func:`save_scenes`);
* :mod:`.training`: a demonstrations file and its scene file split as a
  skill learns from them (:func:`~.training.read_training_data`);
* :mod:`.skill_file`: the skill file, a fitted skill's state as JSON
  (:func:`read_skill_file`, :func:`write_skill_file`,
  :class:`SkillDocument`, :func:`~.skill_file.to_document`), used by
  :meth:`lfdkit.skill.Skill.save` and :meth:`~lfdkit.skill.Skill.load`.

The data these files hold are :mod:`lfdkit.model.demos` and :mod:`lfdkit.model.scene`
(and the skill's state).
"""

from lfdkit.io.atomic import (
    STALE_TEMP_SECONDS,
    NotRegularFileError,
    OutputExistsError,
    atomic_write,
    check_output_path,
    write_text,
)
from lfdkit.io.demos import (
    JSON_FORMAT,
    JSON_VERSION,
    MAX_NPZ_ARRAY_BYTES,
    MAX_NPZ_MEMBERS,
    SUPPORTED_SUFFIXES,
    load_demos,
    path_csv,
    save_demos,
    save_path,
)
from lfdkit.io.scenes import (
    SCENE_JSON_FORMAT,
    SCENE_JSON_VERSION,
    SCENE_SUFFIXES,
    load_scene,
    load_scenes,
    save_scenes,
)
from lfdkit.io.skill_file import (
    MAX_SKILL_FILE_BYTES,
    SKILL_FILE_LIMITS,
    SKILL_FORMAT,
    SKILL_VERSION,
    SkillDocument,
    read_skill_file,
    write_skill_file,
)
from lfdkit.io.text import MAX_FILE_BYTES, MAX_JSON_DEPTH, json_float_array, load_json

__all__ = [
    "JSON_FORMAT",
    "JSON_VERSION",
    "MAX_FILE_BYTES",
    "MAX_JSON_DEPTH",
    "MAX_NPZ_ARRAY_BYTES",
    "MAX_NPZ_MEMBERS",
    "MAX_SKILL_FILE_BYTES",
    "SCENE_JSON_FORMAT",
    "SCENE_JSON_VERSION",
    "SCENE_SUFFIXES",
    "SKILL_FILE_LIMITS",
    "SKILL_FORMAT",
    "SKILL_VERSION",
    "STALE_TEMP_SECONDS",
    "SUPPORTED_SUFFIXES",
    "NotRegularFileError",
    "OutputExistsError",
    "SkillDocument",
    "atomic_write",
    "check_output_path",
    "json_float_array",
    "load_demos",
    "load_json",
    "load_scene",
    "load_scenes",
    "path_csv",
    "read_skill_file",
    "save_demos",
    "save_path",
    "save_scenes",
    "write_skill_file",
    "write_text",
]
