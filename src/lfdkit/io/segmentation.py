"""Cutting a long recording into demonstrations at pauses, and trimming rest at its ends.

A sample is *at rest* when the tool's speed there is below ``speed``: the
distance between the positions ``window / 2`` before and after it
(interpolated), over the time between them. Over a window rather than
between neighbouring samples, so that sensor noise does not read as motion:
motion capture with 0.2 mm of noise at 100 Hz moves 2.5 cm/s between
samples, 1.4 mm/s over 0.2 s. A run of rest
samples lasting at least ``pause`` seconds inside the recording is a pause:
with ``split`` the recording is cut there, each demonstration keeping the
pause's last rest sample before its motion and first rest sample after it
(a demonstration starts and ends at rest). With ``trim`` the rest before the
first motion and after the last is cut the same way, whatever its length.

Between demonstrations a demonstrator usually brings the tool back to the
start, a stroke of its own: with ``returns="drop"`` every piece heading
against the first one (its start→end displacement at an obtuse angle to the
first piece's) is left out, and listed.

Nothing is dropped silently: :class:`Segmentation` accounts for every
sample (in a demonstration, in a pause between two, or trimmed at an end),
and :meth:`Segmentation.table` is the report ``lfdkit import -v`` prints.
Rotation in place (the tool turning without moving) counts as rest.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from lfdkit.core.validation import check_path, check_positive, check_times

__all__ = ["Pause", "Segmentation", "segment_recording"]


@dataclass(frozen=True)
class Pause:
    """Rest samples ``start`` to ``stop - 1`` (indices), from ``t_start`` to ``t_stop`` s."""

    start: int
    stop: int
    t_start: float
    t_stop: float

    @property
    def duration(self) -> float:
        """Seconds at rest."""
        return self.t_stop - self.t_start


@dataclass(frozen=True)
class Segmentation:
    """Where a recording was cut and what was trimmed.

    Attributes
    ----------
    segments : tuple of (int, int)
        ``(start, stop)`` sample indices of each demonstration (``stop``
        exclusive), in time order.
    pauses : tuple of Pause
        The pauses the recording was cut at (between demonstrations).
    trimmed : (int, int)
        Rest samples cut before the first and after the last demonstration.
    returns : tuple of (int, int)
        ``(start, stop)`` of the pieces left out as moves back to the start
        (``returns="drop"``).
    times : ndarray, shape (n,)
        The recording's sample times (seconds).
    speed, pause : float
        The rest threshold (units/s) and the shortest pause (s) used.
    """

    segments: tuple[tuple[int, int], ...]
    pauses: tuple[Pause, ...]
    trimmed: tuple[int, int]
    times: np.ndarray
    speed: float
    pause: float
    returns: tuple[tuple[int, int], ...] = ()

    @property
    def n_samples(self) -> int:
        """Samples of the recording."""
        return len(self.times)

    def accounted(self) -> int:
        """Samples in demonstrations, inside pauses and trimmed: always ``n_samples``.

        A pause's first and last samples are the ends of the demonstrations
        beside it; the others are in no demonstration.
        """
        pieces = sum(b - a for a, b in (*self.segments, *self.returns))
        between = sum(p.stop - p.start - 2 for p in self.pauses)
        return pieces + between + sum(self.trimmed)

    def table(self, name: str = "recording") -> str:
        """The report: one row per demonstration (samples, start, duration), pauses and trims."""
        t = self.times
        lines = [f"{name}: {self.n_samples} samples over {t[-1] - t[0]:.3f} s"]
        lines.append(f"  {'demo':>4}  {'samples':>7}  {'start s':>9}  {'duration s':>10}")
        for k, (a, b) in enumerate(self.segments):
            lines.append(f"  {k:>4}  {b - a:>7}  {t[a] - t[0]:>9.3f}  {t[b - 1] - t[a]:>10.3f}")
        for p in self.pauses:
            lines.append(
                f"  split at a pause of {p.duration:.3f} s from {p.t_start - t[0]:.3f} s "
                f"({p.stop - p.start} samples below {self.speed:g} units/s)"
            )
        for a, b in self.returns:
            lines.append(
                f"  left out a move back to the start: {b - a} samples from "
                f"{t[a] - t[0]:.3f} s, {t[b - 1] - t[a]:.3f} s"
            )
        head, tail = self.trimmed
        if head or tail:
            lines.append(
                f"  trimmed rest: {head} samples at the start "
                f"({_span(t, 0, head):.3f} s), {tail} at the end "
                f"({_span(t, len(t) - tail - 1, len(t) - 1):.3f} s)"
            )
        return "\n".join(lines)


def _span(t: np.ndarray, a: int, b: int) -> float:
    return float(t[b] - t[a]) if b > a else 0.0


def _speeds(times: np.ndarray, positions: np.ndarray, window: float) -> np.ndarray:
    """Speed at each sample over ``window`` seconds centred on it (shortened at the ends).

    Never over less than the neighbouring samples: a window shorter than the
    sampling interval gives central differences.
    """
    lo = np.maximum(times - 0.5 * window, times[0])
    hi = np.minimum(times + 0.5 * window, times[-1])
    idx = np.arange(len(times))
    lo = np.minimum(lo, times[np.maximum(idx - 1, 0)])
    hi = np.maximum(hi, times[np.minimum(idx + 1, len(times) - 1)])
    a = np.stack([np.interp(lo, times, positions[:, k]) for k in range(positions.shape[1])], 1)
    b = np.stack([np.interp(hi, times, positions[:, k]) for k in range(positions.shape[1])], 1)
    return np.linalg.norm(b - a, axis=1) / (hi - lo)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """``(start, stop)`` of each run of True."""
    edges = np.diff(np.r_[0, mask.astype(np.int8), 0])
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True))


def segment_recording(
    times: Any,
    positions: Any,
    *,
    speed: float = 0.01,
    pause: float = 0.5,
    window: float = 0.2,
    split: bool = True,
    trim: bool = True,
    returns: str = "keep",
) -> Segmentation:
    """Find the demonstrations in a recording (see the module notes).

    Parameters
    ----------
    times : array_like, shape (n,)
        Sample times (seconds), strictly increasing.
    positions : array_like, shape (n, q)
        Tool positions (any length unit).
    speed : float
        Rest threshold, position units per second (0.01: 1 cm/s in metres).
    pause : float
        Shortest rest inside the recording that splits it, seconds.
    window : float
        Seconds over which the speed is measured (module notes).
    split : bool
        Cut at the pauses (else one demonstration).
    trim : bool
        Cut the rest before the first motion and after the last.
    returns : {"keep", "drop"}
        ``"drop"``: leave out the pieces heading against the first one (the
        moves back to the start between demonstrations; module notes).

    Returns
    -------
    Segmentation

    Raises
    ------
    ValueError
        If the inputs are malformed, or the recording never moves faster than
        ``speed`` (nothing to cut out: the message gives its top speed).
    """
    pos = check_path(positions, "positions")
    t = check_times(times, len(pos), "times", of="positions")
    speed = check_positive(speed, "speed")
    pause = check_positive(pause, "pause")
    window = check_positive(window, "window")
    if returns not in ("keep", "drop"):
        raise ValueError(f"returns: expected 'keep' or 'drop', got {returns!r}")
    v = _speeds(t, pos, window)
    moving = v >= speed
    if not moving.any():
        raise ValueError(
            f"positions: never move faster than speed={speed:g} units/s (top speed "
            f"{float(v.max()):.3g}); nothing to import: lower the speed threshold"
        )
    first = int(np.argmax(moving))
    last = len(moving) - 1 - int(np.argmax(moving[::-1]))
    # keep one rest sample on each side of the motion: a demonstration starts and ends at rest
    lo = max(first - 1, 0) if trim else 0
    hi = min(last + 1, len(t) - 1) + 1 if trim else len(t)
    pauses: list[Pause] = []
    segments: list[tuple[int, int]] = []
    start = lo
    if split:
        for a, b in _runs(~moving[first : last + 1]):
            a, b = a + first, b + first  # rest samples a .. b-1, with motion on both sides
            if t[b - 1] - t[a] >= pause:
                pauses.append(Pause(a, b, float(t[a]), float(t[b - 1])))
                segments.append((start, a + 1))
                start = b - 1
    segments.append((start, hi))
    dropped: list[tuple[int, int]] = []
    if returns == "drop":
        heading = pos[segments[0][1] - 1] - pos[segments[0][0]]
        back = [(pos[b - 1] - pos[a]) @ heading < 0.0 for a, b in segments]
        dropped = [seg for seg, b in zip(segments, back, strict=True) if b]
        segments = [seg for seg, b in zip(segments, back, strict=True) if not b]
    return Segmentation(
        tuple(segments),
        tuple(pauses),
        (lo, len(t) - hi),
        t,
        float(speed),
        float(pause),
        tuple(dropped),
    )
