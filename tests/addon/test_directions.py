"""The add-on's direction maths against docs/formats/lookup.md."""
import math
import random

import pytest

from clothbake.core import directions as d


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def test_hemi_oct_round_trip():
    rng = random.Random(1)
    for _ in range(2000):
        v = unit((rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 1)))
        back = d.hemi_oct_decode(*d.hemi_oct_encode(v))
        assert max(abs(a - b) for a, b in zip(v, back)) < 1e-12


def test_known_points():
    assert d.hemi_oct_encode((0, 0, 1)) == (0.5, 0.5)
    # The horizon is the square's boundary: +x at (1, 1), +y at (1, 0).
    assert d.hemi_oct_encode((1, 0, 0)) == (1.0, 1.0)
    assert d.hemi_oct_encode((0, 1, 0)) == (1.0, 0.0)
    assert d.hemi_oct_encode((0, 0, 0)) == (0.5, 0.5)


@pytest.mark.parametrize("k", [2, 3, 8, 16])
def test_nodes_are_found_at_their_own_footprint(k):
    for side in (0, 1):
        for j in range(k):
            for i in range(k):
                direction = d.node_direction(k, side, i, j)
                fp = d.locate(k, direction)
                # Horizon nodes (z = 0) belong to both sides; locate says front.
                assert fp.side == (side if direction[2] != 0.0 else 0)
                gi = fp.i0 + fp.fx
                gj = fp.j0 + fp.fy
                assert gi == pytest.approx(i, abs=1e-9)
                assert gj == pytest.approx(j, abs=1e-9)
                assert 0 <= fp.i0 <= k - 2 and fp.i1 == fp.i0 + 1


def test_back_side_mirrors_front():
    rng = random.Random(2)
    for _ in range(200):
        v = unit((rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.01, 1)))
        front = d.locate(8, v)
        back = d.locate(8, (v[0], v[1], -v[2]))
        assert (front.side, back.side) == (0, 1)
        assert (front.i0, front.j0, front.fx, front.fy) == (back.i0, back.j0, back.fx, back.fy)


def test_node_index_matches_manifest_order():
    k = 5
    seen = {d.node_index(k, s, i, j) for s in (0, 1) for j in range(k) for i in range(k)}
    assert seen == set(range(2 * k * k))
    assert d.node_index(k, 1, 0, 0) == k * k
    assert d.node_index(k, 0, 1, 0) == 1 and d.node_index(k, 0, 0, 1) == k


def test_polar_wraps_in_azimuth():
    k = 8
    fp = d.locate(k, unit((1.0, -1e-9, 0.5)), d.POLAR)
    assert fp.i0 == k - 1 and fp.i1 == 0
