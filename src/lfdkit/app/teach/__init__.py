"""Teach by drawing: a local web page to show, learn and try a skill live (``lfdkit teach``).

The page (``static/``: one HTML file, a hand-written script and a style
sheet; nothing from a CDN) lets a person draw demonstrations with a mouse,
pen or finger on a metric canvas, place obstacles and mark which
demonstrations swerved around which, learn a :class:`lfdkit.skill.Skill`
with the code of ``lfdkit learn`` (:func:`lfdkit.skill.learn`), look at its
layers (demonstrations, generalized path and Distance-Space, DMP to the
current goal, the learned reward as a heat map and each class's parameters)
and then drag the start, the goal and the obstacles while the plan follows.

Modules
-------
:mod:`.session`
    What one browser tab owns (its drawing is sent with each request; its
    learned skill and learning job stay here), the checks on every field of
    a request, and the work: learn, layers, plan, heat map, exports.
:mod:`.app`
    The Starlette application: routes, the body-size limit, errors as JSON.
:mod:`.server`
    :func:`serve`, the uvicorn server behind the ``lfdkit teach`` command.

Starlette and uvicorn are the optional extra ``teach``
(``pip install "lfdkit[teach]"``); they are imported only here, so the rest of
lfdkit does not need them.
"""

from __future__ import annotations

from lfdkit.core.lazy import lazy_names

__all__ = ["create_app", "serve"]

# Loaded on first use: Starlette and uvicorn are imported by these modules only.
__getattr__, __dir__ = lazy_names(__name__, {"create_app": "app", "serve": "server"}, globals())
