"""Scene.trace and Scene.occluded through Python, checked against analytic answers."""

import numpy as np
import pytest

import beamtrace


def quad_z0():
    """The square [-1, 1]^2 at z = 0, two triangles wound counter-clockwise seen from +z."""
    vertices = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    return vertices, faces


def unit_cube():
    """The cube [0, 1]^3: 12 triangles wound so that (b - a) x (c - a) points outwards; faces
    2k and 2k+1 make side k (-x, +x, -y, +y, -z, +z)."""
    vertices = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
    quads = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]]
    faces = []
    for a, b, c, d in quads:
        faces += [[a, b, c], [a, c, d]]
    return vertices, np.array(faces)


SIDES = np.array([[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]], dtype=float)


def cube_rays(distance):
    """One ray per side, from `distance` outside a point of the side (off its diagonal), straight
    at it."""
    points = 0.5 + 0.5 * SIDES + np.array([0.125, 0.25, 0.375]) * (1 - np.abs(SIDES))
    return points + distance * SIDES, -SIDES


def test_plane_at_known_range():
    scene = beamtrace.Scene.from_arrays(*quad_z0())
    hits = scene.trace([[0.3, 0.2, 10.0]], [[0.0, 0.0, -1.0]])
    assert hits.range_m.dtype == np.float32
    assert hits.range_m[0] == 10.0
    assert hits.face[0] == 0
    np.testing.assert_array_equal(hits.normal, [[0.0, 0.0, 1.0]])
    # the barycentrics give the hit point back: a + u (b - a) + v (c - a)
    a, b, c = quad_z0()[0][[0, 1, 2]]
    point = a + hits.u[0] * (b - a) + hits.v[0] * (c - a)
    np.testing.assert_allclose(point, [0.3, 0.2, 0.0], atol=1e-6)


def test_plane_from_below_and_unnormalised_directions():
    scene = beamtrace.Scene.from_arrays(*quad_z0())
    hits = scene.trace([[-0.5, 0.5, -4.0], [0.2, 0.1, 3.0]], [[0.0, 0.0, 7.0], [0.0, 0.0, -0.25]])
    np.testing.assert_array_equal(hits.range_m, [4.0, 3.0])
    np.testing.assert_array_equal(hits.face, [1, 0])
    # the geometric normal, whichever side the ray comes from
    np.testing.assert_array_equal(hits.normal[:, 2], [1.0, 1.0])


def test_cube_from_six_sides():
    vertices, faces = unit_cube()
    scene = beamtrace.Scene.from_arrays(vertices, faces)
    origins, directions = cube_rays(5.0)
    hits = scene.trace(origins, directions)
    np.testing.assert_array_equal(hits.range_m, np.full(6, 5.0, dtype=np.float32))
    np.testing.assert_array_equal(hits.face // 2, np.arange(6))
    np.testing.assert_array_equal(hits.normal, SIDES)
    # the normal is the geometric one of the face hit
    tri = vertices[faces[hits.face]]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    np.testing.assert_allclose(hits.normal, n / np.linalg.norm(n, axis=1)[:, None])


@pytest.mark.parametrize("backend", ["brute", "kdtree", "bvh"])
def test_backends_and_threads_agree(backend):
    scene = beamtrace.Scene.from_arrays(*unit_cube())
    rng = np.random.default_rng(7)
    origins = rng.uniform(-3, 4, size=(5000, 3))
    directions = rng.normal(size=(5000, 3))
    reference = scene.trace(origins, directions, backend="bvh", threads=1)
    hits = scene.trace(origins, directions, backend=backend, threads=3)
    assert 0 < np.count_nonzero(reference.face >= 0) < 5000
    for field in ("range_m", "face", "part", "label", "u", "v", "normal"):
        np.testing.assert_array_equal(getattr(hits, field), getattr(reference, field), field)


def test_labels_and_parts():
    vertices, faces = unit_cube()
    labels = np.repeat(np.arange(10, 16), 2)  # side k: class 10 + k
    scene = beamtrace.Scene.from_arrays(vertices, faces, labels=labels)
    assert [p["label"] for p in scene.parts] == list(range(10, 16))
    assert [(p["first_face"], p["face_count"]) for p in scene.parts] == [(2 * k, 2) for k in range(6)]
    hits = scene.trace(*cube_rays(2.0))
    np.testing.assert_array_equal(hits.part, np.arange(6))
    np.testing.assert_array_equal(hits.label, np.arange(10, 16))
    # without labels: one part, class 1 (unclassified)
    plain = beamtrace.Scene.from_arrays(vertices, faces).trace(*cube_rays(2.0))
    np.testing.assert_array_equal(plain.part, np.zeros(6))
    np.testing.assert_array_equal(plain.label, np.ones(6))


def test_misses():
    scene = beamtrace.Scene.from_arrays(*unit_cube())
    hits = scene.trace([[0.5, 0.5, 3.0], [0.5, 0.5, 3.0]], [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
    assert len(hits) == 2
    assert np.isinf(hits.range_m[0]) and hits.range_m[1] == 2.0
    assert (hits.face[0], hits.part[0], hits.label[0]) == (-1, -1, -1)
    assert hits.face.dtype == hits.part.dtype == hits.label.dtype == np.int64
    assert (hits.u[0], hits.v[0]) == (0.0, 0.0)
    np.testing.assert_array_equal(hits.normal[0], [0.0, 0.0, 0.0])


def test_max_range_and_occluded():
    scene = beamtrace.Scene.from_arrays(*quad_z0())
    origins, directions = [[0.0, 0.0, 10.0], [5.0, 5.0, 10.0]], [[0.0, 0.0, -1.0]] * 2
    blocked = scene.occluded(origins, directions)
    assert blocked.dtype == np.bool_
    np.testing.assert_array_equal(blocked, [True, False])
    np.testing.assert_array_equal(scene.occluded(origins, directions, max_range_m=9.5), [False, False])
    np.testing.assert_array_equal(scene.occluded(origins, directions, max_range_m=10.5), [True, False])
    assert np.isinf(scene.trace(origins, directions, max_range_m=9.5).range_m).all()


def test_dtypes_and_layouts_give_the_same_hits():
    scene = beamtrace.Scene.from_arrays(*unit_cube())
    origins, directions = cube_rays(5.0)
    reference = scene.trace(origins, directions)
    fortran = scene.trace(np.asfortranarray(origins), np.asfortranarray(directions))
    strided = scene.trace(np.repeat(origins, 2, axis=0)[::2], np.repeat(directions, 2, axis=0)[::2])
    as_f32 = scene.trace(origins.astype(np.float32), directions.astype(np.float32))
    as_list = scene.trace(origins.tolist(), directions.tolist())
    for other in (fortran, strided, as_f32, as_list):
        np.testing.assert_array_equal(other.range_m, reference.range_m)
        np.testing.assert_array_equal(other.face, reference.face)


def test_empty_batch():
    scene = beamtrace.Scene.from_arrays(*unit_cube())
    hits = scene.trace(np.zeros((0, 3)), np.zeros((0, 3)))
    assert hits.range_m.shape == (0,) and hits.normal.shape == (0, 3)


def test_zero_copy_and_concurrent_calls():
    import threading

    scene = beamtrace.Scene.from_arrays(*unit_cube())
    rng = np.random.default_rng(3)
    origins, directions = rng.uniform(-2, 3, size=(20000, 3)), rng.normal(size=(20000, 3))
    reference = scene.trace(origins, directions, backend="kdtree", threads=1)
    # NumPy's own arrays, written in place by the tracing threads: no copy afterwards
    assert all(getattr(reference, f).flags.c_contiguous for f in ("range_m", "face", "normal"))
    results = [None] * 4

    def work(k):  # the backends are built at first use, once, whichever thread asks first
        results[k] = scene.trace(origins, directions, backend=["bvh", "brute"][k % 2], threads=2)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for hits in results:
        np.testing.assert_array_equal(hits.range_m, reference.range_m)
        np.testing.assert_array_equal(hits.face, reference.face)


def test_misses_after_hits_read_minus_one_and_zero():
    # The output buffers are not zeroed before they are filled, and the allocator hands the
    # memory of earlier results out again: every miss must still be written.
    scene = beamtrace.Scene.from_arrays(*unit_cube())
    start = np.tile([0.5, 0.5, 3.0], (3000, 1))
    down = np.tile([0.0, 0.0, -1.0], (3000, 1))
    for _ in range(3):
        hits = scene.trace(start, down, threads=2)
        assert (hits.face >= 0).all() and np.abs(hits.normal).sum() == 3000
        del hits
        misses = scene.trace(start, -down, threads=2)
        assert (misses.face == -1).all() and (misses.part == -1).all()
        assert (misses.label == -1).all() and not misses.normal.any()
