"""Progress of long work: a bar per stage on a terminal, timed log records, or nothing.

Every lfdkit function that can run for more than about a second (learning,
planning, the simulation, the demo) takes ``progress=``, read by
:func:`as_progress`:

``None`` or ``False`` (the default)
    Silent: library code prints and logs nothing unless asked.
``True``
    A :class:`Progress` that draws a bar per stage (tqdm) on standard error
    when it is a terminal, and logs each stage's start and wall time as
    ``INFO`` records of the logger ``lfdkit.core.progress`` (shown where logging
    is configured, e.g. ``logging.basicConfig(level=logging.INFO)``).
a callable ``f(message)``
    Called with one line of text for each stage as it starts, and at most
    every 2 s with a line on how far a long stage has come (e.g. ``print``,
    or ``list.append`` to keep them).
a :class:`Progress`
    Used as it is (the ``lfdkit`` command makes one from ``--quiet`` and
    ``--verbose``).

Stages
------
Work is reported as nested stages: ``with progress.stage("label", total=n)
as stage: ... stage.advance()``. A stage knows its start time, how many of
its ``total`` items are done and its depth below the stages around it. With
bars, each open stage has its own bar (nested bars stack up, innermost last)
and a background thread redraws the open bars twice a second, so their clocks
keep running through a long item and the terminal is never still while lfdkit
works. A stage's log records carry its ``depth`` and the seconds since the
:class:`Progress` was made (``elapsed``) as record attributes.

Thread safety: one :class:`Progress` is driven by one thread (the one doing
the work); only the redrawing thread runs beside it, under a lock.
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
from collections.abc import Callable
from typing import IO, Any, TypeAlias

__all__ = [
    "COMPILE_NOTE",
    "KERNEL_MODULES",
    "LOGGER",
    "Progress",
    "ProgressLike",
    "Stage",
    "as_progress",
    "kernels_compiled",
]

#: The logger of stage records (``INFO``): starts, wall times and long stages' progress.
LOGGER = logging.getLogger("lfdkit.core.progress")

#: What a ``progress=`` argument accepts (see the module notes).
ProgressLike: TypeAlias = "Progress | Callable[[str], Any] | bool | None"

#: Seconds between two lines of progress within a stage (log records and callbacks).
HEARTBEAT = 2.0
#: Seconds between two redraws of the open bars by the background thread.
REDRAW = 0.5
#: Least seconds between two draws of a bar as its count goes up (tqdm's ``mininterval``).
MIN_INTERVAL = 0.2

#: lfdkit's numba kernel modules (``cache=True``), relative to the package folder.
KERNEL_MODULES = (
    "core/_geometry_kernels.py",
    "mimic/_gmr_kernels.py",
    "mimic/_mean_path_kernels.py",
    "imitate/_dmp_kernels.py",
    "imitate/_rhythmic_kernels.py",
    "emulate/_problem_kernels.py",
    "emulate/_planner_kernels.py",
    "emulate/_ioc_kernels.py",
)
#: Said once when the kernels have never been compiled here (issue 31: a first run showed
#: "iteration 0" for 16 s with no word why). 74 s in all against 13-15 s warm for
#: ``lfdkit demo`` on a 2-core machine: about a minute of compiling.
COMPILE_NOTE = "compiling kernels once (about 60 s; cached afterwards)"


def kernels_compiled(package: str | os.PathLike[str] | None = None) -> bool:
    """Whether numba's cache holds lfdkit's kernels: False on a first run, which compiles them.

    Looks for numba's index files (``MODULE.FUNCTION-LINE.pyXY.nbi``) of
    :data:`KERNEL_MODULES` in their ``__pycache__`` folders, or under
    ``NUMBA_CACHE_DIR`` when set; nothing is imported. Any one found counts:
    numba caches a kernel only once something calls it (GMR's only with
    ``--mimic gmr``), so "none at all" is what tells a fresh install. A
    cache made stale by an edited source also counts (numba recompiles
    those quietly, kernel by kernel).

    Parameters
    ----------
    package : path, optional
        The ``lfdkit`` package folder (default this one).
    """
    from pathlib import Path

    root = Path(package) if package is not None else Path(__file__).resolve().parents[1]
    cache_dir = os.environ.get("NUMBA_CACHE_DIR")
    for module in KERNEL_MODULES:
        source = root / module
        pattern = f"{source.stem}.*.nbi"
        if cache_dir:
            found = any(Path(cache_dir).rglob(pattern))
        else:
            found = any((source.parent / "__pycache__").glob(pattern))
        if found:
            return True
    return False


# tqdm formats: a bar where the total is known, a count and a clock where it is not,
# and a clock alone for a stage without items.
_BAR = "{desc}: {percentage:3.0f}%|{bar}| {n_fmt}/{total_fmt} [{elapsed}<{remaining}{postfix}]"
_COUNT = "{desc}: {unit} {n_fmt} [{elapsed}{postfix}]"
_CLOCK = "{desc} [{elapsed}{postfix}]"


class Stage:
    """One stage of work in progress: made by :meth:`Progress.stage`, used in a ``with``.

    Attributes
    ----------
    label : str
        What the stage does, one line.
    total : int or None
        Number of items, if known.
    done : int
        Items done so far.
    depth : int
        Number of stages around this one.
    started : float
        ``time.perf_counter()`` when the stage was entered.
    ended : float or None
        ``time.perf_counter()`` when it was left (None while it runs).
    """

    def __init__(
        self,
        owner: Progress,
        label: str,
        total: int | None,
        unit: str | None,
        announce: bool,
    ) -> None:
        self.label = label
        self.total = total
        self.unit = unit
        self.done = 0
        self.depth = 0
        self.started = float("nan")
        self.ended: float | None = None
        self._owner = owner
        self._announce = announce
        self._detail = ""
        self._bar: Any = None

    @property
    def seconds(self) -> float:
        """Wall time of the stage so far (from entering it to leaving it, once left), s."""
        end = time.perf_counter() if self.ended is None else self.ended
        return end - self.started

    def __enter__(self) -> Stage:
        self._owner._enter(self)
        return self

    def __exit__(self, kind: Any, value: Any, traceback: Any) -> None:
        self.ended = time.perf_counter()
        self._owner._exit(self, failed=kind is not None)

    def advance(self, n: int = 1, detail: str = "") -> None:
        """Count ``n`` more items done; ``detail`` (e.g. ``"loss 0.012"``) is shown beside them."""
        self.done += n
        if detail:
            self._detail = detail
        self._owner._advance(self, n)

    def describe(self, label: str) -> None:
        """Say what the stage did, once it is known (announced now if it was not at the start)."""
        self.label = label
        if not self._announce:
            self._announce = True
            self._owner._tell(label)
        self._owner._relabel(self)

    def progress_line(self) -> str:
        """One line on how far the stage has come: label, items, detail and seconds."""
        if self.total is not None:
            count = f"{self.done}/{self.total}"
        elif self.unit is not None:
            count = f"{self.unit} {self.done}"
        else:
            count = ""
        parts = [p for p in (count, self._detail) if p]
        parts.append(f"{self.seconds:.1f} s")
        return f"{self.label}: {', '.join(parts)}"


class _SilentStage(Stage):
    """The stage of a silent :class:`Progress`: counts, tells nobody."""

    def __enter__(self) -> Stage:
        self.started = time.perf_counter()
        return self

    def __exit__(self, kind: Any, value: Any, traceback: Any) -> None:
        self.ended = time.perf_counter()

    def advance(self, n: int = 1, detail: str = "") -> None:
        self.done += n

    def describe(self, label: str) -> None:
        self.label = label


class Progress:
    """Reports stages of work: bars on a terminal, log records, a callback; or nothing.

    Parameters
    ----------
    bars : bool or None
        Draw a tqdm bar per open stage on ``file``; None (default): when
        ``file`` is a terminal.
    log : bool
        Log each stage's start and wall time, and long stages' progress, to
        :data:`LOGGER` (``INFO``).
    callback : callable, optional
        Called with each stage's label as it starts and with lines of
        progress (at most every :data:`HEARTBEAT` seconds).
    file : file object, optional
        Where bars go (default: ``sys.stderr`` when the first bar is drawn).
    heartbeat : float, optional
        Seconds between lines of progress within a stage (default :data:`HEARTBEAT`).

    Notes
    -----
    A :class:`Progress` does not survive pickling or copying: it comes back
    silent (it holds a terminal, a lock and a thread, which belong to the
    process that made it).
    """

    def __init__(
        self,
        *,
        bars: bool | None = None,
        log: bool = True,
        callback: Callable[[str], Any] | None = None,
        file: IO[str] | None = None,
        heartbeat: float | None = None,
    ) -> None:
        if callback is not None and not callable(callback):
            raise TypeError(f"callback: expected a callable, got {type(callback).__name__}")
        heartbeat = HEARTBEAT if heartbeat is None else heartbeat
        if isinstance(heartbeat, bool) or not (
            isinstance(heartbeat, (int, float)) and heartbeat >= 0
        ):
            raise ValueError(f"heartbeat: expected a number of seconds >= 0, got {heartbeat!r}")
        self._file = file
        if bars is None:
            stream = sys.stderr if file is None else file
            isatty = getattr(stream, "isatty", None)
            bars = bool(isatty()) if callable(isatty) else False
        self.bars = bool(bars)
        self.log = bool(log)
        self.callback = callback
        self.heartbeat = float(heartbeat)
        self.started = time.perf_counter()
        self._stack: list[Stage] = []
        self._lock = threading.RLock()
        self._last_line = self.started
        self._redraw_stop: threading.Event | None = None

    @property
    def silent(self) -> bool:
        """Whether this progress shows, logs and tells nothing."""
        return not (self.bars or self.log or self.callback is not None)

    def __reduce__(self) -> tuple[Callable[..., Progress], tuple[Any, ...]]:
        return (as_progress, (None,))

    def __repr__(self) -> str:
        parts = [f"bars={self.bars}", f"log={self.log}"]
        if self.callback is not None:
            parts.append(f"callback={self.callback!r}")
        return f"Progress({', '.join(parts)})"

    # ------------------------------------------------------------ public
    def stage(
        self,
        label: str,
        *,
        total: int | None = None,
        unit: str | None = None,
        announce: bool = True,
    ) -> Stage:
        """A stage of work, to enter with ``with``.

        Parameters
        ----------
        label : str
            What it does, one line (e.g. ``"MPC over 100 points"``).
        total : int, optional
            Number of items (a bar with a percentage); otherwise a count of
            ``unit`` items, or, without a unit either, a running clock.
        unit : str, optional
            What an item is, for a stage without a total: shown as
            ``"<unit> <count>"`` (e.g. ``"iteration 12"``).
        announce : bool
            Tell the callback the label at the start (default); False when
            the stage will :meth:`Stage.describe` itself at its end.

        Returns
        -------
        Stage
        """
        if total is not None:
            total = int(total)
            if total < 0:
                raise ValueError(f"total: expected a count >= 0, got {total}")
        if self.silent:
            return _SilentStage(self, label, total, unit, announce)
        return Stage(self, label, total, unit, announce)

    def note(self, message: str) -> None:
        """One line outside any stage's count: logged, and told to the callback."""
        self._tell(message)
        self._record(message, len(self._stack))

    def write(self, text: str) -> None:
        """Print ``text`` on the bars' file without tearing the bars (``tqdm.write``)."""
        stream = self._stream()
        if self.bars:
            from tqdm import tqdm

            with self._lock:
                tqdm.write(text, file=stream)
        else:
            print(text, file=stream, flush=True)

    def close(self) -> None:
        """Close every open stage's bar and stop redrawing (idempotent)."""
        with self._lock:
            while self._stack:
                stage = self._stack.pop()
                if stage._bar is not None:
                    stage._bar.close()
                    stage._bar = None
            self._stop_redraw()

    # ------------------------------------------------------------ stages
    def _stream(self) -> IO[str]:
        return sys.stderr if self._file is None else self._file

    def _enter(self, stage: Stage) -> None:
        with self._lock:
            stage.depth = len(self._stack)
            stage.started = time.perf_counter()
            self._stack.append(stage)
            if stage._announce:
                self._tell(stage.label)
            self._record(f"{stage.label} ...", stage.depth)
            if self.bars:
                stage._bar = self._new_bar(stage)
                self._start_redraw()

    def _exit(self, stage: Stage, *, failed: bool) -> None:
        with self._lock:
            if stage in self._stack:
                # Stages left open inside this one (an exception) close with it.
                while self._stack:
                    inner = self._stack.pop()
                    if inner._bar is not None:
                        inner._bar.close()
                        inner._bar = None
                    if inner is stage:
                        break
            if not self._stack:
                self._stop_redraw()
            what = "stopped after" if failed else "done in"
            self._record(f"{stage.label}: {what} {_seconds(stage.seconds)}", stage.depth)

    def _advance(self, stage: Stage, n: int) -> None:
        with self._lock:
            bar = stage._bar
            if bar is not None:
                if stage._detail:
                    bar.set_postfix_str(stage._detail, refresh=False)
                bar.update(n)
            if self.log or self.callback is not None:
                now = time.perf_counter()
                if now - self._last_line >= self.heartbeat:
                    line = stage.progress_line()
                    self._tell(line)
                    self._record(line, stage.depth)
                    self._last_line = now

    def _relabel(self, stage: Stage) -> None:
        with self._lock:
            if stage._bar is not None:
                stage._bar.set_description_str(_shorten(stage.label), refresh=False)

    def _tell(self, message: str) -> None:
        if self.callback is not None:
            self.callback(message)
            self._last_line = time.perf_counter()

    def _record(self, message: str, depth: int) -> None:
        if self.log and LOGGER.isEnabledFor(logging.INFO):
            now = time.perf_counter()
            LOGGER.info(message, extra={"depth": depth, "elapsed": now - self.started})
            self._last_line = now

    # ------------------------------------------------------------ bars
    def _new_bar(self, stage: Stage) -> Any:
        from tqdm import tqdm

        if stage.total is not None:
            bar_format = _BAR
        elif stage.unit is not None:
            bar_format = _COUNT
        else:
            bar_format = _CLOCK
        stream = self._stream()
        # A terminal that says it is 0 by 0 (some containers' pseudo-terminals) would
        # get no bars at all: draw them for 80 by 24 there.
        sized = all(_terminal_size(stream))
        return tqdm(
            total=stage.total,
            desc=_shorten(stage.label),
            unit=stage.unit or "it",
            file=stream,
            position=stage.depth,
            leave=False,
            dynamic_ncols=sized,
            ncols=None if sized else 80,
            nrows=None if sized else 24,
            mininterval=MIN_INTERVAL,
            miniters=1,
            bar_format=bar_format,
        )

    def _start_redraw(self) -> None:
        if self._redraw_stop is not None:
            return
        stop = threading.Event()
        self._redraw_stop = stop
        thread = threading.Thread(
            target=self._redraw, args=(stop,), name="lfdkit-progress", daemon=True
        )
        thread.start()

    def _stop_redraw(self) -> None:
        if self._redraw_stop is not None:
            self._redraw_stop.set()
            self._redraw_stop = None

    def _redraw(self, stop: threading.Event) -> None:
        """Redraw the open bars every :data:`REDRAW` s until ``stop`` is set."""
        while not stop.wait(REDRAW):
            with self._lock:
                if stop.is_set():
                    return
                for stage in self._stack:
                    if stage._bar is not None:
                        stage._bar.refresh()


def as_progress(progress: ProgressLike, name: str = "progress") -> Progress:
    """The :class:`Progress` a ``progress=`` argument asks for (see the module notes).

    Parameters
    ----------
    progress : Progress, callable, bool or None
    name : str
        The argument's name, for the error message.

    Raises
    ------
    TypeError
        For anything else, naming ``name``.
    """
    if isinstance(progress, Progress):
        return progress
    if progress is None or progress is False:
        return _SILENT
    if progress is True:
        return Progress()
    if callable(progress):
        return Progress(bars=False, log=False, callback=progress)
    raise TypeError(
        f"{name}: expected True, False, None, a callable taking a message or an "
        f"lfdkit.core.progress.Progress, got {type(progress).__name__}"
    )


def _terminal_size(stream: Any) -> tuple[int, int]:
    """Columns and lines of the terminal ``stream`` writes to (0 where it does not say)."""
    try:
        size = os.get_terminal_size(stream.fileno())
    except (AttributeError, OSError, ValueError):
        return 0, 0
    return size.columns, size.lines


def _seconds(value: float) -> str:
    return f"{value:.2f} s" if value < 10 else f"{value:.1f} s"


def _shorten(label: str, limit: int = 60) -> str:
    """A label short enough to leave room for the bar."""
    return label if len(label) <= limit else label[: limit - 1] + "…"


_SILENT = Progress(bars=False, log=False)
