"""The Starlette application behind ``lfdkit teach``: the page, its JSON API, its limits.

Why Starlette: a small, well-kept ASGI toolkit (routing, static files,
responses, a test client) with no template engine, ORM or front-end build to
carry; uvicorn serves it. The page is plain HTML, CSS and one hand-written
script shipped in ``static/``, so it works offline.

API (every ``/api`` request but ``POST /api/session`` carries the tab's id in
the ``X-Lfdkit-Session`` header; a custom header also keeps other web sites'
pages from posting to the server, which answers no cross-origin request):

=====================================  ========================================================
``POST /api/session``                  a new session id, the limits and the default view
``GET  /api/example``                  the shipped sweeping demonstrations and scenes
``POST /api/import/K``                 an uploaded file (body, ``?format=csv|json|npz``),
                                       ``K`` is ``demos`` or ``scenes``
``POST /api/export/K``                 ``demos.csv`` / ``scenes.csv`` of the drawing sent
``POST /api/learn``                    learn from the drawing sent (a worker thread)
``GET  /api/learn``                    the job's state and progress lines; the layers when done
``POST /api/plan``                     plan for a start, goal and obstacles (+ heat map)
``POST /api/plan/frames``              the task-frame skill's plan for the frames' poses,
                                       ``{"frames": {name: [x, y, angle]}}`` (m, rad), and
                                       its warnings
``GET  /api/export/skill``             the skill file (``Skill.save``'s bytes)
``GET  /api/export/task-frame-skill``  the task-frame skill's file (``TaskFrameSkill.save``'s
                                       bytes, ``lfdkit learn --task-frames``'s)
``POST /api/export/plan``              the plan as ``t,x,y`` CSV
``POST /api/export/urscript``          the UR5 program of the plan
=====================================  ========================================================

A learn whose clean demonstrations all recorded the same task frames also
learns a task-frame skill from them (``GET /api/learn``'s ``layers.task_frames``: its
frames and where to start them; null when none was learned, and a progress
line says why).

Errors are ``{"error": "<one line>"}`` with a 4xx status (5xx for a bug, whose
traceback goes to the server's log, never to the page). Bodies over
``LIMITS["max_body_bytes"]`` get 413.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from lfdkit.app.teach import session as work
from lfdkit.app.teach.session import LIMITS, VIEW, RequestError, SessionStore

__all__ = ["LOOPBACK_HOSTS", "SESSION_HEADER", "STATIC", "create_app"]

#: The folder of the page's files (shipped in the wheel).
STATIC = Path(__file__).resolve().parent / "static"
#: The header that carries a tab's session id.
SESSION_HEADER = "X-Lfdkit-Session"
#: Host names a server on the loopback answers to (a guard against DNS rebinding).
LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "[::1]", "::1", "testserver")

LOGGER = logging.getLogger("lfdkit.app.teach")

_SECURITY_HEADERS = [
    (
        b"content-security-policy",
        b"default-src 'self'; img-src 'self' data: blob:; style-src 'self'; "
        b"script-src 'self'; connect-src 'self'; frame-ancestors 'none'",
    ),
    (b"x-content-type-options", b"nosniff"),
    (b"referrer-policy", b"no-referrer"),
    (b"cache-control", b"no-store"),
]


class _Guard:
    """Pure ASGI middleware: refuse oversized bodies early, add the security headers."""

    def __init__(self, app: Any, max_body_bytes: int) -> None:
        self.app = app
        self.max_body_bytes = max_body_bytes

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        for name, value in scope.get("headers", ()):
            if name == b"content-length":
                try:
                    size = int(value)
                except ValueError:
                    size = -1
                if size < 0 or size > self.max_body_bytes:
                    await _too_large(self.max_body_bytes)(scope, receive, send)
                    return

        async def send_with_headers(message: dict) -> None:
            if message["type"] == "http.response.start":
                message.setdefault("headers", [])
                message["headers"] = list(message["headers"]) + _SECURITY_HEADERS
            await send(message)

        await self.app(scope, receive, send_with_headers)


def _too_large(limit: int) -> JSONResponse:
    return JSONResponse(
        {"error": f"request too large: at most {limit / 1e6:g} MB"}, status_code=413
    )


async def _body(request: Request) -> bytes:
    """The request body, counted as it arrives (a body without a length is bounded too)."""
    limit = request.app.state.max_body_bytes
    chunks, size = [], 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise RequestError(f"request too large: at most {limit / 1e6:g} MB", 413)
        chunks.append(chunk)
    return b"".join(chunks)


def _refuse_constant(name: str) -> None:
    raise ValueError(f"{name} is not a number JSON allows")


async def _json(request: Request) -> Any:
    body = await _body(request)
    try:
        return json.loads(body.decode("utf-8"), parse_constant=_refuse_constant)
    except UnicodeDecodeError:
        raise RequestError("request: not UTF-8 text") from None
    except json.JSONDecodeError as exc:
        raise RequestError(
            f"request: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})"
        ) from None
    except ValueError as exc:
        raise RequestError(f"request: {exc}") from None
    except RecursionError:
        raise RequestError("request: JSON nested too deeply") from None


def _session(request: Request) -> work.Session:
    store: SessionStore = request.app.state.sessions
    return store.get(request.headers.get(SESSION_HEADER))


def _kind(request: Request) -> str:
    kind = request.path_params["kind"]
    if kind not in ("demos", "scenes"):
        raise RequestError(f"no such file kind {kind[:40]!r}: demos or scenes", 404)
    return kind


def _download(content: str | bytes, media_type: str, filename: str) -> Response:
    return Response(
        content,
        media_type=media_type,
        headers={"content-disposition": f'attachment; filename="{filename}"'},
    )


# ------------------------------------------------------------------ routes
async def index(request: Request) -> Response:
    return FileResponse(STATIC / "index.html", media_type="text/html")


async def new_session(request: Request) -> Response:
    await _body(request)
    session = request.app.state.sessions.new()
    return JSONResponse({"session": session.id, "limits": LIMITS, "view": list(VIEW)})


async def example(request: Request) -> Response:
    _session(request)
    return JSONResponse(await run_in_threadpool(work.example_data))


async def import_file(request: Request) -> Response:
    _session(request)
    kind = _kind(request)
    body = await _body(request)
    fmt = request.query_params.get("format")
    reader = work.import_demos if kind == "demos" else work.import_scenes
    return JSONResponse(await run_in_threadpool(reader, body, fmt))


async def export_drawing(request: Request) -> Response:
    _session(request)
    kind = _kind(request)
    data = work.parse_teach_data(await _json(request))
    writer = work.export_demos_csv if kind == "demos" else work.export_scenes_csv
    text = await run_in_threadpool(writer, data)
    return _download(text, "text/csv", f"{kind}.csv")


async def learn(request: Request) -> Response:
    session = _session(request)
    payload = await _json(request)
    job = work.start_learning(request.app.state.sessions, session, payload)
    return JSONResponse(job.status(), status_code=202)


async def learn_status(request: Request) -> Response:
    session = _session(request)
    with session.lock:
        job, layers = session.job, session.layers
        if job is None:
            return JSONResponse({"state": "idle", "lines": [], "layers": layers})
        status = job.status()
    if status["state"] == "done":
        status["layers"] = layers
    return JSONResponse(status)


async def plan(request: Request) -> Response:
    session = _session(request)
    payload = await _json(request)
    return JSONResponse(await run_in_threadpool(work.plan_response, session, payload))


async def plan_frames(request: Request) -> Response:
    session = _session(request)
    payload = await _json(request)
    return JSONResponse(await run_in_threadpool(work.frame_plan_response, session, payload))


async def export_frame_skill(request: Request) -> Response:
    session = _session(request)
    data = await run_in_threadpool(work.export_frame_skill, session)
    return _download(data, "application/json", "task-frame-skill.json")


async def export_skill(request: Request) -> Response:
    session = _session(request)
    data = await run_in_threadpool(work.export_skill, session)
    return _download(data, "application/json", "skill.json")


async def export_plan(request: Request) -> Response:
    session = _session(request)
    payload = await _json(request)
    text = await run_in_threadpool(work.export_plan_csv, session, payload)
    return _download(text, "text/csv", "plan.csv")


async def export_urscript(request: Request) -> Response:
    session = _session(request)
    payload = await _json(request)
    text = await run_in_threadpool(work.export_urscript, session, payload)
    return _download(text, "text/plain", "program.script")


# ------------------------------------------------------------------ errors
async def _request_error(request: Request, exc: Exception) -> Response:
    status = getattr(exc, "status", 400)
    return JSONResponse({"error": str(exc)}, status_code=status)


async def _value_error(request: Request, exc: Exception) -> Response:
    # lfdkit's own checks (a start inside an obstacle, no safe plan, a class never
    # learned, an arm out of reach): their message is one readable line.
    text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return JSONResponse({"error": text}, status_code=422)


async def _http_error(request: Request, exc: Exception) -> Response:
    assert isinstance(exc, HTTPException)
    return JSONResponse({"error": exc.detail}, status_code=exc.status_code)


async def _unexpected(request: Request, exc: Exception) -> Response:
    LOGGER.error("unexpected error on %s", request.url.path, exc_info=exc)
    return JSONResponse(
        {"error": f"unexpected {type(exc).__name__} on the server (its log has the details)"},
        status_code=500,
    )


def create_app(
    *,
    allowed_hosts: tuple[str, ...] | list[str] | None = LOOPBACK_HOSTS,
    max_body_bytes: int | None = None,
    max_sessions: int | None = None,
) -> Starlette:
    """The page's application.

    Parameters
    ----------
    allowed_hosts : sequence of str or None
        Host names the server answers to (default: the loopback's, which
        stops DNS-rebinding pages from reaching it); None for any.
    max_body_bytes : int, optional
        Largest request body (default ``LIMITS["max_body_bytes"]``, 2 MB).
    max_sessions : int, optional
        Tabs served at once (default ``LIMITS["max_sessions"]``).
    """
    routes = [
        Route("/", index),
        Route("/api/session", new_session, methods=["POST"]),
        Route("/api/example", example),
        Route("/api/import/{kind:str}", import_file, methods=["POST"]),
        Route("/api/export/skill", export_skill),
        Route("/api/export/task-frame-skill", export_frame_skill),
        Route("/api/export/plan", export_plan, methods=["POST"]),
        Route("/api/export/urscript", export_urscript, methods=["POST"]),
        Route("/api/export/{kind:str}", export_drawing, methods=["POST"]),
        Route("/api/learn", learn, methods=["POST"]),
        Route("/api/learn", learn_status, methods=["GET"]),
        Route("/api/plan", plan, methods=["POST"]),
        Route("/api/plan/frames", plan_frames, methods=["POST"]),
        Mount("/static", StaticFiles(directory=STATIC), name="static"),
    ]
    limit = int(max_body_bytes or LIMITS["max_body_bytes"])
    middleware = [Middleware(_Guard, max_body_bytes=limit)]
    if allowed_hosts is not None:
        middleware.append(Middleware(TrustedHostMiddleware, allowed_hosts=list(allowed_hosts)))
    app = Starlette(
        routes=routes,
        middleware=middleware,
        exception_handlers={
            RequestError: _request_error,
            ValueError: _value_error,
            TypeError: _value_error,
            HTTPException: _http_error,
            Exception: _unexpected,
        },
    )
    app.state.sessions = SessionStore(max_sessions)
    app.state.max_body_bytes = limit
    return app
