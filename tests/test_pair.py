import math

import numpy as np
import pytest

from sesp import Pair, SeSP
from sesp.pair import TOUCH_TOLERANCE, as_pair

from cases import STAPLE


def test_pair_of_one_particle_is_identical_and_mirror_symmetric():
    pair = Pair.of(SeSP(n=4, opening=1.0), segments=32)
    assert pair.identical and pair.mirror_symmetric and pair.other is pair.particle
    assert pair.reach == pytest.approx(2 * pair.curve1.max_radius)
    assert pair.tolerance == TOUCH_TOLERANCE * pair.reach
    assert pair.vertices1.flags.c_contiguous and pair.vertices1.shape == (33, 2)


def test_mixture_with_a_polyline_is_neither():
    pair = Pair.of(SeSP(n=2, opening=math.pi), STAPLE, segments=16)
    assert not pair.identical and not pair.mirror_symmetric
    np.testing.assert_array_equal(pair.curve2.vertices, STAPLE.vertices)
    with pytest.raises(ValueError, match="closed shape"):
        pair.closed()


def test_closed_pair_and_as_pair():
    pair = Pair.of(SeSP(n=2, opening=1.0), SeSP(n=4, opening=2.0), segments=16)
    closed = pair.closed()
    assert closed.particle.opening == 0 and closed.other.opening == 0 and closed.other.n == 4
    assert as_pair(pair) is pair
    with pytest.raises(ValueError, match="other must be None"):
        as_pair(pair, SeSP())
