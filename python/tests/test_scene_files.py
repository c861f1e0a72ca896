"""Scene.load: the scene files `survey` and `render` use, and mesh files."""

import numpy as np

import beamtrace


def test_sphere_targets_scene(examples):
    # the scene of examples/surveys/tripod_spheres.yaml, scanned from 1.6 m above the site
    scene = beamtrace.Scene.load(examples / "scenes" / "sphere_targets.yaml")
    names = [p["name"] for p in scene.parts]
    assert names == ["site", "targets", "far-target"]
    eye = np.array([0.0, 0.0, 1.6])
    centre = np.array([0.0, 8.0, 1.5])  # the middle target of the row (-8 + 2 * 4)
    hits = scene.trace([eye, eye], [centre - eye, [0.0, 0.0, -1.0]])
    expected = np.linalg.norm(centre - eye) - 0.1
    np.testing.assert_allclose(hits.range_m[0], expected, rtol=1e-6)
    assert (hits.part[0], hits.label[0]) == (1, 64)
    np.testing.assert_allclose(hits.normal[0], -(centre - eye) / np.linalg.norm(centre - eye), atol=1e-5)
    np.testing.assert_allclose(hits.range_m[1], 1.6, rtol=1e-6)
    assert (hits.part[1], hits.label[1]) == (0, 2)
    np.testing.assert_allclose(hits.normal[1], [0.0, 0.0, 1.0])


def test_mesh_file_matches_arrays(tmp_path):
    vertices = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    path = tmp_path / "quad.obj"
    path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in vertices) + "f 1 2 3 4\n")
    scene = beamtrace.Scene.load(str(path))
    assert scene.face_count == 2 and scene.parts[0]["name"] == str(path)
    origins = [[0.5, -0.5, 2.0], [-0.5, 0.5, 2.0]]
    hits = scene.trace(origins, [[0, 0, -1]] * 2)
    reference = beamtrace.Scene.from_arrays(vertices, [[0, 1, 2], [0, 2, 3]]).trace(origins, [[0, 0, -1]] * 2)
    np.testing.assert_array_equal(hits.range_m, [2.0, 2.0])
    np.testing.assert_array_equal(hits.face, reference.face)
    np.testing.assert_array_equal(hits.u, reference.u)
    lo, hi = scene.bounds
    assert lo == (-1.0, -1.0, 0.0) and hi == (1.0, 1.0, 0.0)


def test_shared_mesh_files(shared_data):
    meshes = shared_data / "meshes"
    for name in ("gltf/BoxTextured.glb", "ply/cube.ply"):
        scene = beamtrace.Scene.load(meshes / name)
        assert scene.face_count == 12, name
        (x0, y0, _), (x1, y1, z1) = scene.bounds
        hits = scene.trace([[(x0 + x1) / 2 + 0.1, (y0 + y1) / 2 + 0.2, z1 + 10]], [[0, 0, -1]])
        assert hits.range_m[0] == 10.0, name
        np.testing.assert_array_equal(hits.normal[0], [0.0, 0.0, 1.0])
    # the PLY and STL twins of one mesh: the same hits on a grid of rays from above
    ply, stl = (beamtrace.Scene.load(meshes / f"{k}/Wuson.{k}") for k in ("ply", "stl"))
    (x0, y0, _), (x1, y1, z1) = ply.bounds
    xy = np.stack(np.meshgrid(np.linspace(x0, x1, 40), np.linspace(y0, y1, 40)), -1).reshape(-1, 2)
    origins = np.column_stack([xy, np.full(len(xy), z1 + 1)])
    down = np.tile([0.0, 0.0, -1.0], (len(xy), 1))
    a, b = ply.trace(origins, down), stl.trace(origins, down)
    assert 100 < np.count_nonzero(a.face >= 0) < len(xy)
    np.testing.assert_array_equal(a.range_m, b.range_m)
    np.testing.assert_array_equal(a.face, b.face)
