"""Work units for batch tests on worker processes: a module that imports next to nothing.

A worker unpickles a unit by importing its module; a unit defined in a test
module would make each worker import that test module and all it imports
(seconds on 2 cores), so the units that run on workers live here.
"""

from __future__ import annotations

import time


def square_late_first(i: int) -> dict:
    """``{"square": i * i}``; task 0 naps 0.3 s first (later tasks overtake it), task 4 fails."""
    if i == 0:
        time.sleep(0.3)
    if i == 4:
        raise ValueError("four")
    return {"square": i * i}
