"""Serve the teach page with uvicorn until Ctrl-C (the ``lfdkit teach`` command)."""

from __future__ import annotations

import contextlib
import ipaddress
import socket
import threading
import webbrowser
from collections.abc import Callable
from typing import Any

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "is_loopback", "make_server", "open_in_browser", "serve"]

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8765


def is_loopback(host: str) -> bool:
    """Whether ``host`` names this machine only (``127.0.0.1``, ``::1``, ``localhost``)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def bind(host: str, port: int) -> socket.socket:
    """A listening socket on ``host:port`` (port 0: a free one), or ``OSError`` saying why."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    # IPPROTO_TCP by name: asyncio sets TCP_NODELAY only on sockets that say so, and
    # without it each small response waits ~40 ms for the client's delayed ACK.
    sock = socket.socket(family, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host.strip("[]"), port))
    except OSError as exc:
        sock.close()
        raise OSError(f"cannot listen on {host}:{port}: {exc.strerror or exc}") from None
    sock.listen(128)
    sock.set_inheritable(True)
    return sock


def make_server(host: str = DEFAULT_HOST, port: int = DEFAULT_PORT) -> tuple[Any, socket.socket]:
    """A uvicorn server of the page and its bound socket (not started yet).

    The application answers only to the loopback's host names when ``host``
    is a loopback address (:data:`lfdkit.app.teach.app.LOOPBACK_HOSTS`).
    """
    import uvicorn

    from lfdkit.app.teach.app import LOOPBACK_HOSTS, create_app

    app = create_app(allowed_hosts=LOOPBACK_HOSTS if is_loopback(host) else None)
    config = uvicorn.Config(
        app,
        log_level="warning",
        lifespan="off",
        timeout_graceful_shutdown=2,
        server_header=False,
    )
    return uvicorn.Server(config), bind(host, port)


def url_of(sock: socket.socket) -> str:
    host, port = sock.getsockname()[:2]
    shown = f"[{host}]" if ":" in host else host
    return f"http://{shown}:{port}/"


def open_in_browser(
    url: str,
    warn: Callable[[str], Any],
    opener: Callable[[str], bool] = webbrowser.open,
) -> bool:
    """Open ``url`` in the default browser, or warn in one line with the URL to open by hand.

    :func:`webbrowser.open` says "no browser" by returning ``False`` (no
    display, no browser installed) or, for some, by raising; either way the
    user is told rather than left waiting for a window that never comes.
    """
    try:
        opened = bool(opener(url))
        reason = "no browser found (no display?)"
    except Exception as exc:  # webbrowser.Error, OSError from a broken launcher, ...
        opened = False
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    if not opened:
        warn(f"warning: cannot open a browser here: {reason}; open {url} by hand")
    return opened


def serve(
    host: str = DEFAULT_HOST,
    port: int = DEFAULT_PORT,
    *,
    open_browser: bool = False,
    say: Callable[[str], Any] = print,
    show_url: Callable[[str], Any] | None = None,
    warn: Callable[[str], Any] | None = None,
) -> None:
    """Serve the page until Ctrl-C (or SIGTERM), then return.

    Parameters
    ----------
    host : str
        Address to listen on; the loopback by default. Any other exposes the
        page (and its learning) to the network: the caller warns.
    port : int
        Port (0: a free one, printed).
    open_browser : bool
        Open the page in the default browser once the server listens.
    say : callable
        Where the lines for the user go (the address, the stop).
    show_url : callable, optional
        Given the bare URL once the port is bound, always (the command's
        output: with ``--port 0`` it is the only way to learn the port).
    warn : callable, optional
        Where the warning goes when no browser can be opened (``say`` when
        not given).

    Raises
    ------
    OSError
        When the address cannot be listened on (in use, not this machine's).
    """
    server, sock = make_server(host, port)
    url = url_of(sock)
    if show_url is not None:
        show_url(url)
    say(f"serving the teach page on {url} (Ctrl-C stops)")
    if open_browser:

        def open_when_started() -> None:
            for _ in range(200):
                if server.started:
                    open_in_browser(url, warn or say)
                    return
                threading.Event().wait(0.05)

        threading.Thread(target=open_when_started, daemon=True).start()
    try:
        # uvicorn shuts down gracefully on SIGINT/SIGTERM, then raises the signal
        # again: the KeyboardInterrupt that follows is the normal way out.
        with contextlib.suppress(KeyboardInterrupt):
            server.run(sockets=[sock])
    finally:
        sock.close()
    say("stopped")
