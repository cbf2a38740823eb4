"""Saved BVHs: BVH.save / simdbvh.load_bvh and pickling give a BVH whose hits
are bit-identical to the one saved (every method with a tree), and bad files
raise simdbvh.Error naming the file."""
import os
import pickle

import numpy as np
import pytest

import simdbvh
from test_simdbvh import sphere_mesh


def rays(n=5000, seed=3):
    rng = np.random.default_rng(seed)
    o = rng.uniform(-2, 2, (n, 3)).astype(np.float32)
    d = (rng.uniform(-1, 1, (n, 3)) - o * 0.3).astype(np.float32)
    return o, d


def same_hits(a, b):
    o, d = rays()
    ha, hb = a.intersect(o, d), b.intersect(o, d)
    assert ha["hit"].sum() > 100  # the rays do hit the sphere
    for k in ("hit", "prim"):
        np.testing.assert_array_equal(ha[k], hb[k])
    for k in ("t", "u", "v"):  # bit for bit (NaN-free: misses are inf / 0)
        np.testing.assert_array_equal(ha[k].view(np.uint32), hb[k].view(np.uint32))
    np.testing.assert_array_equal(a.occluded(o, d), b.occluded(o, d))


@pytest.mark.parametrize("method", ["bvh2", "bvh4", "bvh8", "bvh16"])
def test_save_load_bit_identical(tmp_path, method):
    built = simdbvh.BVH(sphere_mesh(), method)
    path = str(tmp_path / "s.simdbvh")
    built.save(path)
    loaded = simdbvh.load_bvh(path)
    assert loaded.method == method
    same_hits(built, loaded)
    same_hits(built, simdbvh.load_bvh(path, verify=False))
    # The point queries run on the mesh from the file.
    p = np.random.default_rng(1).uniform(-2, 2, (200, 3)).astype(np.float32)
    a, b = loaded.closest_point(p), built.closest_point(p)
    np.testing.assert_array_equal(a["prim"], b["prim"])
    np.testing.assert_array_equal(a["distance"].view(np.uint32), b["distance"].view(np.uint32))
    np.testing.assert_array_equal(loaded.contains(p), built.contains(p))


@pytest.mark.parametrize("method", ["bvh2", "bvh8"])
def test_pickle_round_trip(method):
    built = simdbvh.BVH(sphere_mesh(), method, isa="scalar")
    again = pickle.loads(pickle.dumps(built))
    assert again.method == method and again.isa == "scalar"
    same_hits(built, again)


def test_mesh_pickles():
    m = sphere_mesh()
    m2 = pickle.loads(pickle.dumps(m))
    np.testing.assert_array_equal(m2.vertices, m.vertices)
    np.testing.assert_array_equal(m2.faces, m.faces)


def test_brute_has_nothing_to_save(tmp_path):
    with pytest.raises(simdbvh.Error, match="no tree to save"):
        simdbvh.BVH(sphere_mesh(), "brute").save(str(tmp_path / "b.simdbvh"))
    assert not os.listdir(tmp_path)


def test_bad_files_raise_naming_the_file(tmp_path):
    path = tmp_path / "s.simdbvh"
    simdbvh.BVH(sphere_mesh()).save(str(path))
    data = path.read_bytes()
    bad = tmp_path / "bad.simdbvh"
    bad.write_bytes(data[: len(data) // 2])
    with pytest.raises(simdbvh.Error, match=r"bad\.simdbvh: truncated"):
        simdbvh.load_bvh(str(bad))
    flipped = bytearray(data)
    flipped[len(data) - 100] ^= 4
    bad.write_bytes(bytes(flipped))
    with pytest.raises(simdbvh.Error, match=r"bad\.simdbvh: checksum mismatch"):
        simdbvh.load_bvh(str(bad))
    bad.write_bytes(b"ply\nformat ascii 1.0\n")
    with pytest.raises(simdbvh.Error, match="wrong magic"):
        simdbvh.load_bvh(str(bad))
    state = simdbvh.BVH(sphere_mesh()).__getstate__()
    damaged = bytearray(state[0])
    damaged[-1] ^= 1
    with pytest.raises(simdbvh.Error, match="pickled BVH: checksum mismatch"):
        simdbvh.BVH.__new__(simdbvh.BVH).__setstate__((bytes(damaged), None))
