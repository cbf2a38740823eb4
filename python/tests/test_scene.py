"""simdbvh.Scene against the library's own rules and hand-computed answers:
every method (bvh4, bvh8, bvh16, brute) bit-identical on built-in scenes and
to the CLI, closed-form hits on spheres, planes, boxes and translated
instances, every bad input as simdbvh.Error, the GIL released during a trace.

Built-ins that need cached meshes (room: bunny and teapot; instances-N: the
dragon) skip when the cache (SIMDBVH_CACHE, else ~/.cache/simdbvh/scenes)
lacks them."""
import os
import subprocess

import numpy as np
import pytest

import simdbvh
from gil_probe import assert_gil_released

METHODS = ("bvh8", "bvh4", "bvh16", "brute")
KEYS = ("hit", "t", "u", "v", "prim", "geom", "inst")

TRI_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
TRI_F = np.array([[0, 1, 2]])


def translate(x, y, z):
    return np.array([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z]], dtype=np.float32)


def load_or_skip(name, method="bvh8"):
    try:
        return simdbvh.load_scene(name, method=method)
    except simdbvh.Error as e:
        if "not cached" in str(e):
            pytest.skip(f"{name}: {e}")
        raise


def assert_same(got, want, label):
    """Bit equality of t, u, v (as uint32) and equality of the ids."""
    for k in ("t", "u", "v"):
        np.testing.assert_array_equal(got[k].view(np.uint32), want[k].view(np.uint32), err_msg=f"{label}: {k}")
    for k in ("hit", "prim", "geom", "inst"):
        np.testing.assert_array_equal(got[k], want[k], err_msg=f"{label}: {k}")


def random_rays(scene, n, seed):
    """Origins uniform in the scene's bounds, directions uniform on the sphere."""
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    o = rng.uniform(lo, hi, (n, 3)).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    return o, d


def check_hit_ids(h, scene):
    """The documented id conventions: -1 for misses, planes after the instances."""
    miss = ~h["hit"]
    assert (h["prim"][miss] == -1).all() and (h["geom"][miss] == -1).all() and (h["inst"][miss] == -1).all()
    assert np.isinf(h["t"][miss]).all()
    plane = h["hit"] & (h["inst"] >= scene.num_instances)
    assert (h["geom"][plane] == -1).all()
    np.testing.assert_array_equal(h["prim"][plane], h["inst"][plane] - scene.num_instances)
    inst = h["hit"] & ~plane
    assert (h["geom"][inst] >= 0).all() and (h["geom"][inst] < scene.num_geometries).all()


# --- every method gives the same bits ------------------------------------------------------------


def test_room_every_method_bit_identical():
    ref = load_or_skip("room", method="brute")
    assert (ref.num_geometries, ref.num_instances, ref.num_planes) == (4, 5, 4)
    o, d = random_rays(ref, 3000, seed=17)
    want = ref.intersect(o, d)
    check_hit_ids(want, ref)
    planes = want["inst"] >= ref.num_instances
    assert planes.sum() > 500 and (~planes).sum() > 300, (planes.sum(), (~planes).sum())
    assert len(set(want["geom"][~planes].tolist())) == 4  # bunny, teapot, boxes, spheres
    any_ref = ref.occluded(o, d, tmax=1.0)
    for method in ("bvh8", "bvh4", "bvh16"):
        s = simdbvh.load_scene("room", method=method)
        assert s.method == method
        assert_same(s.intersect(o, d), want, f"room {method}")
        assert_same(s.intersect(o, d, threads=2), want, f"room {method} threads=2")
        np.testing.assert_array_equal(s.occluded(o, d, tmax=1.0), any_ref, err_msg=f"room {method} occluded")
    assert_same(ref.intersect(o, d, threads=2), want, "room brute threads=2")


def test_room_every_isa_bit_identical():
    ref = load_or_skip("room", method="bvh8")
    o, d = random_rays(ref, 1000, seed=5)
    want = ref.intersect(o, d)
    for isa in simdbvh.isas():
        for method in ("bvh4", "bvh16"):
            s = simdbvh.load_scene("room", method=method, isa=isa)
            assert s.isa == isa
            assert_same(s.intersect(o, d), want, f"room {method}/{isa}")


def test_instances_4_every_method_bit_identical():
    """Four dragons (871k triangles each): the trees on 2,000 rays, the brute force (~0.1 s per ray) on 12 of them."""
    s8 = load_or_skip("instances-4", method="bvh8")
    assert (s8.num_geometries, s8.num_instances, s8.num_planes) == (1, 4, 0)
    assert s8.stats["instanced_primitives"] == 4 * s8.stats["primitives"]
    rng = np.random.default_rng(23)
    lo, hi = s8.bounds
    # Half the rays aimed at points near the dragons' centres, so that many hit.
    o = rng.uniform(lo, hi, (2000, 3)).astype(np.float32)
    d = rng.normal(size=(2000, 3)).astype(np.float32)
    d[::2] = rng.uniform(lo, hi, (1000, 3)) * 0.1 + (lo + hi) * 0.45 - o[::2]
    want = s8.intersect(o, d, threads=2)
    check_hit_ids(want, s8)
    assert want["hit"].sum() > 200, want["hit"].sum()
    assert len(set(want["inst"][want["hit"]].tolist())) >= 3
    for method in ("bvh4", "bvh16"):
        assert_same(simdbvh.load_scene("instances-4", method=method).intersect(o, d), want, f"instances-4 {method}")
    pick = np.r_[np.flatnonzero(want["hit"])[:8], np.flatnonzero(~want["hit"])[:4]]
    brute = simdbvh.load_scene("instances-4", method="brute")
    got = brute.intersect(o[pick], d[pick])
    assert_same(got, {k: v[pick] for k, v in want.items()}, "instances-4 brute")


def test_numpy_scene_every_method_bit_identical():
    """A scene made of arrays only: two meshes, two sphere sets, a box set, rotated and scaled instances, planes."""
    rng = np.random.default_rng(9)
    ico = simdbvh.load("icosphere-2")
    grid = np.stack(np.meshgrid(np.arange(4), np.arange(4), indexing="ij"), -1).reshape(-1, 2)
    sheet_v = np.c_[grid, rng.uniform(-0.1, 0.1, len(grid))].astype(np.float32)
    idx = lambda i, j: 4 * i + j
    sheet_f = [[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)] for i in range(3) for j in range(3)] + \
              [[idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)] for i in range(3) for j in range(3)]
    spheres = np.c_[rng.uniform(-3, 3, (50, 3)), rng.uniform(0.05, 0.4, 50)]
    boxes_lo = rng.uniform(-3, 3, (40, 3))
    boxes = np.c_[boxes_lo, boxes_lo + rng.uniform(0.0, 0.5, (40, 3))]  # some flat ones (extent 0 rounds)
    boxes[0, 4] = boxes[0, 1]  # a flat box

    def rot(axis, deg, scale, t):
        a = np.asarray(axis, float) / np.linalg.norm(axis)
        k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        th = np.radians(deg)
        r = np.eye(3) + np.sin(th) * k + (1 - np.cos(th)) * k @ k
        return np.c_[r * scale, t]

    instances = [(0, rot([1, 1, 0], 30, 0.7, [1, 0, 0])), (0, rot([0, 0, 1], 200, 1.3, [-2, 1, 0.5])),
                 (1, rot([0, 1, 0], 45, [1.0, 2.0, 0.5], [0, -2, 1])), (2, np.eye(4)),
                 (3, rot([1, 0, 1], 10, 1.0, [0.5, 0.5, 0.5])), (4, translate(0, 0, 0.25)),
                 (2, rot([1, 2, 3], 77, 0.5, [2, 2, 2]))]
    planes = np.array([[0, -4, 0, 0, 1, 0], [0, 0, 5, 0.1, 0.2, -1]])
    kw = dict(meshes=[ico, (sheet_v, sheet_f)], spheres=[spheres[:25], spheres[25:]], boxes=boxes,
              instances=instances, planes=planes)
    ref = simdbvh.Scene(**kw, method="brute")
    assert (ref.num_geometries, ref.num_instances, ref.num_planes) == (5, 7, 2)
    assert ref.stats["primitives"] == len(ico) + 18 + 50 + 40
    o = rng.uniform(-4, 4, (3000, 3))
    d = rng.normal(size=(3000, 3))
    want = ref.intersect(o, d, normals=True)
    check_hit_ids(want, ref)
    kinds = set(want["geom"][want["hit"]].tolist())
    assert kinds == {-1, 0, 1, 2, 3, 4}, kinds
    for method in ("bvh8", "bvh4", "bvh16"):
        s = simdbvh.Scene(**kw, method=method)
        got = s.intersect(o, d, normals=True)
        assert_same(got, want, f"numpy scene {method}")
        np.testing.assert_array_equal(got["normals"], want["normals"])
        np.testing.assert_array_equal(s.occluded(o, d, tmax=2.0), ref.occluded(o, d, tmax=2.0))
    n = want["normals"][want["hit"]]
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-6)
    assert np.isnan(want["normals"][~want["hit"]]).all()


def test_batches_across_chunks_bit_identical():
    """A batch of several chunks (the module traces a scene batch in pieces of 32,768 rays, the library's chunk):
    every ray's hit at its own position, against the brute force on the same batch, one and two threads."""
    ref = simdbvh.load_scene("spheres-200", method="brute")
    n = 2 * 32768 + 16384 + 1234
    rng = np.random.default_rng(31)
    lo, hi = ref.bounds
    o = rng.uniform(lo, hi, (n, 3)).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    tmax = np.where(np.arange(n) % 3 == 0, np.float32(0.05), np.float32(np.inf))  # every third ray short
    want = ref.intersect(o, d, tmax=tmax, threads=2)
    any_want = ref.occluded(o, d, tmax=tmax, threads=2)
    check_hit_ids(want, ref)
    assert 0.2 * n < want["hit"].sum() < 0.9 * n, want["hit"].sum()
    assert not np.array_equal(any_want[:32768], any_want[32768:65536])  # the pieces differ: misplaced ones show
    for method in ("bvh8", "bvh16"):
        s = simdbvh.load_scene("spheres-200", method=method)
        for threads in (1, 2):
            assert_same(s.intersect(o, d, tmax=tmax, threads=threads), want, f"{method} threads={threads}")
            np.testing.assert_array_equal(s.occluded(o, d, tmax=tmax, threads=threads), any_want,
                                          err_msg=f"{method} threads={threads} occluded")


def test_bit_identical_to_the_cli(tmp_path):
    """The same rays through `simdbvh trace --scene` (scene hit files) and the module; on spheres-2000 40,000 rays
    on two threads, so the module's chunks of 32,768 rays end inside the batch."""
    cli = os.environ.get("SIMDBVH_CLI")
    if not cli:
        pytest.skip("SIMDBVH_CLI is not set (ctest sets it)")
    names = ["spheres-2000"]
    try:
        simdbvh.load_scene("room", method="brute")
        names.append("room")
    except simdbvh.Error:
        pass  # not cached
    rec_t = np.dtype([("t", "<f4"), ("u", "<f4"), ("v", "<f4"), ("prim", "<u4"), ("geom", "<u4"), ("inst", "<u4")])
    for name in names:
        rays = tmp_path / f"{name}.rays"
        r = subprocess.run([cli, "gen-rays", "--scene", name, "--kind", "incoherent", "--count",
                            "40000" if name.startswith("spheres") else "3000",
                            "--out", str(rays)], capture_output=True, text=True)
        assert r.returncode == 0, r.stdout + r.stderr
        rec = np.fromfile(rays, dtype="<f4").reshape(-1, 8)
        for method, any_hit in (("bvh8", False), ("bvh4", False), ("brute", False), ("bvh8", True)):
            hits = tmp_path / f"{name}.{method}.hits"
            r = subprocess.run([cli, "trace", "--scene", name, "--rays", str(rays), "--out", str(hits),
                                "--method", method] + (["--any-hit"] if any_hit else []),
                               capture_output=True, text=True)
            assert r.returncode == 0, r.stdout + r.stderr
            want = np.fromfile(hits, dtype=rec_t)
            scene = simdbvh.load_scene(name, method=method)
            args = (rec[:, 0:3], rec[:, 4:7], rec[:, 3], rec[:, 7])
            if any_hit:
                np.testing.assert_array_equal(scene.occluded(*args, threads=2), want["prim"] != 0xFFFFFFFF)
                continue
            got = scene.intersect(*args, threads=2)
            label = f"{name} {method}"
            for k in ("t", "u", "v"):
                np.testing.assert_array_equal(got[k].view(np.uint32), want[k].view(np.uint32), err_msg=label)
            for k in ("prim", "geom", "inst"):
                np.testing.assert_array_equal(got[k], np.where(want[k] == 0xFFFFFFFF, -1, want[k]), err_msg=label)
            assert got["hit"].sum() > 500, label


# --- answers by hand -----------------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_unit_sphere_by_hand(method):
    s = simdbvh.Scene(spheres=[[0, 0, 0, 1]], method=method)
    assert (s.num_geometries, s.num_instances, s.num_planes) == (1, 1, 0)
    o = np.array([[0, 0, -5], [0, 0, -5], [0, 0, 0], [0, 2, -5], [0, 0, 5]], dtype=np.float32)
    d = np.array([[0, 0, 1], [0, 0, 2], [1, 0, 0], [0, 0, 1], [0, 0, 1]], dtype=np.float32)
    h = s.intersect(o, d, normals=True)
    assert h["hit"].tolist() == [True, True, True, False, False]
    # From z = -5 along +z: the near root z = -1 at t = 4 (t = 2 for the doubled direction); from the
    # centre: the far root at t = 1.
    assert h["t"][:3].tolist() == [4.0, 2.0, 1.0]
    assert np.isinf(h["t"][3:]).all()
    assert h["prim"].tolist() == [0, 0, 0, -1, -1]
    assert h["geom"].tolist() == [0, 0, 0, -1, -1] and h["inst"].tolist() == [0, 0, 0, -1, -1]
    # u = (atan2(n.y, n.x) + pi) / 2pi, v = acos(n.z) / pi: the south pole n = (0, 0, -1) gives u = 1/2, v = 1;
    # n = (1, 0, 0) gives u = 1/2 (atan2(0, 1) = 0), v = 1/2.
    assert h["u"][:3].tolist() == [0.5, 0.5, 0.5] and h["v"][:3].tolist() == [1.0, 1.0, 0.5]
    np.testing.assert_array_equal(h["normals"][:3], [[0, 0, -1], [0, 0, -1], [1, 0, 0]])
    assert np.isnan(h["normals"][3:]).all()
    assert s.occluded(o, d).tolist() == [True, True, True, False, False]
    assert s.occluded(o, d, tmax=3.5).tolist() == [False, True, True, False, False]
    assert s.intersect(o, d, tmin=4.5)["t"][0] == 6.0  # the far root z = +1
    assert np.isinf(s.intersect(o, d, tmax=3.99)["t"][0])


@pytest.mark.parametrize("method", METHODS)
def test_plane_by_hand(method):
    # The floor y = 0 (a point and a normal, as the library's Plane) and a sphere above it.
    s = simdbvh.Scene(spheres=[[0, 2, 0, 0.5]], planes=[[0, 0, 0, 0, 1, 0]], method=method)
    assert s.num_planes == 1 and s.num_instances == 1
    o = np.array([[1, 3, 2], [1, 3, 2], [0, 5, 0], [0, 1, 0], [0, -1, 0]], dtype=np.float32)
    d = np.array([[0, -1, 0], [0, -2, 0], [0, -1, 0], [1, 0, 0], [0.5, 1, 0.25]], dtype=np.float32)
    h = s.intersect(o, d, normals=True)
    assert h["hit"].tolist() == [True, True, True, False, True]
    assert h["t"].tolist()[:3] == [3.0, 1.5, 2.5] and h["t"][4] == 1.0  # the sphere's top y = 2.5 at t = 2.5
    # Plane 0 of a scene with one instance: prim 0, geom -1, inst 1 (the planes follow the instances).
    assert h["prim"].tolist() == [0, 0, 0, -1, 0]
    assert h["geom"].tolist() == [-1, -1, 0, -1, -1]
    assert h["inst"].tolist() == [1, 1, 0, -1, 1]
    assert h["u"][[0, 1, 4]].tolist() == [0, 0, 0] and h["v"][[0, 1, 4]].tolist() == [0, 0, 0]
    np.testing.assert_array_equal(h["normals"][[0, 1, 4]], [[0, 1, 0]] * 3)  # not turned toward the ray
    # A plane with a long normal through (0, 0, -2): z = -2.
    s = simdbvh.Scene(planes=[[0, 0, -2, 0, 0, -10]], method=method)
    assert s.num_instances == 0
    h = s.intersect([[0.3, 0.4, 2.0]], [[0, 0, -1]], normals=True)
    assert h["t"][0] == 4.0 and h["inst"][0] == 0 and h["prim"][0] == 0
    np.testing.assert_array_equal(h["normals"][0], [0, 0, -1])


@pytest.mark.parametrize("method", METHODS)
def test_translated_instance_by_hand(method):
    # One triangle (0,0,0) (1,0,0) (0,1,0), placed at the origin and translated by (10, 0, 0).
    s = simdbvh.Scene(meshes=[(TRI_V, TRI_F)], instances=[(0, np.eye(4)), (0, translate(10, 0, 0))],
                      method=method)
    o = np.array([[10.25, 0.5, 5], [0.25, 0.5, 5], [5.25, 0.5, 5], [10.5, 0.25, -3]], dtype=np.float32)
    d = np.array([[0, 0, -1], [0, 0, -1], [0, 0, -1], [0, 0, 0.5]], dtype=np.float32)
    h = s.intersect(o, d, normals=True)
    assert h["hit"].tolist() == [True, True, False, True]
    # The hit point (x - 10, y) = (1 - u - v) v0 + u v1 + v v2 = (u, v) in the object's frame; t in world units.
    assert h["t"].tolist()[:2] == [5.0, 5.0] and h["t"][3] == 6.0
    assert h["inst"].tolist() == [1, 0, -1, 1]
    assert h["geom"].tolist() == [0, 0, -1, 0] and h["prim"].tolist() == [0, 0, -1, 0]
    assert h["u"][[0, 1, 3]].tolist() == [0.25, 0.25, 0.5] and h["v"][[0, 1, 3]].tolist() == [0.5, 0.5, 0.25]
    np.testing.assert_array_equal(h["normals"][[0, 1, 3]], [[0, 0, 1]] * 3)  # by winding
    # Scaled by 2 about the origin (a (3, 4) [A | b]): the triangle reaches (2, 0, 0) and (0, 2, 0).
    s2 = simdbvh.Scene(meshes=simdbvh.Mesh(TRI_V, TRI_F), instances=[(0, [[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 0]])],
                       method=method)
    h = s2.intersect([[1.0, 0.5, 4.0]], [[0, 0, -1]])
    assert h["t"][0] == 4.0 and h["u"][0] == 0.5 and h["v"][0] == 0.25 and h["inst"][0] == 0


@pytest.mark.parametrize("method", METHODS)
def test_box_and_tie_rules_by_hand(method):
    # A unit box set twice at the same place (two instances) and a sphere set: equal t goes to the lower inst.
    s = simdbvh.Scene(spheres=[[5, 5, 5, 1]], boxes=[[0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1]],
                      instances=[(1, translate(0, 0, 0)), (1, np.eye(3, 4)), (0, np.eye(3, 4))], method=method)
    h = s.intersect([[0.5, 0.25, -2], [5, 5, 0]], [[0, 0, 1], [0, 0, 1]], normals=True)
    assert h["hit"].all()
    assert h["t"].tolist() == [2.0, 4.0]
    # Box face z = 0: u = x, v = y; both boxes and both instances tie: inst 0, prim 0.
    assert (h["inst"][0], h["geom"][0], h["prim"][0]) == (0, 1, 0)
    assert (h["u"][0], h["v"][0]) == (0.5, 0.25)
    assert (h["inst"][1], h["geom"][1], h["prim"][1]) == (2, 0, 0)
    np.testing.assert_array_equal(h["normals"], [[0, 0, -1], [0, 0, -1]])


def test_json_scene_equals_the_array_scene(tmp_path):
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "s.json").write_text("""{
      "geometries": [{"name": "tri", "mesh": "tri.obj"},
                     {"spheres": [{"center": [0, 1, 0], "radius": 0.5}]},
                     {"boxes": [{"min": [2, 0, 0], "max": [3, 1, 1]}]}],
      "instances": [{"geometry": "tri", "translate": [10, 0, 0]},
                    {"geometry": 1, "transform": [[1, 0, 0, 0], [0, 1, 0, 2], [0, 0, 1, 0]]},
                    {"geometry": 2}],
      "planes": [{"point": [0, -1, 0], "normal": [0, 1, 0]}]}""")
    js = simdbvh.load_scene(str(tmp_path / "s.json"))
    arr = simdbvh.Scene(meshes=[(TRI_V, TRI_F)], spheres=[[0, 1, 0, 0.5]], boxes=[[2, 0, 0, 3, 1, 1]],
                        instances=[(0, translate(10, 0, 0)), (1, translate(0, 2, 0)), (2, np.eye(4))],
                        planes=[[0, -1, 0, 0, 1, 0]])
    assert (js.num_geometries, js.num_instances, js.num_planes) == (3, 3, 1)
    rng = np.random.default_rng(4)
    o = rng.uniform(-1, 11, (2000, 3))
    d = rng.normal(size=(2000, 3))
    a, b = js.intersect(o, d), arr.intersect(o, d)
    assert_same(a, b, "json vs arrays")
    assert set(a["inst"][a["hit"]].tolist()) >= {1, 2, 3}
    h = js.intersect([[10.25, 0.5, 5]], [[0, 0, -1]])
    assert (h["t"][0], h["inst"][0], h["geom"][0]) == (5.0, 0, 0)


def test_properties_stats_and_repr():
    s = simdbvh.load_scene("spheres-100", method="bvh16")
    assert (s.num_geometries, s.num_instances, s.num_planes) == (1, 1, 0)
    assert s.method == "bvh16" and s.isa in simdbvh.isas()
    st = s.stats
    assert st["primitives"] == 100 and st["instanced_primitives"] == 100 and st["bytes"] > 0
    assert st["build_ms"] >= 0 and st["max_cond"] == 1.0
    lo, hi = s.bounds
    assert (lo >= -0.5).all() and (hi <= 1.5).all() and (lo < hi).all()
    b = simdbvh.load_scene("spheres-100", method="brute")
    assert b.isa == "scalar" and "bytes" not in b.stats and b.stats["primitives"] == 100
    assert "simdbvh.Scene" in repr(s) and "bvh16" in repr(s)
    empty = simdbvh.Scene()
    assert (empty.num_geometries, empty.num_instances, empty.num_planes) == (0, 0, 0)
    h = empty.intersect(np.zeros((3, 3)), np.ones((3, 3)))
    assert not h["hit"].any() and (h["inst"] == -1).all()
    assert empty.intersect(np.zeros((0, 3)), np.zeros((0, 3)))["t"].shape == (0,)
    # Geometries without an instance are not traced; empty geometries are allowed.
    s = simdbvh.Scene(spheres=[np.zeros((0, 4)), [[0, 0, 0, 1]]], boxes=np.zeros((0, 6)), instances=[(1, np.eye(4))])
    assert s.num_geometries == 3
    assert s.intersect([[0, 0, -5]], [[0, 0, 1]])["geom"][0] == 1


# --- errors ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("kwargs, match", [
    (dict(method="octree"), "method"),
    (dict(method="bvh2"), "method"),
    (dict(isa="sse9"), "isa"),
    (dict(spheres=np.zeros((2, 3))), r"spheres: expected shape \(n, 4\)"),
    (dict(spheres=[[0, 0, np.nan, 1]]), r"geometries\[0\].spheres\[0\].center: not finite"),
    (dict(spheres=[[0, 0, 0, -1]]), "radius: negative"),
    (dict(spheres=[[0, 0, 0, np.inf]]), "radius: not finite"),
    (dict(spheres="abc"), "spheres"),
    (dict(boxes=[[0, 0, 0, 1, -1, 1]]), r"geometries\[0\].boxes\[0\]: min > max"),
    (dict(boxes=np.zeros((1, 5))), r"boxes: expected shape \(n, 6\)"),
    (dict(planes=[[0, 0, 0, 0, 0, 0]]), r"planes\[0\].normal: zero"),
    (dict(planes=[[0, 1, 0, 0]]), r"planes: expected shape \(n, 6\)"),
    (dict(planes=[[0, 0, np.nan, 0, 1, 0]]), r"planes\[0\].point: not finite"),
    (dict(meshes=[(TRI_V, TRI_F + 3)]), r"meshes\[0\]: faces: .*out of range"),
    (dict(meshes=[(np.full((3, 3), np.nan), TRI_F)]), "meshes"),
    (dict(meshes=[(TRI_V[:, :2], TRI_F)]), r"meshes\[0\]: vertices: expected shape"),
    (dict(meshes=[TRI_V]), r"meshes\[0\]: expected a simdbvh.Mesh"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[(1, np.eye(4))]), r"instances\[0\].geometry: no geometry 1"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[(-1, np.eye(4))]), r"instances\[0\].geometry: no geometry -1"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[("a", np.eye(4))]), r"instances\[0\].geometry: expected an integer"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[(0, np.zeros((3, 4)))]), r"instances\[0\].transform: singular"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[(0, np.diag([1.0, 1.0, 0.0, 1.0]))]), "singular"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[(0, translate(np.nan, 0, 0))]), r"instances\[0\].transform: non-finite"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[(0, np.eye(3))]), r"instances\[0\].transform: expected shape"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[(0, np.ones((4, 4)))]), "last row"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=[0]), r"instances\[0\]: expected a \(geometry_index, transform\)"),
    (dict(meshes=[(TRI_V, TRI_F)], instances=5), "instances: expected a list"),
])
def test_construction_errors(kwargs, match):
    for method in ("bvh8", "brute"):
        args = dict(method=method) | kwargs
        with pytest.raises(simdbvh.Error, match=match):
            simdbvh.Scene(**args)


def test_query_and_loading_errors(tmp_path):
    s = simdbvh.Scene(spheres=[[0, 0, 0, 1]])
    with pytest.raises(simdbvh.Error, match="differ in length"):
        s.intersect(np.zeros((2, 3)), np.ones((3, 3)))
    with pytest.raises(simdbvh.Error, match="shape"):
        s.occluded(np.zeros((2, 2)), np.ones((2, 2)))
    with pytest.raises(simdbvh.Error, match="threads"):
        s.intersect(np.zeros((2, 3)), np.ones((2, 3)), threads=-1)
    with pytest.raises(simdbvh.Error, match="tmax"):
        s.intersect(np.zeros((2, 3)), np.ones((2, 3)), tmax=np.ones(3))
    with pytest.raises(simdbvh.Error):
        simdbvh.load_scene("/nonexistent/scene.json")
    with pytest.raises(simdbvh.Error):
        simdbvh.load_scene("/nonexistent/mesh.ply")
    with pytest.raises(simdbvh.Error, match="method"):
        simdbvh.load_scene("spheres-10", method="bvh2")
    bad = tmp_path / "bad.json"
    bad.write_text('{"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]}], ')
    with pytest.raises(simdbvh.Error, match="bad.json"):
        simdbvh.load_scene(str(bad))
    bad.write_text('{"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]}], '
                   '"instances": [{"geometry": 0, "transform": [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0]]}]}')
    with pytest.raises(simdbvh.Error, match=r"instances\[0\].transform: singular"):
        simdbvh.load_scene(str(bad))
    bad.write_text('{"geometries": [], "colour": 1}')
    with pytest.raises(simdbvh.Error, match="colour"):
        simdbvh.load_scene(str(bad))
    assert issubclass(simdbvh.Error, ValueError)


def test_a_scene_name_with_a_nul_byte_is_refused(tmp_path):
    """The loaders would read the name up to the NUL: the existing s.json and tri.obj, or the built-in room."""
    (tmp_path / "s.json").write_text('{"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]}]}')
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    for name in (str(tmp_path / "s.json") + "\0.obj", str(tmp_path / "tri.obj") + "\0", "spheres-10\0x"):
        with pytest.raises(simdbvh.Error, match="name contains a NUL byte"):
            simdbvh.load_scene(name)
    assert simdbvh.load_scene(str(tmp_path / "s.json")).num_geometries == 1


SPECIAL_FILES_SCRIPT = r"""
import json, os, resource, sys
import simdbvh
vm = next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmSize:")) * 1024
resource.setrlimit(resource.RLIMIT_AS, (vm + (1500 << 20), resource.getrlimit(resource.RLIMIT_AS)[1]))
out = {}
for name in sys.argv[1:]:
    for load in (simdbvh.load_scene, simdbvh.load) if not name.endswith(".json") else (simdbvh.load_scene,):
        try:
            load(name)
            out[f"{load.__name__} {name}"] = "accepted"
        except simdbvh.Error as e:
            out[f"{load.__name__} {name}"] = str(e)
        except MemoryError:
            out[f"{load.__name__} {name}"] = "MemoryError"
print(json.dumps(out))
"""


def test_special_files_named_as_scenes_are_refused(tmp_path):
    """A FIFO, a folder and /dev/zero (through a symlink) named x.json or x.obj: simdbvh.Error at once, naming the
    file (the JSON loader blocked on the FIFO, read /dev/zero until memory ran out and called a folder 'not valid
    JSON'; the C++ loader reads regular files only). In a child process with a timeout and an address-space limit,
    so a hang or a runaway read fails this test instead of stopping the run."""
    import json
    import sys
    fifo, folder, zero, null = (tmp_path / n for n in ("fifo.json", "folder.json", "zero.json", "null.json"))
    os.mkfifo(fifo)
    folder.mkdir()
    zero.symlink_to("/dev/zero")
    null.symlink_to("/dev/null")
    obj_fifo, obj_folder = tmp_path / "fifo.obj", tmp_path / "folder.ply"
    os.mkfifo(obj_fifo)
    obj_folder.mkdir()
    names = [str(p) for p in (fifo, folder, zero, null, obj_fifo, obj_folder)]
    try:
        r = subprocess.run([sys.executable, "-c", SPECIAL_FILES_SCRIPT, *names], capture_output=True, text=True,
                           timeout=30, env=dict(os.environ))
    except subprocess.TimeoutExpired:
        pytest.fail("a load hung on a FIFO or a device")
    assert r.returncode == 0, r.stdout + r.stderr
    got = json.loads(r.stdout)
    assert len(got) == 8, got
    for name in names:
        for load in ("load_scene", "load") if not name.endswith(".json") else ("load_scene",):
            msg = got[f"{load} {name}"]
            want = "is a directory" if "folder" in name else "is not a regular file"
            assert msg.startswith(f"{name}: {want}"), f"{load}({name!r}): {msg}"


# --- the GIL -----------------------------------------------------------------------------------------


def test_gil_is_released_during_build_and_trace():
    """A second Python thread keeps running while one thread builds and traces."""
    rng = np.random.default_rng(3)
    spheres = np.c_[rng.uniform(-1, 1, (20000, 3)), rng.uniform(0.001, 0.01, 20000)]
    o = rng.uniform(-2, 2, (1500, 3))
    d = -o + rng.uniform(-0.1, 0.1, (1500, 3))
    # slow on purpose: 20,000 spheres per ray
    assert_gil_released(lambda: simdbvh.Scene(spheres=spheres, method="brute").intersect(o, d))


def test_a_mesh_file_is_one_geometry_and_references_are_stable(tmp_path):
    import gc
    import sys
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    s = simdbvh.load_scene(str(tmp_path / "tri.obj"), method="bvh4")
    assert (s.num_geometries, s.num_instances, s.num_planes) == (1, 1, 0)
    o = np.tile([0.25, 0.5, 2.0], (500, 1))
    d = np.tile([0.0, 0.0, -1.0], (500, 1))
    refs = (sys.getrefcount(o), sys.getrefcount(d), sys.getrefcount(s))
    for _ in range(200):
        h = s.intersect(o, d, normals=True)
        s.occluded(o, d)
    assert h["t"][0] == 2.0 and h["u"][0] == 0.25 and h["v"][0] == 0.5
    del h
    gc.collect()
    assert (sys.getrefcount(o), sys.getrefcount(d), sys.getrefcount(s)) == refs
