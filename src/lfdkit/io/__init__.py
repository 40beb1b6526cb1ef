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

from lfdkit.core.lazy import lazy_names

# Loaded on first use (PEP 562): a batch's results file needs .atomic, not the
# demonstration and scene readers (and NumPy) behind them (0.2 s in a fresh process).
__getattr__, __dir__ = lazy_names(
    __name__,
    {
        "STALE_TEMP_SECONDS": "atomic",
        "NotRegularFileError": "atomic",
        "OutputExistsError": "atomic",
        "atomic_write": "atomic",
        "check_output_path": "atomic",
        "write_text": "atomic",
        "JSON_FORMAT": "demos",
        "JSON_VERSION": "demos",
        "MAX_NPZ_ARRAY_BYTES": "demos",
        "MAX_NPZ_MEMBERS": "demos",
        "SUPPORTED_SUFFIXES": "demos",
        "load_demos": "demos",
        "path_csv": "demos",
        "save_demos": "demos",
        "save_path": "demos",
        "SCENE_JSON_FORMAT": "scenes",
        "SCENE_JSON_VERSION": "scenes",
        "SCENE_SUFFIXES": "scenes",
        "load_scene": "scenes",
        "load_scenes": "scenes",
        "save_scenes": "scenes",
        "MAX_SKILL_FILE_BYTES": "skill_file",
        "SKILL_FILE_LIMITS": "skill_file",
        "SKILL_FORMAT": "skill_file",
        "SKILL_VERSION": "skill_file",
        "SkillDocument": "skill_file",
        "read_skill_file": "skill_file",
        "write_skill_file": "skill_file",
        "MAX_FILE_BYTES": "text",
        "MAX_JSON_DEPTH": "text",
        "json_float_array": "text",
        "load_json": "text",
    },
    globals(),
)

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
