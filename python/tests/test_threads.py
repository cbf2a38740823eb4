"""One BVH shared by Python threads: a refit and the queries are serialised by the object (queries share it, a refit
has it alone), so each query answers for the vertices before or after a refit, bit for bit, never a mix; queries
still run side by side."""
import threading
import time

import numpy as np
import pytest

import simdbvh
from test_simdbvh import sphere_mesh


def same(a, b):
    """Bit equality of every array of two result dicts (or of two arrays)."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("method,n", [("bvh8", 20000), ("bvh4", 20000), ("bvh2", 20000), ("brute", 300)])
def test_refit_is_serialised_with_queries_on_other_threads(method, n):
    """One thread refits between a sphere and an ellipsoid while two others query: every answer is the
    single-threaded answer for one of the two meshes (before, the GIL was released and nothing serialised them:
    answers matched neither mesh)."""
    mesh = sphere_mesh(24)
    va = mesh.vertices
    vb = (va * np.array([1.5, 0.5, 1.0]) + np.array([0.2, 0.0, -0.1])).astype(np.float32)
    rng = np.random.default_rng(9)
    o = rng.uniform(-2, 2, (n, 3)).astype(np.float32)
    d = (rng.uniform(-1, 1, (n, 3)) - 0.3 * o).astype(np.float32)
    p = rng.uniform(-1.6, 1.6, (n // 4, 3)).astype(np.float32)
    queries = {
        "intersect": lambda b, t=1: b.intersect(o, d, points=True, normals=True, threads=t),
        "occluded": lambda b, t=1: b.occluded(o, d, tmax=1.0, threads=t),
        "signed_distance": lambda b, t=1: b.signed_distance(p, threads=t),
        "closest_point": lambda b, t=1: b.closest_point(p, threads=t),
        "count_crossings": lambda b, t=1: b.count_crossings(o[: n // 4], d[: n // 4], threads=t),
    }
    want = {}
    for label, v in (("a", va), ("b", vb)):
        ref = simdbvh.BVH(simdbvh.Mesh(v, mesh.faces), method=method)
        want[label] = {q: f(ref) for q, f in queries.items()}
    for q in queries:
        assert not same(want["a"][q], want["b"][q]), q  # the two meshes answer differently

    bvh = simdbvh.BVH(simdbvh.Mesh(va, mesh.faces), method=method)
    stop = threading.Event()
    refits = []
    seen = {"a": 0, "b": 0}
    bad = []

    def refitter():
        while not stop.is_set():  # each mesh kept a moment, for queries to see both
            bvh.refit(vb)
            time.sleep(0.002)
            bvh.refit(va, threads=2)
            time.sleep(0.002)
            refits.append(2)

    def querier(seed, threads):
        names = list(queries)
        order = np.random.default_rng(seed).integers(0, len(names), 24)
        for k in order:
            q = names[k]
            got = queries[q](bvh, threads)
            for label in ("a", "b"):
                if same(got, want[label][q]):
                    seen[label] += 1
                    break
            else:
                bad.append(q)

    r = threading.Thread(target=refitter)
    qs = [threading.Thread(target=querier, args=(s, t)) for s, t in ((1, 1), (2, 2))]
    r.start()
    for t in qs:
        t.start()
    for t in qs:
        t.join()
    stop.set()
    r.join()
    assert not bad, f"{len(bad)} of 48 answers match neither mesh: {sorted(set(bad))}"
    assert len(refits) >= 4 and seen["a"] and seen["b"], (len(refits), seen)  # they did interleave


def test_queries_on_one_bvh_still_run_side_by_side():
    """While a long query holds the BVH (shared), a short one from another thread finishes first: queries are
    not serialised among themselves."""
    mesh = sphere_mesh(64)
    bvh = simdbvh.BVH(mesh, method="brute")  # slow on purpose: ~16k triangles per ray
    rng = np.random.default_rng(3)
    o = rng.uniform(-2, 2, (3000, 3))
    d = -o + rng.uniform(-0.1, 0.1, (3000, 3))
    order = []

    def long_query():
        bvh.intersect(o, d)
        order.append("long")

    t = threading.Thread(target=long_query)
    start = time.perf_counter()
    t.start()
    time.sleep(0.05)
    assert bvh.contains([[0.0, 0.0, 0.0]])[0]
    order.append("short")
    t.join()
    assert time.perf_counter() - start > 0.2, "the long query must take a while for this test to mean anything"
    assert order == ["short", "long"]
