"""The applications built on the layers and the skill, and the user's ways in.

:mod:`.plot` (figures), :mod:`.report` (the HTML report), :mod:`.batch` (many
independent tasks on an executor), :mod:`.evaluation` (the mimic comparison)
sit below the tasks, which use them; :mod:`.cli` (the ``lfdkit`` command) and
:mod:`.teach` (the local web page) are the top floor: they run everything,
tasks included.
"""
