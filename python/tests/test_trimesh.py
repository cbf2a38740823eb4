"""simdbvh.trimesh: trimesh's RayMeshIntersector contract on meshes whose answers are known by hand (a unit
cube, far from the origin too), and against the module's brute force on a sphere."""
import pickle
import types

import numpy as np
import pytest

import simdbvh.trimesh as st

CUBE_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                   [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=np.float64)
CUBE_F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                   [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
# The faces of the cube's sides: x = 0 (10, 11), x = 1 (6, 7), z = 0 (0, 1), z = 1 (2, 3).
X0, X1 = {10, 11}, {6, 7}


def cube(offset=0.0, scale=1.0):
    return types.SimpleNamespace(vertices=CUBE_V * scale + offset, faces=CUBE_F)


# Rays along +x through the cube at (y, z) off every edge and diagonal, one missing it, one along -x.
ORIGINS = np.array([[-1, 0.3, 0.6], [-1, 0.7, 0.2], [-1, 2.0, 0.5], [3, 0.6, 0.3]], dtype=np.float64)
DIRS = np.array([[2, 0, 0], [1, 0, 0], [1, 0, 0], [-5, 0, 0]], dtype=np.float64)


def test_first_any_and_ids_on_the_cube():
    r = st.RayMeshIntersector(cube())
    first = r.intersects_first(ORIGINS, DIRS)
    assert first.dtype == np.int64 and first[2] == -1
    assert first[0] in X0 and first[1] in X0 and first[3] in X1
    assert r.intersects_any(ORIGINS, DIRS).tolist() == [True, True, False, True]
    tri, ray = r.intersects_id(ORIGINS, DIRS, multiple_hits=False)
    assert ray.tolist() == [0, 1, 3] and tri.tolist() == first[[0, 1, 3]].tolist()


def test_every_hit_in_order_with_locations():
    r = st.RayMeshIntersector(cube())
    tri, ray, loc = r.intersects_id(ORIGINS, DIRS, multiple_hits=True, return_locations=True)
    # Each crossing once: two per ray that meets the cube, the near side first.
    assert ray.tolist() == [0, 0, 1, 1, 3, 3]
    assert [t in X0 for t in tri[[0, 2]]] == [True, True] and tri[4] in X1
    assert tri[1] in X1 and tri[3] in X1 and tri[5] in X0
    want = np.array([[0, 0.3, 0.6], [1, 0.3, 0.6], [0, 0.7, 0.2], [1, 0.7, 0.2], [1, 0.6, 0.3], [0, 0.6, 0.3]])
    np.testing.assert_allclose(loc, want, rtol=0, atol=1e-12)
    locations, index_ray, index_tri = r.intersects_location(ORIGINS, DIRS)
    np.testing.assert_array_equal(locations, loc)
    assert index_ray.tolist() == ray.tolist() and index_tri.tolist() == tri.tolist()
    tri1, ray1 = r.intersects_id(ORIGINS, DIRS, max_hits=1)
    assert ray1.tolist() == [0, 1, 3] and tri1.tolist() == tri[[0, 2, 4]].tolist()


def test_an_edge_between_two_triangles_is_one_crossing():
    # (y, z) = (0.5, 0.5) lies on the diagonal of the x = 0 and x = 1 faces: one hit on each face, not two.
    r = st.RayMeshIntersector(cube())
    tri, ray = r.intersects_id([[-1, 0.5, 0.5]], [[1, 0, 0]])
    assert ray.tolist() == [0, 0] and tri[0] in X0 and tri[1] in X1


@pytest.mark.parametrize("offset", [1e5, 1e6, 1e7])
def test_locations_far_from_the_origin(offset):
    # A 10-unit cube at 1e5 .. 1e7: traced relative to its corner, the locations lie on its sides in double.
    r = st.RayMeshIntersector(cube(offset, 10.0))
    o = ORIGINS * 10.0 + offset
    tri, ray, loc = r.intersects_id(o, DIRS, return_locations=True)
    assert ray.tolist() == [0, 0, 1, 1, 3, 3]
    want = np.array([[0, 3, 6], [10, 3, 6], [0, 7, 2], [10, 7, 2], [10, 6, 3], [0, 6, 3]]) + offset
    np.testing.assert_allclose(loc, want, rtol=0, atol=1e-7)
    inside = r.contains_points(np.array([[5, 5, 5], [5, 5, 11], [9.999, 0.001, 5]]) + offset)
    assert inside.tolist() == [True, False, True]


def test_contains_points_exact_on_the_cube():
    r = st.RayMeshIntersector(cube())
    pts = np.array([[0.5, 0.5, 0.5], [1.5, 0.5, 0.5], [0.5, 0.5, 1.0], [1e-6, 1e-6, 1e-6], [-1e-6, 0.5, 0.5]])
    assert r.contains_points(pts).tolist() == [True, False, False, True, False]


def test_against_brute_force_on_a_sphere():
    rng = np.random.default_rng(7)
    n = 24
    th, ph = np.meshgrid(np.linspace(0, np.pi, n + 1)[1:-1], np.linspace(0, 2 * np.pi, 2 * n, endpoint=False))
    v = np.concatenate([[[0, 0, 1], [0, 0, -1]],
                        np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1).reshape(-1, 3)])
    ring = lambda i, j: 2 + (j % (2 * n)) * (n - 1) + (i - 1)
    f = [[0, ring(1, j), ring(1, j + 1)] for j in range(2 * n)]
    f += [[1, ring(n - 1, j + 1), ring(n - 1, j)] for j in range(2 * n)]
    for i in range(1, n - 1):
        for j in range(2 * n):
            f += [[ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)], [ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]]
    mesh = types.SimpleNamespace(vertices=v + 250.0, faces=np.array(f))
    o = rng.uniform(-2, 2, (2000, 3)) + 250.0
    d = rng.normal(size=(2000, 3))
    fast, slow = st.RayMeshIntersector(mesh), st.RayMeshIntersector(mesh, method="brute", threads=1)
    for a, b in zip(fast.intersects_id(o, d, return_locations=True), slow.intersects_id(o, d, return_locations=True)):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(fast.intersects_first(o, d), slow.intersects_first(o, d))
    p = rng.uniform(-1.2, 1.2, (2000, 3)) + 250.0
    inside = fast.contains_points(p)
    assert inside.tolist() == slow.contains_points(p).tolist()
    r = np.linalg.norm(p - 250.0, axis=1)
    assert inside[r < 0.98].all() and not inside[r > 1.0].any()  # every facet lies between r = 0.989 and 1


def test_empty_batches_bad_shapes_and_pickling():
    r = st.RayMeshIntersector(cube())
    tri, ray, loc = r.intersects_id(np.zeros((0, 3)), np.zeros((0, 3)), return_locations=True)
    assert tri.shape == (0,) and ray.shape == (0,) and loc.shape == (0, 3)
    assert r.intersects_first(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)
    with pytest.raises(ValueError, match="must both be"):
        r.intersects_id(ORIGINS, DIRS[:2])
    with pytest.raises(ValueError, match="max_hits"):
        r.intersects_id(ORIGINS, DIRS, max_hits=0)
    with pytest.raises(ValueError, match="vertices"):
        st.RayMeshIntersector(types.SimpleNamespace(vertices=np.zeros((0, 3)), faces=np.zeros((0, 3), int)))
    copy = pickle.loads(pickle.dumps(r))
    np.testing.assert_array_equal(copy.intersects_first(ORIGINS, DIRS), r.intersects_first(ORIGINS, DIRS))
    assert "12 triangles" in repr(r) and "bvh8" in repr(r)
