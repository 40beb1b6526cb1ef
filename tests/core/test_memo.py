"""Tests for lfdkit.core.memo: digests of arrays, and values kept to a bound."""

from __future__ import annotations

import numpy as np

from lfdkit.core.memo import DigestMemo, array_digest


def test_a_digest_tells_apart_values_shapes_and_labels_not_memory_order() -> None:
    a = np.arange(6.0).reshape(2, 3)
    assert array_digest(a) == array_digest(a.copy()) == array_digest(np.asfortranarray(a))
    assert array_digest(a) != array_digest(a.reshape(3, 2))  # the same bytes, another shape
    assert array_digest(a) != array_digest(a + 1e-12)
    assert array_digest(a, label="40") != array_digest(a, label="41")
    assert array_digest(a, a[:1]) != array_digest(a[:1], a)
    assert len(array_digest(a)) == 20


def test_the_least_recently_used_go_first_past_the_byte_bound() -> None:
    one = np.zeros(100)  # 800 bytes
    memo = DigestMemo(max_bytes=2 * one.nbytes)
    for k in (b"a", b"b"):
        memo.put(k, one.copy())
    assert memo.get(b"a") is not None  # a is now the most recently used
    memo.put(b"c", one.copy())
    assert memo.get(b"b") is None and memo.get(b"a") is not None and memo.get(b"c") is not None
    assert len(memo) == 2 and memo.nbytes == 2 * one.nbytes
    # A value larger than the bound on its own is handed back, not kept.
    big = np.zeros(1000)
    assert memo.put(b"d", big) is big and memo.get(b"d") is None and len(memo) == 2


def test_a_count_bound_and_the_first_value_put_under_a_key_stays() -> None:
    memo: DigestMemo[str] = DigestMemo(max_items=2)
    assert memo.put(b"k", "first") == "first"
    assert memo.put(b"k", "second") == "first"  # another thread made it meanwhile: one kept
    memo.put(b"l", "l")
    memo.put(b"m", "m")
    assert len(memo) == 2 and memo.get(b"k") is None and memo.nbytes == 0
