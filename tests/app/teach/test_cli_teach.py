"""``lfdkit teach``: serves on the loopback, warns for other hosts, stops cleanly on Ctrl-C."""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path

import pytest

pytest.importorskip("starlette", reason="the teach page needs: pip install 'lfdkit[teach]'")
pytest.importorskip("uvicorn", reason="the teach page needs: pip install 'lfdkit[teach]'")

SRC = str(Path(__file__).resolve().parents[3] / "src")
URL = re.compile(r"serving the teach page on (http://\S+/) ")


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = SRC + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _start(*args: str) -> tuple[subprocess.Popen, str, list[str]]:
    process = subprocess.Popen(
        [sys.executable, "-m", "lfdkit.app.cli", "teach", "--port", "0", *args],
        stderr=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        env=_env(),
    )
    lines: list[str] = []
    end = time.monotonic() + 60
    while time.monotonic() < end:
        line = process.stderr.readline()
        if not line:
            break
        lines.append(line)
        found = URL.search(line)
        if found:
            return process, found.group(1), lines
    process.kill()
    raise AssertionError(f"no address printed: {lines}")


def _get(url: str) -> str:
    end = time.monotonic() + 20
    while True:
        try:
            with urllib.request.urlopen(url, timeout=5) as answer:
                return answer.read().decode()
        except OSError:
            if time.monotonic() > end:
                raise
            time.sleep(0.1)


@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM])
def test_serves_the_page_and_stops_cleanly(stop) -> None:
    process, url, _ = _start()
    try:
        assert url.startswith("http://127.0.0.1:")
        assert "/static/teach.js" in _get(url)
        request = urllib.request.Request(url + "api/session", method="POST", data=b"")
        with urllib.request.urlopen(request, timeout=5) as answer:
            assert json.loads(answer.read())["session"]
        process.send_signal(stop)
        _, err = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 0, err
    assert "lfdkit teach: stopped" in err
    assert "Traceback" not in err


def test_another_host_gets_a_warning() -> None:
    process, url, lines = _start("--host", "0.0.0.0")
    try:
        assert any("warning: listening on 0.0.0.0" in line for line in lines)
        port = url.rsplit(":", 1)[1].strip("/")
        assert "/static/teach.js" in _get(f"http://127.0.0.1:{port}/")
        process.send_signal(signal.SIGINT)
        process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 0


def test_a_busy_port_is_one_line_and_exit_1() -> None:
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen(1)
        port = busy.getsockname()[1]
        done = subprocess.run(
            [sys.executable, "-m", "lfdkit.app.cli", "teach", "--port", str(port)],
            capture_output=True,
            text=True,
            env=_env(),
            timeout=60,
        )
    assert done.returncode == 1
    assert re.fullmatch(
        rf"lfdkit teach: error: cannot listen on 127\.0\.0\.1:{port}: .+\n", done.stderr
    ), done.stderr


def test_bad_port_is_a_usage_error(capsys) -> None:
    from lfdkit.app.cli import main

    with pytest.raises(SystemExit) as exit_:
        main(["teach", "--port", "70000"])
    assert exit_.value.code == 2
    assert "--port" in capsys.readouterr().err


def test_without_the_extra_it_says_what_to_install(monkeypatch, capsys) -> None:
    from lfdkit.app.cli import main

    monkeypatch.setitem(sys.modules, "uvicorn", None)
    assert main(["teach"]) == 1
    err = capsys.readouterr().err
    assert 'pip install "lfdkit[teach]"' in err and "uvicorn" in err


def test_help_imports_neither_starlette_nor_uvicorn() -> None:
    code = (
        "import sys, contextlib, io\n"
        "from lfdkit.app.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try:\n        main(['teach', '--help'])\n    except SystemExit:\n        pass\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('starlette', 'uvicorn', 'numba', 'scipy', 'sklearn')))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=_env(), timeout=60
    )
    assert done.stdout.strip() == "[]", done.stdout + done.stderr


def test_the_url_is_on_stdout_even_when_quiet_and_a_missing_browser_is_said() -> None:
    """``--port 0 -q --open`` with no display and no browser: the URL, and why none opened."""
    env = _env()
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "BROWSER"):
        env.pop(name, None)
    # No browser on the PATH (only this Python's folder) and none named: webbrowser finds none.
    env["PATH"] = str(Path(sys.executable).parent)
    env["BROWSER"] = str(Path(sys.executable).parent / "no-such-browser")
    process = subprocess.Popen(
        [sys.executable, "-m", "lfdkit.app.cli", "teach", "--port", "0", "-q", "--open"],
        stderr=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        env=env,
    )
    watchdog = threading.Timer(60, process.kill)  # a missing line fails, never hangs
    watchdog.start()
    try:
        url = process.stdout.readline().strip()
        assert re.fullmatch(r"http://127\.0\.0\.1:\d+/", url), url
        assert int(url.rsplit(":", 1)[1].strip("/")) > 0
        warning = process.stderr.readline()
        assert "/static/teach.js" in _get(url)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=30)
    finally:
        watchdog.cancel()
        if process.poll() is None:
            process.kill()
    assert process.returncode == 0, err
    assert re.fullmatch(
        rf"lfdkit teach: warning: cannot open a browser here: .+; open {re.escape(url)} by hand\n",
        warning,
    ), warning
    # -q: nothing else on either stream (no "serving", no "stopped").
    assert out == "" and err == "", (out, err)


@pytest.mark.parametrize(
    ("opener", "reason"),
    [
        (lambda url: False, "no browser found (no display?)"),
        (lambda url: (_ for _ in ()).throw(__import__("webbrowser").Error("boom")), "boom"),
        (lambda url: (_ for _ in ()).throw(OSError()), "OSError"),
    ],
)
def test_a_browser_that_cannot_open_is_one_warning_with_the_url(opener, reason) -> None:
    from lfdkit.app.teach.server import open_in_browser

    lines: list[str] = []
    assert open_in_browser("http://127.0.0.1:9/", lines.append, opener) is False
    assert lines == [
        f"warning: cannot open a browser here: {reason}; open http://127.0.0.1:9/ by hand"
    ]


def test_a_browser_that_opens_is_silent() -> None:
    from lfdkit.app.teach.server import open_in_browser

    lines: list[str] = []
    opened: list[str] = []
    assert open_in_browser("http://x/", lines.append, lambda url: opened.append(url) or True)
    assert opened == ["http://x/"] and lines == []
