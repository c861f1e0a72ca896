"""Scene.all_hits: every hit of every ray, ray by ray, by increasing range."""

import numpy as np
import pytest

import beamtrace


def three_floors():
    """Squares 4 m wide at z = 0, 1, 2 (labels 2, 3, 4), their normals up (+z)."""
    vertices, faces = [], []
    for level in range(3):
        base = len(vertices)
        vertices += [[-2, -2, level], [2, -2, level], [2, 2, level], [-2, 2, level]]
        faces += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    return beamtrace.Scene.from_arrays(np.array(vertices, float), np.array(faces),
                                       labels=[2, 2, 3, 3, 4, 4])


def test_every_floor_in_range_order():
    scene = three_floors()
    origins = [[0.5, -1.0, 10], [-1.0, 0.5, 10], [5, 5, 10], [0.5, -1.0, -1]]
    directions = [[0, 0, -1], [0, 0, -2], [0, 0, -1], [0, 0, 1]]
    hits = scene.all_hits(origins, directions)
    np.testing.assert_array_equal(hits.offsets, [0, 3, 6, 6, 9])
    assert len(hits) == 9
    np.testing.assert_array_equal(hits.ray, [0, 0, 0, 1, 1, 1, 3, 3, 3])
    np.testing.assert_array_equal(hits.range_m, [8, 9, 10, 8, 9, 10, 1, 2, 3])
    np.testing.assert_array_equal(hits.label, [4, 3, 2, 4, 3, 2, 2, 3, 4])
    np.testing.assert_array_equal(hits.part, [2, 1, 0, 2, 1, 0, 0, 1, 2])
    # (0.5, -1) lies in each square's first triangle (y < x), (-1, 0.5) in its second
    np.testing.assert_array_equal(hits.face, [4, 2, 0, 5, 3, 1, 0, 2, 4])
    # down the normals' opposite: the front side; up from below: the back
    np.testing.assert_array_equal(hits.front, [True] * 6 + [False] * 3)
    assert hits.front.dtype == np.bool_


def test_facing_and_max_range_select_hits():
    scene = three_floors()
    down = scene.all_hits([[0.5, -1.0, 10]], [[0, 0, -1]], max_range_m=8.5)
    np.testing.assert_array_equal(down.range_m, [8])
    up = scene.all_hits([[0.5, -1.0, -1]], [[0, 0, 1]], facing="front")
    assert len(up) == 0 and list(up.offsets) == [0, 0]
    back = scene.all_hits([[0.5, -1.0, -1]], [[0, 0, 1]], facing="back")
    np.testing.assert_array_equal(back.range_m, [1, 2, 3])
    with pytest.raises(beamtrace.ConfigError, match="facing"):
        scene.all_hits([[0, 0, 1]], [[0, 0, 1]], facing="sideways")
    with pytest.raises(ValueError, match="directions"):
        scene.all_hits([[0, 0, 1]], [[0, 0]])


@pytest.mark.parametrize("backend", ["bvh", "kdtree", "brute"])
def test_first_hit_is_trace_and_sorted(examples, backend):
    scene = beamtrace.Scene.load(examples / "scenes" / "sphere_targets.yaml")
    rng = np.random.default_rng(2)
    n = 5000
    origins = np.column_stack([rng.uniform(-12, 12, n), rng.uniform(-2, 2, n), np.full(n, 1.5)])
    targets = np.column_stack([rng.uniform(-9, 9, n), np.full(n, 8.0), rng.uniform(1.3, 1.7, n)])
    directions = targets - origins
    hits = scene.all_hits(origins, directions, backend=backend)
    nearest = scene.trace(origins, directions, backend=backend)
    counts = np.diff(hits.offsets)
    hit = np.isfinite(nearest.range_m)
    np.testing.assert_array_equal(counts > 0, hit)
    assert np.sum(counts >= 2) > 10  # rays through a sphere: its entry and exit
    first = hits.offsets[:-1][hit]
    np.testing.assert_array_equal(hits.range_m[first], nearest.range_m[hit])
    np.testing.assert_array_equal(hits.face[first], nearest.face[hit])
    same_ray = hits.ray[1:] == hits.ray[:-1]
    assert np.all(hits.range_m[1:][same_ray] >= hits.range_m[:-1][same_ray])
    np.testing.assert_array_equal(hits.ray, np.repeat(np.arange(n), counts))
