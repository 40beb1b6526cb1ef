"""``lfdkit teach``: serves on the loopback, warns for other hosts, stops cleanly on Ctrl-C."""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
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
