#!/usr/bin/python3
"""Point queries side by side: simdbvh (CLI) against Open3D's RaycastingScene.

Same mesh, same points (simdbvh gen-points: uniform in the bounds grown by 10%),
in one run: inside/outside (simdbvh inside --rule parity, the rule Open3D and
CGAL use; tests/compare checks simdbvh against CGAL), signed distance and the
closest point. Timings are medians of --reps runs after an untimed warm-up:
simdbvh's "query" time printed by the CLI (the library call, without loading
and building), Open3D's query calls (its scene is built once, untimed). Prints a
markdown table and writes JSON.

    /usr/bin/python3 scripts/compare_points.py --scene dragon --count 200000

Debian 12: python3-open3d, python3-numpy (scripts/setup.sh installs them). Open3D runs with
scripts/open3d/embree_mask_shim.c preloaded: without it Debian's build misses every ray, so its
occupancy is 0 everywhere and its signed distances are all positive (docs/open3d.md).
"""
import argparse
import gzip
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from fractions import Fraction

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "open3d"))
from shim import preload_env  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = {"dragon": "dragon_vrip.ply.gz", "dragon-res2": "dragon_vrip_res2.ply.gz",
          "dragon-res3": "dragon_vrip_res3.ply.gz", "dragon-res4": "dragon_vrip_res4.ply.gz",
          "bunny": "bunny.ply", "teapot": "teapot.ply"}


def cache_dir():
    """The scene cache, by the rule of scripts/fetch_scenes.sh and the library's workloads::cache_dir()."""
    if os.environ.get("SIMDBVH_CACHE"):
        return os.environ["SIMDBVH_CACHE"]
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    base = xdg if xdg.startswith("/") else os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "simdbvh", "scenes")


def mesh_path(scene, tmp):
    path = os.path.join(cache_dir(), SCENES[scene]) if scene in SCENES else scene
    if not os.path.isfile(path):
        sys.exit(f"compare_points: {path}: not found (run scripts/fetch_scenes.sh)")
    if path.endswith(".gz"):
        plain = os.path.join(tmp, os.path.basename(path)[:-3])
        with gzip.open(path, "rb") as src, open(plain, "wb") as dst:
            shutil.copyfileobj(src, dst)
        return plain
    return path


def run_cli(cli, args):
    r = subprocess.run([cli] + args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"compare_points: simdbvh {' '.join(args)} failed:\n{r.stdout}{r.stderr}")
    return r.stdout


def cli_query_ms(out):
    m = re.search(r"query ([0-9.e+-]+) ms", out)
    return float(m.group(1))


def timed(fn, reps):
    fn()  # warm-up
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        result = fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times), result


def o3d_worker(argv):
    """Child process: one Open3D query, so that an abort (Debian's 0.16 build
    asserts in Eigen on some meshes) is reported instead of ending the run."""
    query, threads, reps, ply, pts_file, out = argv
    mesh = o3d.io.read_triangle_mesh(ply)
    verts = np.asarray(mesh.vertices, dtype=np.float32)
    tris = np.asarray(mesh.triangles, dtype=np.uint32)
    scene = o3d.t.geometry.RaycastingScene(nthreads=int(threads))
    scene.add_triangles(o3d.core.Tensor(verts), o3d.core.Tensor(tris))
    q = o3d.core.Tensor(np.fromfile(pts_file, dtype="<f4").reshape(-1, 3))
    fns = {"inside": lambda: {"occupancy": scene.compute_occupancy(q).numpy()},
           "signed distance": lambda: {"sd": scene.compute_signed_distance(q).numpy()},
           "closest point": lambda: {k: v.numpy() for k, v in scene.compute_closest_points(q).items()}}
    ms, res = timed(fns[query], int(reps))
    np.savez(out, ms=ms, **res)


def o3d_screen(argv):
    """Child process: the indices of the points on which Open3D's closest-point
    query aborts the process (Debian's 0.16 asserts in Eigen's
    AlignedVector3::squaredNorm on a few points of the dragon). The scene is built
    once with one thread; each range of points runs in a fork()ed child, and a
    range whose child dies is halved until single points remain. Writes the
    indices, one per line."""
    ply, pts_file, out = argv
    mesh = o3d.io.read_triangle_mesh(ply)
    scene = o3d.t.geometry.RaycastingScene(nthreads=1)
    scene.add_triangles(o3d.core.Tensor(np.asarray(mesh.vertices, dtype=np.float32)),
                        o3d.core.Tensor(np.asarray(mesh.triangles, dtype=np.uint32)))
    pts = np.fromfile(pts_file, dtype="<f4").reshape(-1, 3)
    # Commit the scene here (the first query builds Embree's tree, with threads): a
    # child that had to build it would wait for threads fork() does not copy.
    scene.compute_closest_points(o3d.core.Tensor(np.zeros((1, 3), dtype=np.float32)))

    def dies(lo, hi):
        pid = os.fork()
        if pid == 0:
            os.close(2)  # the assertion's message, once per bisection step
            q = o3d.core.Tensor(np.ascontiguousarray(pts[lo:hi]))
            scene.compute_closest_points(q)
            scene.compute_signed_distance(q)
            os._exit(0)
        _, status = os.waitpid(pid, 0)
        return status != 0

    def bad(lo, hi):
        if not dies(lo, hi):
            return []
        if hi - lo == 1:
            return [lo]
        mid = (lo + hi) // 2
        return bad(lo, mid) + bad(mid, hi)

    found = []
    for lo in range(0, len(pts), 4096):
        found += bad(lo, min(lo + 4096, len(pts)))
    with open(out, "w") as f:
        f.write("".join(f"{i}\n" for i in found))


def screen_o3d(ply, pts_file, tmp, env):
    out = os.path.join(tmp, "o3d_bad.txt")
    # One OpenMP thread: libgomp's pool does not survive fork(), and Open3D's tensor
    # copies run in OpenMP regions.
    r = subprocess.run([sys.executable, os.path.abspath(__file__), "--o3d-screen", ply, pts_file, out],
                       capture_output=True, text=True, env=dict(env, OMP_NUM_THREADS="1"))
    if r.returncode != 0 or not os.path.exists(out):
        sys.exit(f"compare_points: screening Open3D's aborts failed (exit {r.returncode}):\n{r.stderr[-2000:]}")
    with open(out) as f:
        return [int(line) for line in f if line.strip()]


def exact_parity(a, b, c, lo, hi, p, axis, sign):
    """Crossings of the ray p + s * sign * e_axis (s > 0) with the triangles (vertex
    arrays a, b, c and their boxes lo, hi), in exact rational arithmetic (every
    float is a fraction): (count, degenerate), where degenerate counts a ray
    through an edge, a vertex or the point itself on a triangle. An independent
    referee for points where the libraries disagree."""
    u, v = (axis + 1) % 3, (axis + 2) % 3
    cand = (lo[:, u] <= p[u]) & (hi[:, u] >= p[u]) & (lo[:, v] <= p[v]) & (hi[:, v] >= p[v])
    cand &= (hi[:, axis] >= p[axis]) if sign > 0 else (lo[:, axis] <= p[axis])
    P = [Fraction(float(x)) for x in p]
    count = degenerate = 0
    for i in np.nonzero(cand)[0]:
        A, B, C = ([Fraction(float(x)) for x in t[i]] for t in (a, b, c))

        def edge(q, r):
            return (r[u] - q[u]) * (P[v] - q[v]) - (r[v] - q[v]) * (P[u] - q[u])
        w = (edge(A, B), edge(B, C), edge(C, A))
        if all(x > 0 for x in w) or all(x < 0 for x in w):
            z = (w[1] * A[axis] + w[2] * B[axis] + w[0] * C[axis]) / sum(w)
            if z == P[axis]:
                degenerate += 1
            elif (z > P[axis]) == (sign > 0):
                count += 1
        elif all(x >= 0 for x in w) or all(x <= 0 for x in w):
            degenerate += 1
    return count, degenerate


def referee_inside(verts, tris, pts, idx, limit=50):
    """For up to `limit` points: 1 inside, 0 outside by exact parity along +z, -z, +x
    and -y when all four agree and none is degenerate, else None."""
    a, b, c = (verts[tris[:, k]].astype(np.float64) for k in range(3))
    lo, hi = np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)
    out = {}
    for k in idx[:limit]:
        res = [exact_parity(a, b, c, lo, hi, pts[k], ax, sg) for ax, sg in ((2, 1), (2, -1), (0, 1), (1, -1))]
        odd = {n % 2 for n, _ in res}
        out[int(k)] = odd.pop() if len(odd) == 1 and all(d == 0 for _, d in res) else None
    return out


def run_o3d(query, threads, reps, ply, pts_file, tmp, env):
    out = os.path.join(tmp, "o3d.npz")
    if os.path.exists(out):
        os.remove(out)
    r = subprocess.run([sys.executable, os.path.abspath(__file__), "--o3d-worker", query, str(threads), str(reps),
                        ply, pts_file, out], capture_output=True, text=True, env=env)
    if r.returncode != 0 or not os.path.exists(out):
        last = (r.stderr.strip().splitlines() or ["exit status %d" % r.returncode])[-1]
        return None, f"crashed (exit {r.returncode}): {last[:160]}"
    data = np.load(out)
    return float(data["ms"]), {k: data[k] for k in data.files if k != "ms"}


# query: (simdbvh command and options, tree, output file); the tree is each
# command's default, named so that the rows say what ran.
QUERIES = {"inside": (["inside", "--rule", "parity"], "bvh8", "s.bin"),
           "signed distance": (["distance", "--rule", "parity"], "bvh4", "d.bin"),
           "closest point": (["distance", "--unsigned"], "bvh4", "u.bin")}


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--o3d-worker":
        return o3d_worker(sys.argv[2:])
    if len(sys.argv) > 1 and sys.argv[1] == "--o3d-screen":
        return o3d_screen(sys.argv[2:])
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="dragon")
    ap.add_argument("--count", type=int, default=200000)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, os.cpu_count() or 1])
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "release", "simdbvh"))
    ap.add_argument("--json", default=os.path.join(ROOT, "out", "points_compare.json"))
    ap.add_argument("--queries", nargs="+", default=list(QUERIES), choices=list(QUERIES),
                    help="which queries to run (default: all three)")
    ap.add_argument("--no-screen", action="store_true",
                    help="keep the points on which Open3D aborts (its closest-point rows then fail)")
    a = ap.parse_args()
    if a.reps < 1 or a.count < 1:
        sys.exit("compare_points: --reps and --count must be >= 1")
    tmp = tempfile.mkdtemp(prefix="simdbvh_points_")
    try:
        ply = mesh_path(a.scene, tmp)
        pts_file = os.path.join(tmp, "p.bin")
        run_cli(a.cli, ["gen-points", "--scene", a.scene, "--count", str(a.count), "--out", pts_file])
        pts = np.fromfile(pts_file, dtype="<f4").reshape(-1, 3)
        generated = len(pts)
        env = preload_env(tmp)  # Debian's Open3D misses every ray without it (docs/open3d.md)
        screen = not a.no_screen and set(a.queries) & {"signed distance", "closest point"}
        excluded = screen_o3d(ply, pts_file, tmp, env) if screen else []
        if excluded:  # both libraries get the same, screened points
            pts = np.delete(pts, excluded, axis=0)
            pts.astype("<f4").tofile(pts_file)

        rows = []
        ours = {}
        for t in a.threads:
            for query, (args, tree, out) in QUERIES.items():
                if query not in a.queries:
                    continue
                path = os.path.join(tmp, out)
                cmd = args[:1] + ["--scene", a.scene, "--points", pts_file, "--out", path,
                                  "--threads", str(t), "--tree", tree] + args[1:]
                run_cli(a.cli, cmd)  # warm-up (page cache, first touch)
                ms = statistics.median(cli_query_ms(run_cli(a.cli, cmd)) for _ in range(a.reps))
                rows.append({"method": "simdbvh " + tree, "query": query, "threads": t, "ms": ms,
                             "points_per_s": len(pts) / ms * 1e3})
                ours[query] = path
        rec_t = np.dtype([("d", "<f4"), ("prim", "<u4"), ("p", "<f4", 3)])
        sides = np.fromfile(ours["inside"], dtype=np.uint8) if "inside" in ours else None
        rec = np.fromfile(ours["signed distance"], dtype=rec_t) if "signed distance" in ours else None
        urec = np.fromfile(ours["closest point"], dtype=rec_t) if "closest point" in ours else None

        mesh = o3d.io.read_triangle_mesh(ply)
        verts = np.asarray(mesh.vertices, dtype=np.float32)
        tris = np.asarray(mesh.triangles, dtype=np.uint32)
        o3d_results, failures = {}, {}
        for t in a.threads:
            for query in a.queries:
                ms, res = run_o3d(query, t, a.reps, ply, pts_file, tmp, env)
                if ms is None:
                    failures[query] = res
                    rows.append({"method": "open3d RaycastingScene", "query": query, "threads": t, "failed": res})
                    continue
                rows.append({"method": "open3d RaycastingScene", "query": query, "threads": t, "ms": ms,
                             "points_per_s": len(pts) / ms * 1e3})
                o3d_results[query] = res

        # points exactly on the surface are not inside/outside questions
        off = sides != 2 if sides is not None else rec["d"] != 0 if rec is not None else np.ones(len(pts), bool)
        summary = {"scene": a.scene, "points": int(len(pts)), "triangles": int(len(tris)),
                   "generated_points": generated, "excluded_open3d_aborts": excluded,
                   "open3d_version": o3d.__version__, "surface_points": int(np.sum(~off)),
                   "simdbvh_inside": None if sides is None else int(np.sum(sides == 1)), "open3d_failures": failures, "rows": rows}
        lines = []
        if "inside" in o3d_results:
            occ = o3d_results["inside"]["occupancy"].astype(np.uint8)
            summary["open3d_wrong_inside"] = int(np.sum((occ != sides) & off))
            summary["open3d_inside"] = int(np.sum(occ == 1))
            lines.append(f"inside/outside: Open3D differs on {summary['open3d_wrong_inside']} of {len(pts)} points "
                         f"(Open3D says {summary['open3d_inside']} inside, simdbvh {summary['simdbvh_inside']})")
            differ = np.nonzero((occ != sides) & off)[0]
            if len(differ):
                verdict = referee_inside(verts, tris, pts, differ)
                summary["referee"] = {str(k): v for k, v in verdict.items()}
                right = {"simdbvh": int(sum(v == sides[k] for k, v in verdict.items())),
                         "Open3D": int(sum(v == occ[k] for k, v in verdict.items())),
                         "undecided": int(sum(v is None for v in verdict.values()))}
                summary["referee_right"] = right
                lines.append(f"  exact parity (rational arithmetic, rays along +z, -z, +x, -y) on {len(verdict)} of "
                             f"them: simdbvh right on {right['simdbvh']}, Open3D on {right['Open3D']}, "
                             f"undecided {right['undecided']}")
        if "signed distance" in o3d_results:
            sd = o3d_results["signed distance"]["sd"]
            summary["open3d_wrong_sign"] = int(np.sum((np.sign(sd) != np.sign(rec["d"])) & off & (rec["d"] != 0)))
            lines.append(f"signed distance: Open3D's sign differs on {summary['open3d_wrong_sign']} points")
        if "closest point" in o3d_results:
            cp = o3d_results["closest point"]
            o3d_d = np.linalg.norm(cp["points"].astype(np.float64) - pts.astype(np.float64), axis=1)
            diff = np.abs(o3d_d - urec["d"].astype(np.float64))
            other = cp["primitive_ids"].astype(np.uint32) != urec["prim"]
            # A tie: another triangle at the same distance within float rounding (the
            # closest feature is a shared vertex or edge; simdbvh gives it to the lower id).
            # Open3D computes in float: its distance carries rounding on the scale of the
            # coordinates, so a tie is the same distance to within 4 ulps of them.
            tol = 4 * np.finfo(np.float32).eps * np.maximum(np.abs(pts).max(axis=1), o3d_d)
            summary["max_distance_difference"] = float(diff.max())
            summary["open3d_other_closest_triangle"] = int(np.sum(other))
            summary["open3d_other_triangle_farther"] = int(np.sum(other & (diff > tol)))
            lines.append(f"closest point: max distance difference {diff.max():.3g}; Open3D names another triangle "
                         f"on {summary['open3d_other_closest_triangle']} points, "
                         f"{summary['open3d_other_closest_triangle'] - summary['open3d_other_triangle_farther']} "
                         f"of them at the same distance to within float rounding (mostly a shared vertex or edge: a tie, "
                         f"which simdbvh gives to the lower id), {summary['open3d_other_triangle_farther']} farther")
        for q, why in failures.items():
            lines.append(f"Open3D {q}: {why}")
        os.makedirs(os.path.dirname(a.json), exist_ok=True)
        with open(a.json, "w") as f:
            json.dump(summary, f, indent=1)

        print(f"scene {a.scene}: {len(tris)} triangles, {len(pts)} points uniform in the bounds (+10%), "
              f"Open3D {o3d.__version__}; simdbvh agrees with CGAL (tests/compare)")
        if screen:
            print(f"left out: {len(excluded)} of {generated} points on which Open3D's closest point or signed "
                  f"distance aborts the process (indices in the JSON)")
        for line in lines:
            print(line)
        print("\n| query | threads | simdbvh points/s | Open3D points/s | ratio |\n|---|---:|---:|---:|---:|")
        for t in a.threads:
            for query in a.queries:
                s_row = next(r for r in rows if r["method"].startswith("simdbvh") and r["query"] == query and r["threads"] == t)
                o_row = next(r for r in rows if r["method"].startswith("open3d") and r["query"] == query and r["threads"] == t)
                o_rate = o_row.get("points_per_s")
                print(f"| {query} | {t} | {s_row['points_per_s']:,.0f} | "
                      + (f"{o_rate:,.0f} | {s_row['points_per_s'] / o_rate:.2f}x |" if o_rate else "crashed | - |"))
        print(f"\nwrote {a.json}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
