"""Demo records: one demonstration with its times, orientations, id and scene."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.model.demos import Demo, demo_fields
from lfdkit.model.scene import Obstacle, Scene


def test_records_split_into_their_fields_in_order():
    scene = Scene((Obstacle("cup", [0.5, 0.5], 0.05),))
    records = [
        Demo(np.zeros((3, 2)), np.arange(3.0), None, "a"),
        Demo(np.ones((4, 2)), scene=scene),
    ]
    fields = demo_fields(records)
    assert [p.shape for p in fields.points] == [(3, 2), (4, 2)]
    np.testing.assert_array_equal(fields.times[0], [0.0, 1.0, 2.0])
    assert fields.times[1] is None and fields.orientations == [None, None]
    assert fields.ids == ["a", None] and fields.scenes == [None, scene]


@pytest.mark.parametrize("demos", [[np.zeros((3, 2))], np.zeros((2, 3, 2)), [], None, "demos"])
def test_anything_but_records_is_left_to_the_array_form(demos):
    assert demo_fields(demos) is None


def test_records_mixed_with_arrays_or_given_twice_are_refused_naming_them():
    record = Demo(np.zeros((3, 2)))
    with pytest.raises(TypeError, match=r"^obstacle_demos\[1\]: expected a Demo record"):
        demo_fields([record, np.zeros((3, 2))], "obstacle_demos")
    with pytest.raises(ValueError, match=r"^ids: the Demo records carry their own ids"):
        demo_fields([record], given={"times": None, "ids": [0]})
    assert demo_fields([record], given={"times": None}) is not None
