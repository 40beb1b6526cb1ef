"""The ``lfdkit`` command.

Subcommands: ``demo`` (the whole workflow on the built-in sweeping example),
``learn`` (a skill from demonstration files), ``plan`` (a path for a new
start, goal and scene), ``plot`` (a skill's reward, demonstrations and plan),
``import`` (demonstrations from ROS bags and MCAP recordings), ``execute``
(a skill on a UR arm: poses, joints, URScript, a MuJoCo check),
``compare`` (the mimicking methods on the built-in data sets), ``datasets``
(list the built-in data sets, or export one as files ``learn`` reads),
``bench`` (the benchmarks: ``--benchmarks DIR``, ./benchmarks or the source
checkout's) and ``teach`` (a local web page to draw demonstrations, learn and
try the skill live; the optional extra ``teach``).

Lengths are in the unit ``--units`` names (``m``, ``cm`` or ``mm``): for
``learn`` the demonstrations' (stored in the skill, default metres); for
``plan`` and ``plot`` the numbers and files of the command line (default the
skill's); for ``compare`` the table and figures (default each data set's own).

Exit codes: 0 success, 1 the work failed (the reason on stderr in one line,
never a traceback; ``-v`` adds it for an unexpected failure), 2 wrong usage
(argparse, or a folder given or looked for that is not there), 130
interrupted (Ctrl-C). Progress and warnings go to stderr: on a terminal a
bar per stage of the work under a clock of the whole command
(:mod:`lfdkit.core.progress`), with ``--verbose`` a line per stage with its wall
time; ``--quiet`` prints nothing on success. Every time a command reports is
counted from the start of :func:`main`. Output files are checked (exists
without ``--force``, folder missing or not writable) before the work.

Modules: :mod:`.entry` (``main``, the parser, the plumbing), one module per
command (:mod:`.learn`, :mod:`.plan`, ... each with ``run_command(args)`` and
``add_options(parser)``), :mod:`.common` (what several commands share) and
two option modules: :mod:`.via` (``--via``) and :mod:`.periodic` (``learn
--periodic``, and ``plan``/``plot``/``execute`` of a periodic skill, whose file
says which kind of skill it is).
"""

from lfdkit.app.cli.entry import main

__all__ = ["main"]
