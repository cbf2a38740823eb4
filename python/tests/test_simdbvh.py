"""The Python module against the library's own rules and closed-form answers:
a unit cube (inside, distances, hits known by hand), an icosphere (every path
bit-identical), numpy dtype/layout handling, errors as simdbvh.Error."""
import os

import numpy as np
import pytest

import simdbvh
from gil_probe import assert_gil_released

CUBE_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                   [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=np.float64)
# Outward, counter-clockwise.
CUBE_F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                   [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])


@pytest.fixture(scope="module")
def cube():
    return simdbvh.Mesh(CUBE_V, CUBE_F)


def sphere_mesh(n=24):
    """A closed UV sphere of radius 1."""
    verts = [[0, 0, 1], [0, 0, -1]]
    for i in range(1, n):
        th = np.pi * i / n
        for j in range(2 * n):
            ph = np.pi * j / n
            verts.append([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
    faces = []
    ring = lambda i, j: 2 + (i - 1) * 2 * n + (j % (2 * n))
    for j in range(2 * n):
        faces.append([0, ring(1, j), ring(1, j + 1)])
        faces.append([1, ring(n - 1, j + 1), ring(n - 1, j)])
    for i in range(1, n - 1):
        for j in range(2 * n):
            faces.append([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)])
            faces.append([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)])
    return simdbvh.Mesh(np.array(verts), np.array(faces))


def test_mesh_round_trip_and_closure(cube):
    assert len(cube) == 12
    assert cube.vertices.dtype == np.float32 and cube.vertices.shape == (8, 3)
    np.testing.assert_array_equal(cube.faces, CUBE_F)
    c = cube.closure()
    assert c["closed"] and c["consistently_oriented"] and c["edges"] == 18
    open_cube = simdbvh.Mesh(CUBE_V, CUBE_F[:-2])
    assert open_cube.closure()["boundary_edges"] == 4


def test_hits_on_the_cube(cube):
    for method in ("bvh4", "bvh8", "bvh16", "bvh2", "brute"):
        bvh = simdbvh.BVH(cube, method=method)
        o = np.array([[0.25, 0.5, -1.0], [0.5, 0.5, 0.5], [2.0, 2.0, 2.0]], dtype=np.float32)
        d = np.array([[0, 0, 1], [1, 0, 0], [1, 0, 0]], dtype=np.float32)
        h = bvh.intersect(o, d)
        assert h["hit"].tolist() == [True, True, False]
        assert h["t"][0] == 1.0 and h["t"][1] == 0.5 and np.isinf(h["t"][2])
        assert h["prim"][2] == -1
        assert bvh.occluded(o, d).tolist() == [True, True, False]
        assert not bvh.occluded(o, d, tmax=0.25)[0]
        assert bvh.intersect(o, d, tmin=np.array([2.0, 0.0, 0.0]))["t"][0] == 2.0  # the top face


def test_hit_points_and_normals(cube):
    bvh = simdbvh.BVH(cube)
    o = np.array([[0.25, 0.5, -1.0], [0.5, 0.5, 0.5], [2.0, 2.0, 2.0], [0.3, 0.7, 5.0]], dtype=np.float32)
    d = np.array([[0, 0, 1], [1, 0, 0], [1, 0, 0], [0, 0, -1]], dtype=np.float32)
    h = bvh.intersect(o, d, points=True, normals=True)
    assert h["hit"].tolist() == [True, True, False, True]
    # By hand: the floor z = 0 (outward normal -z), the wall x = 1 (+x), a miss, the top z = 1 (+z).
    np.testing.assert_allclose(h["points"][[0, 1, 3]], [[0.25, 0.5, 0], [1, 0.5, 0.5], [0.3, 0.7, 1]], atol=1e-6)
    np.testing.assert_array_equal(h["normals"][[0, 1, 3]], [[0, 0, -1], [1, 0, 0], [0, 0, 1]])
    assert np.isnan(h["points"][2]).all() and np.isnan(h["normals"][2]).all()
    assert "points" not in bvh.intersect(o, d)
    # On a sphere: points lie on their triangle's plane, normals are unit and orthogonal to its edges.
    mesh = sphere_mesh(16)
    rng = np.random.default_rng(3)
    org = rng.uniform(-3, 3, (2000, 3)).astype(np.float32)
    to = rng.uniform(-0.5, 0.5, (2000, 3)).astype(np.float32)
    h = simdbvh.BVH(mesh).intersect(org, to - org, points=True, normals=True)
    hit = h["hit"]
    assert hit.sum() > 1000
    tri = mesh.vertices.astype(np.float64)[mesh.faces[h["prim"][hit]]]
    n = h["normals"][hit].astype(np.float64)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-6)
    for e in (tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]):
        assert np.abs(np.einsum("ij,ij->i", n, e)).max() < 1e-5
    off_plane = np.einsum("ij,ij->i", n, h["points"][hit] - tri[:, 0])
    assert np.abs(off_plane).max() < 1e-6
    # And they agree with origin + t * direction up to the rounding of t.
    np.testing.assert_allclose(h["points"][hit], org[hit] + h["t"][hit, None] * (to - org)[hit], atol=1e-5)


def test_every_path_and_isa_bit_identical():
    mesh = sphere_mesh()
    rng = np.random.default_rng(1)
    o = rng.uniform(-2, 2, (5000, 3))
    d = rng.uniform(-1, 1, (5000, 3)) - 0.3 * o
    ref = simdbvh.BVH(mesh, method="brute").intersect(o, d)
    assert ref["hit"].sum() > 1000
    runs = [simdbvh.BVH(mesh, method="bvh2")] + [simdbvh.BVH(mesh, method=m, isa=i) for i in simdbvh.isas()
                                                 for m in ("bvh4", "bvh8", "bvh16")]
    for bvh in runs:
        for threads in (1, 2):
            h = bvh.intersect(o, d, threads=threads)
            for k in ("t", "u", "v", "prim"):
                np.testing.assert_array_equal(h[k], ref[k], err_msg=f"{bvh.method}/{bvh.isa} {k}")


def test_sorted_batches_bit_identical():
    """Rays from just inside the sphere's surface in random directions, as many as the library's automatic rule
    sorts (a wide tree traces such a batch whole in a sorted order, simdbvh/bvh8/batch_order.h): the hits land at
    the caller's positions, the BVH2's bit for bit, with one and two threads and in batches of 2^20 and fewer."""
    mesh = sphere_mesh()
    rng = np.random.default_rng(5)
    n = (1 << 20) + 3001  # two batches
    p = rng.normal(size=(n, 3))
    o = (0.97 * p / np.linalg.norm(p, axis=1)[:, None]).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    tmax = np.full(n, np.inf, dtype=np.float32)
    tmax[::5] = 1.0  # some end before the sphere
    ref = simdbvh.BVH(mesh, method="bvh2").intersect(o, d, tmax=tmax, threads=2)
    ref_any = simdbvh.BVH(mesh, method="bvh2").occluded(o, d, tmax=tmax, threads=2)
    assert 0.5 * n < ref["hit"].sum() < n
    for method in ("bvh8", "bvh16"):
        bvh = simdbvh.BVH(mesh, method=method)
        for threads in (1, 2):
            h = bvh.intersect(o, d, tmax=tmax, threads=threads)
            for k in ("hit", "t", "u", "v", "prim"):
                np.testing.assert_array_equal(h[k], ref[k], err_msg=f"{method} {threads} threads {k}")
            np.testing.assert_array_equal(bvh.occluded(o, d, tmax=tmax, threads=threads), ref_any)
        few = bvh.intersect(o[:50000], d[:50000], tmax=tmax[:50000])
        np.testing.assert_array_equal(few["t"], ref["t"][:50000])


def test_refit_answers_for_the_moved_mesh():
    mesh = sphere_mesh()
    v = mesh.vertices
    moved_v = (v * np.array([1.5, 0.5, 1.0]) + np.array([0.2, 0.0, -0.1])).astype(np.float32)  # an ellipsoid
    moved = simdbvh.Mesh(moved_v, mesh.faces)
    rng = np.random.default_rng(3)
    o = rng.uniform(-2, 2, (4000, 3))
    d = rng.uniform(-1, 1, (4000, 3)) - 0.3 * o
    ref = simdbvh.BVH(moved, method="brute").intersect(o, d)
    ref_count = simdbvh.BVH(moved, method="brute").count_crossings(o, d)
    before = simdbvh.BVH(mesh, method="brute").intersect(o, d)
    assert (ref["prim"] != before["prim"]).sum() > 500
    before_count = simdbvh.BVH(mesh, method="brute").count_crossings(o, d)
    assert (ref_count["crossings"] != before_count["crossings"]).sum() > 100
    for method in ("bvh2", "bvh4", "bvh8", "bvh16", "brute"):
        bvh = simdbvh.BVH(mesh, method=method)
        bvh.refit(moved_v, threads=2)
        h = bvh.intersect(o, d)
        for k in ("t", "u", "v", "prim"):
            np.testing.assert_array_equal(h[k], ref[k], err_msg=f"{method} {k}")
        # The BVH2 of count and all is built on first use: here after the refit, from the moved vertices.
        np.testing.assert_array_equal(bvh.count_crossings(o, d)["crossings"], ref_count["crossings"], err_msg=method)
        # Built before the refit (by a count), it is refitted with the wide tree.
        early = simdbvh.BVH(mesh, method=method)
        np.testing.assert_array_equal(early.count_crossings(o, d)["crossings"], before_count["crossings"])
        early.refit(moved_v)
        np.testing.assert_array_equal(early.count_crossings(o, d)["crossings"], ref_count["crossings"], err_msg=method)
        assert bvh.contains(np.array([[1.4, 0.0, -0.1]]))[0]  # inside the ellipsoid, outside the sphere
        with pytest.raises(simdbvh.Error, match="expected"):
            bvh.refit(moved_v[:-1])
        bad = moved_v.copy()
        bad[5, 1] = np.nan
        with pytest.raises(simdbvh.Error):
            bvh.refit(bad)
        np.testing.assert_array_equal(bvh.intersect(o, d)["prim"], ref["prim"])  # unchanged by the failed calls


def test_inside_distance_and_signed_distance(cube):
    bvh = simdbvh.BVH(cube)
    p = np.array([[0.5, 0.5, 0.25], [0.5, 0.5, 3.0], [1.0, 0.5, 0.5], [2.0, 2.0, 0.5], [0.0, 0.0, 0.0]])
    assert bvh.sides(p).tolist() == [1, 0, 2, 0, 2]
    assert bvh.contains(p).tolist() == [True, False, False, False, False]
    sd = bvh.signed_distance(p)
    assert sd[0] == -0.25 and sd[1] == 2.0 and sd[2] == 0.0 and sd[4] == 0.0
    assert sd[3] == pytest.approx(np.sqrt(2.0))
    c = bvh.closest_point(p)
    np.testing.assert_allclose(c["points"][1], [0.5, 0.5, 1.0])
    assert c["distance"][1] == 2.0
    far = bvh.closest_point(p, max_distance=0.5)
    assert far["prim"][1] == -1 and np.isinf(far["distance"][1])
    # A grid through the cube's vertices and edges: exact, against the closed box.
    g = np.stack(np.meshgrid(*[np.arange(-2, 7) * 0.25] * 3, indexing="ij"), -1).reshape(-1, 3)
    on = np.all((g >= 0) & (g <= 1), axis=1) & np.any((g == 0) | (g == 1), axis=1)
    inside = np.all((g > 0) & (g < 1), axis=1)
    s = bvh.sides(g, threads=2)
    np.testing.assert_array_equal(s == 2, on)
    np.testing.assert_array_equal(s == 1, inside)


def test_point_queries_identical_on_every_tree():
    """contains, sides, closest_point and signed_distance walk the mesh's wide tree
    when it has one: the same arrays as the BVH2 and brute force, on 1 and 2 threads."""
    mesh = sphere_mesh()
    rng = np.random.default_rng(7)
    p = np.concatenate([rng.uniform(-1.3, 1.3, (3000, 3)), mesh.vertices[::5]])
    ref = simdbvh.BVH(mesh, method="brute")
    want_sides = ref.sides(p)
    want_near = ref.closest_point(p)
    want_sd = ref.signed_distance(p)
    assert (want_sides == 1).sum() > 500 and (want_sides == 2).sum() == len(mesh.vertices[::5])
    for method in ("bvh2", "bvh4", "bvh8", "bvh16"):
        bvh = simdbvh.BVH(mesh, method=method)
        for threads in (1, 2):
            np.testing.assert_array_equal(bvh.sides(p, threads=threads), want_sides, err_msg=method)
            np.testing.assert_array_equal(bvh.signed_distance(p, threads=threads), want_sd, err_msg=method)
            near = bvh.closest_point(p, threads=threads)
            for k in ("distance", "prim", "points", "u", "v"):
                np.testing.assert_array_equal(near[k], want_near[k], err_msg=f"{method} {k}")


def test_inside_ray_choice():
    """ray= picks the axis ray counted from each point. On the cube without its
    top (an open mesh), a point inside sees no crossing upward (+z: outside)
    and one downward (-z: inside); the default (shortest, toward the nearest
    face of the bounds) and the wide trees agree with brute force."""
    open_cube = simdbvh.Mesh(CUBE_V, np.delete(CUBE_F, [2, 3], axis=0))  # no top face
    top = np.array([[0.3, 0.4, 0.9]])  # nearest face of the bounds: the (missing) top
    bottom = np.array([[0.3, 0.4, 0.1]])  # nearest face: the bottom
    for method in ("brute", "bvh2", "bvh8"):
        bvh = simdbvh.BVH(open_cube, method=method)
        assert bvh.sides(top, ray="+z").tolist() == [0], method
        assert bvh.sides(top, ray="-z").tolist() == [1], method
        assert bvh.sides(top).tolist() == [0], method
        assert bvh.sides(bottom).tolist() == [1], method
        assert bvh.contains(top, ray="-z").tolist() == [True], method
    with pytest.raises(ValueError, match="unknown ray 'z'"):
        simdbvh.BVH(open_cube).sides(top, ray="z")


def test_crossings_and_all_hits(cube):
    bvh = simdbvh.BVH(cube)
    # Rays 0 and 1 pass exactly through the diagonals splitting the bottom and top
    # faces (two triangles each): each face is crossed once. Ray 2 passes
    # through face interiors.
    o = np.array([[0.5, 0.5, -1.0], [0.5, 0.5, 0.5], [0.25, 0.75, -1.0]])
    d = np.array([[0, 0, 1], [0, 0, 1], [0, 0, 1]])
    c = bvh.count_crossings(o, d)
    assert c["winding"].tolist() == [0, 1, 0]
    assert c["crossings"].tolist() == [2, 1, 2]
    a = bvh.intersect_all(o, d, max_hits=1)
    assert a["ray"].tolist() == [0, 1, 2]
    assert a["dropped"].tolist() == [1, 0, 1]
    assert a["t"].tolist() == [1.0, 0.5, 1.0]


def test_all_hits_on_threads():
    """intersect_all spreads its rays over threads=: every ray from outside through the centre of a closed sphere
    crosses it exactly twice, and the arrays are the same bits for 1 and 2 threads and for the brute force."""
    mesh = sphere_mesh(32)
    rng = np.random.default_rng(5)
    o = rng.normal(size=(20000, 3))
    o = 3 * o / np.linalg.norm(o, axis=1, keepdims=True)
    d = -o + rng.uniform(-0.01, 0.01, o.shape)
    one = simdbvh.BVH(mesh, method="bvh2").intersect_all(o, d)
    assert np.bincount(one["ray"], minlength=len(o)).tolist() == [2] * len(o)
    for got in (simdbvh.BVH(mesh, method="bvh2").intersect_all(o, d, threads=2),
                simdbvh.BVH(mesh, method="brute").intersect_all(o[:2000], d[:2000], threads=2)):
        n = len(got["dropped"])
        keep = one["ray"] < n
        for k in ("ray", "t", "prim", "u", "v", "facing"):
            assert got[k].tobytes() == one[k][keep].tobytes(), k
    with pytest.raises(simdbvh.Error, match="threads"):
        simdbvh.BVH(mesh).intersect_all(o[:1], d[:1], threads=-1)


def test_threads_zero_means_every_core():
    """threads=0 (as Open3D reads it) runs on every hardware thread: the same bits as one thread, for rays, points
    and scenes; negative counts and counts over 1024 are refused."""
    mesh = sphere_mesh(24)
    rng = np.random.default_rng(8)
    o = rng.uniform(-2, 2, (5000, 3))
    d = -o + rng.uniform(-0.2, 0.2, o.shape)
    bvh = simdbvh.BVH(mesh)
    one, every = bvh.intersect(o, d, threads=1), bvh.intersect(o, d, threads=0)
    assert all(one[k].tobytes() == every[k].tobytes() for k in one)
    assert bvh.signed_distance(o, threads=0).tobytes() == bvh.signed_distance(o).tobytes()
    scene = simdbvh.Scene(meshes=[mesh])
    a, b = scene.intersect(o, d, threads=0), scene.intersect(o, d)
    assert all(a[k].tobytes() == b[k].tobytes() for k in a)
    for bad in (-1, 1025):
        with pytest.raises(simdbvh.Error, match=r"threads must be 0 \(every core\) or 1..1024"):
            bvh.contains(o, threads=bad)


def test_repr():
    bvh = simdbvh.BVH(sphere_mesh(8), method="bvh4")
    assert repr(bvh) == f"<simdbvh.BVH: {len(sphere_mesh(8))} triangles, bvh4/{bvh.isa}>"


def test_dtypes_layouts_and_errors(cube):
    bvh = simdbvh.BVH(cube)
    p64 = np.asfortranarray(np.array([[0.5, 0.5, 0.25]] * 4, dtype=np.float64))
    assert bvh.contains(p64).all()
    assert bvh.contains([0.5, 0.5, 0.5]).tolist() == [True]  # a single point
    with pytest.raises(simdbvh.Error, match="shape"):
        bvh.contains(np.zeros((3, 2)))
    with pytest.raises(simdbvh.Error, match="out of range"):
        simdbvh.Mesh(CUBE_V, CUBE_F + 10)
    with pytest.raises(simdbvh.Error, match="out of range"):
        simdbvh.Mesh(CUBE_V, -CUBE_F - 1)
    bad = CUBE_V.copy()
    bad[3, 1] = np.nan
    with pytest.raises(simdbvh.Error):
        simdbvh.Mesh(bad, CUBE_F)
    with pytest.raises(ValueError):  # simdbvh.Error is a ValueError
        simdbvh.BVH(cube, method="octree")
    with pytest.raises(simdbvh.Error, match="differ in length"):
        bvh.intersect(np.zeros((2, 3)), np.ones((3, 3)))
    with pytest.raises(simdbvh.Error, match="threads"):
        bvh.contains(p64, threads=-1)
    with pytest.raises(simdbvh.Error, match="rule"):
        bvh.sides(p64, rule="majority")
    with pytest.raises(simdbvh.Error):
        simdbvh.load("/nonexistent/mesh.ply")
    with pytest.raises(simdbvh.Error, match="isa"):
        simdbvh.BVH(cube, isa="sse9")


def test_load_a_file(tmp_path):
    path = tmp_path / "tri.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    m = simdbvh.load(str(path))
    assert len(m) == 1
    h = simdbvh.BVH(m).intersect([[0.2, 0.2, 1.0]], [[0, 0, -1]])
    assert h["prim"][0] == 0 and h["t"][0] == 1.0


def test_a_path_with_a_nul_byte_is_refused(tmp_path):
    """A C++ loader would read the path up to the NUL and open another file: here the existing tri.obj."""
    path = tmp_path / "tri.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(simdbvh.Error, match="path contains a NUL byte"):
        simdbvh.load(str(path) + "\0.ply")
    with pytest.raises(simdbvh.Error, match="path contains a NUL byte"):
        simdbvh.load(os.fsencode(str(path)) + b"\0")
    assert len(simdbvh.load(str(path))) == 1


def test_gil_is_released_during_a_long_trace():
    """A second Python thread keeps running while one thread traces."""
    mesh = sphere_mesh(64)
    bvh = simdbvh.BVH(mesh, method="brute")  # slow on purpose: ~16k triangles per ray
    rng = np.random.default_rng(3)
    o = rng.uniform(-2, 2, (3000, 3))
    d = -o + rng.uniform(-0.1, 0.1, (3000, 3))
    assert_gil_released(lambda: bvh.intersect(o, d))


def test_memory_and_reference_counts_are_stable():
    import gc
    import resource
    import sys
    mesh = sphere_mesh(12)
    bvh = simdbvh.BVH(mesh)
    o = np.zeros((1000, 3))
    d = np.tile([1.0, 0.2, 0.1], (1000, 1))
    refs = (sys.getrefcount(o), sys.getrefcount(d), sys.getrefcount(bvh))
    for _ in range(50):  # warm up the allocator
        bvh.intersect(o, d)
        bvh.signed_distance(o)
    gc.collect()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for _ in range(1000):
        h = bvh.intersect(o, d)
        bvh.contains(o)
        bvh.count_crossings(o, d)
    del h
    gc.collect()
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    assert (sys.getrefcount(o), sys.getrefcount(d), sys.getrefcount(bvh)) == refs
    assert after - before < 20 * 1024, f"peak RSS grew by {after - before} KiB over 1,000 calls"


def test_bit_identical_to_the_cli(tmp_path):
    """The same rays through the C++ CLI (simdbvh trace) and the module: 40,000 rays with per-ray tmin and tmax,
    so the module's chunks (kRayChunk = 16,384 rays, python/src/arrays.h) end inside the batch, on one thread and
    on two."""
    import subprocess
    cli = os.environ.get("SIMDBVH_CLI")
    if not cli:
        pytest.skip("SIMDBVH_CLI is not set (ctest sets it)")
    rays = tmp_path / "r.bin"
    r = subprocess.run([cli, "gen-rays", "--scene", "icosphere-3", "--kind", "incoherent", "--count", "40000",
                        "--out", str(rays)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    rec = np.fromfile(rays, dtype="<f4").reshape(-1, 8)
    mesh = simdbvh.load("icosphere-3")
    for method in ("bvh8", "bvh2"):
        hits = tmp_path / f"{method}.hits"
        r = subprocess.run([cli, "trace", "--scene", "icosphere-3", "--rays", str(rays), "--out", str(hits),
                            "--method", method], capture_output=True, text=True)
        assert r.returncode == 0, r.stdout + r.stderr
        want = np.fromfile(hits, dtype=np.dtype([("t", "<f4"), ("u", "<f4"), ("v", "<f4"), ("prim", "<u4")]))
        bvh = simdbvh.BVH(mesh, method=method)
        for threads in (1, 2):
            got = bvh.intersect(rec[:, 0:3], rec[:, 4:7], tmin=rec[:, 3], tmax=rec[:, 7], threads=threads)
            np.testing.assert_array_equal(got["t"].view(np.uint32), want["t"].view(np.uint32))
            np.testing.assert_array_equal(got["u"].view(np.uint32), want["u"].view(np.uint32))
            np.testing.assert_array_equal(got["v"].view(np.uint32), want["v"].view(np.uint32))
            np.testing.assert_array_equal(got["prim"], np.where(want["prim"] == 0xFFFFFFFF, -1, want["prim"]))
            np.testing.assert_array_equal(got["hit"], want["prim"] != 0xFFFFFFFF)
            assert got["hit"].sum() > 10000
