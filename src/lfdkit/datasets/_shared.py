"""Helpers the data-set generators share (synthetic and emulation sets)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from lfdkit.core.validation import check_positive

__all__ = ["SizedDemoSet", "check_count_at_least", "generate", "smooth_offset"]

_TWO_PI = 2.0 * np.pi


def check_count_at_least(value: Any, name: str, minimum: int = 1) -> int:
    """A whole number of things (demonstrations, points) of at least ``minimum``."""
    value = check_positive(value, name, integer=True, allow_zero=minimum == 0)
    if value < minimum:
        raise ValueError(f"{name}: must be >= {minimum}, got {value}")
    return value


def smooth_offset(
    rng: np.random.Generator,
    u: np.ndarray,
    sd: float,
    freq: tuple[float, float] = (0.5, 2.5),
    n_terms: int = 3,
    *,
    whole_cycles: bool = False,
) -> np.ndarray:
    """Random smooth function of ``u in [0, 1]``: a sum of sinusoids with std about ``sd``.

    Frequencies (cycles per unit ``u``) are uniform in ``freq``, phases uniform,
    amplitude weights uniform in [0.5, 1]; amplitudes are scaled so that
    ``sqrt(sum a_k**2 / 2) = sd``. The magnitude never exceeds
    ``sqrt(2 * n_terms) * sd``. Always consumes the same number of draws.
    With ``whole_cycles`` the frequencies are whole numbers uniform in ``freq``
    (inclusive), so the function is periodic: equal at ``u = 0`` and ``1``.
    """
    if whole_cycles:
        f = rng.integers(freq[0], freq[1] + 1, n_terms).astype(np.float64)
    else:
        f = rng.uniform(freq[0], freq[1], n_terms)
    phase = rng.uniform(0.0, _TWO_PI, n_terms)
    w = rng.uniform(0.5, 1.0, n_terms)
    amp = w * sd * np.sqrt(2.0 / np.sum(w**2))
    return np.sum(amp[:, None] * np.sin(_TWO_PI * f[:, None] * u[None, :] + phase[:, None]), axis=0)


def generate(
    registry: Mapping[str, Callable[..., Any]],
    kind: str,
    name: str,
    seed: Any,
    kwargs: dict[str, Any],
) -> Any:
    """Call the generator registered under ``name``; a clear error listing the valid names."""
    try:
        generator = registry[name]
    except (KeyError, TypeError):
        valid = ", ".join(sorted(registry))
        raise ValueError(f"name: unknown {kind} {name!r}; valid names: {valid}") from None
    return generator(seed=seed, **kwargs)


class SizedDemoSet:
    """``n_demos`` and ``n_dims`` of a data set with ``demos`` and a ``nominal`` (n, q)."""

    demos: list[np.ndarray]
    nominal: np.ndarray

    @property
    def n_demos(self) -> int:
        """Number of demonstrations."""
        return len(self.demos)

    @property
    def n_dims(self) -> int:
        """Spatial dimension ``q`` of the demonstrations."""
        return int(self.nominal.shape[1])
