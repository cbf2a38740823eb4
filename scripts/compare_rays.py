#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Rays side by side: the simdbvh Python module against Open3D's RaycastingScene.

Same mesh (the float32 vertices and faces simdbvh loaded), same rays
(`simdbvh gen-rays`: primary, incoherent, diffuse), one process per library.
Each library is timed on its query call only (scene built once, untimed; the
builds are reported apart as medians of 3), medians of --reps calls after an
untimed warm-up, one thread and all cores. Hits are compared ray by ray
against simdbvh's: identical (both miss, or the same triangle at the same t),
the same triangle with t rounded apart (Embree's arithmetic is not ours),
a tie (the same t on another triangle), another triangle nearer or farther,
or a miss on one side only. simdbvh's answers are bit-identical to its brute
force and classified against the double-precision reference in `simdbvh
accuracy`; this table says where Open3D differs from them, not who is right.

Open3D runs with scripts/open3d/embree_mask_shim.c preloaded: Debian 12's
python3-open3d 0.16.1 sets ray.mask = 0 and Debian's libembree3 honours masks,
so without the shim every ray misses (docs/open3d.md). The shim sets the mask
to all ones before Embree's call and changes nothing else.

    /usr/bin/python3 scripts/compare_rays.py --scene dragon --count 1000000

Writes DIR/compare_rays.json and, with --chart, a bar chart (matplotlib).
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KINDS = ("primary", "incoherent", "diffuse")


def median_call(fn, reps):
    fn()  # untimed warm-up
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def read_rays(path):
    r = np.fromfile(path, dtype="<f4").reshape(-1, 8)  # ox oy oz tmin dx dy dz tmax
    return r[:, 0:3].copy(), r[:, 4:7].copy(), r[:, 3].copy(), r[:, 7].copy()


def machine():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip() + f", {os.cpu_count()} CPUs"
    except OSError:
        pass
    return platform.processor()


def open3d_worker(args):
    """Runs in a child process with the shim preloaded: Open3D's hits and times."""
    import open3d as o3d

    data = np.load(args.worker)
    verts, faces = data["vertices"], data["faces"].astype(np.uint32)
    builds = []
    for _ in range(3):
        t0 = time.perf_counter()
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(verts), o3d.core.Tensor(faces))
        scene.cast_rays(o3d.core.Tensor(np.zeros((1, 6), np.float32)))  # the scene commits (builds) here
        builds.append(time.perf_counter() - t0)
    out = {"version": o3d.__version__, "build_ms": statistics.median(builds) * 1e3, "kinds": {}}
    for kind in KINDS:
        rays = o3d.core.Tensor(np.ascontiguousarray(data[kind]))
        res = {}
        for threads in args.threads:
            res[str(threads)] = median_call(lambda: scene.cast_rays(rays, nthreads=threads), args.reps)
        ans = scene.cast_rays(rays, nthreads=0)
        np.save(os.path.join(args.tmp, f"o3d_{kind}_t.npy"), ans["t_hit"].numpy())
        np.save(os.path.join(args.tmp, f"o3d_{kind}_prim.npy"), ans["primitive_ids"].numpy().astype(np.int64))
        out["kinds"][kind] = res
    json.dump(out, sys.stdout)


def classify(t_ours, prim_ours, t_o3d, prim_o3d):
    hit_a, hit_b = prim_ours >= 0, prim_o3d != 0xFFFFFFFF
    prim_b = np.where(hit_b, prim_o3d, -1)
    both = hit_a & hit_b
    same_t = both & (t_ours == t_o3d)
    same_prim = both & (prim_ours == prim_b)
    return {
        "identical": int(((~hit_a) & (~hit_b)).sum() + (same_t & same_prim).sum()),
        "same triangle, t rounded apart": int((same_prim & ~same_t).sum()),
        "tie (same t, other triangle)": int((same_t & ~same_prim).sum()),
        "other triangle, nearer for Open3D": int((both & ~same_prim & (t_o3d < t_ours)).sum()),
        "other triangle, farther for Open3D": int((both & ~same_prim & (t_o3d > t_ours)).sum()),
        "Open3D misses, simdbvh hits": int((hit_a & ~hit_b).sum()),
        "Open3D hits, simdbvh misses": int((~hit_a & hit_b).sum()),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="dragon")
    ap.add_argument("--count", type=int, default=1000000)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, os.cpu_count() or 1])
    ap.add_argument("--out", default=os.path.join(ROOT, "out"))
    ap.add_argument("--chart", default=None, help="PNG path for the chart")
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "release", "simdbvh"))
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--tmp", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return open3d_worker(args)

    sys.path.insert(0, os.path.join(ROOT, "build", "release", "python"))
    import simdbvh

    mesh = simdbvh.load(args.scene)
    with tempfile.TemporaryDirectory() as tmp:
        arrays = {"vertices": np.ascontiguousarray(mesh.vertices, np.float32), "faces": np.asarray(mesh.faces)}
        ours = {}
        builds = []
        for _ in range(3):
            t0 = time.perf_counter()
            bvh = simdbvh.BVH(mesh, method="bvh8")
            builds.append(time.perf_counter() - t0)
        for kind in KINDS:
            path = os.path.join(tmp, kind + ".bin")
            subprocess.run([args.cli, "gen-rays", "--scene", args.scene, "--kind", kind, "--count", str(args.count),
                            "--out", path], check=True, capture_output=True)
            o, d, tmin, tmax = read_rays(path)
            if not (np.all(tmin == 0) and np.all(np.isinf(tmax))):
                sys.exit("compare_rays: Open3D's rays are [0, inf): the generated rays must be too")
            arrays[kind] = np.hstack([o, d]).astype(np.float32)
            res = {}
            for threads in args.threads:
                res[str(threads)] = median_call(lambda: bvh.intersect(o, d, threads=threads), args.reps)
            h = bvh.intersect(o, d, threads=args.threads[-1])
            ours[kind] = (res, h["t"], h["prim"].astype(np.int64))
        np.savez(os.path.join(tmp, "input.npz"), **arrays)
        sys.path.insert(0, os.path.join(ROOT, "scripts", "open3d"))
        from shim import preload_env
        env = preload_env(tmp)
        r = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", os.path.join(tmp, "input.npz"),
                            "--tmp", tmp, "--reps", str(args.reps), "--threads", *map(str, args.threads)],
                           env=env, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"compare_rays: the Open3D worker failed (exit {r.returncode}):\n{r.stderr[-2000:]}")
        o3d = json.loads(r.stdout)
        report = {"scene": args.scene, "triangles": len(mesh), "rays": args.count, "reps": args.reps,
                  "machine": machine(), "load_average": os.getloadavg(), "open3d_version": o3d["version"],
                  "command": " ".join([os.path.relpath(sys.argv[0], ROOT)] + sys.argv[1:]),
                  "build_ms": {"simdbvh bvh8": statistics.median(builds) * 1e3, "open3d": o3d["build_ms"]},
                  "rows": []}
        for kind in KINDS:
            res, t_ours, prim_ours = ours[kind]
            t_o3d = np.load(os.path.join(tmp, f"o3d_{kind}_t.npy"))
            prim_o3d = np.load(os.path.join(tmp, f"o3d_{kind}_prim.npy"))
            row = {"kind": kind, "hits": classify(t_ours, prim_ours, t_o3d, prim_o3d)}
            for threads in args.threads:
                a, b = res[str(threads)], o3d["kinds"][kind][str(threads)]
                row[f"t{threads}"] = {"simdbvh_mrays_s": args.count / a / 1e6, "open3d_mrays_s": args.count / b / 1e6,
                                      "ratio": b / a}
            report["rows"].append(row)

    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "compare_rays.json"), "w") as f:
        json.dump(report, f, indent=1)
    print(f"{args.scene} ({len(mesh)} triangles), {args.count} rays per kind, medians of {args.reps} after a warm-up;"
          f" {report['machine']}; Open3D {o3d['version']} with the mask shim")
    print(f"build (median of 3): simdbvh bvh8 {report['build_ms']['simdbvh bvh8']:.0f} ms,"
          f" Open3D {report['build_ms']['open3d']:.0f} ms")
    print("| rays | threads | simdbvh Mrays/s | Open3D Mrays/s | simdbvh / Open3D |")
    print("|---|---:|---:|---:|---:|")
    for row in report["rows"]:
        for threads in args.threads:
            c = row[f"t{threads}"]
            print(f"| {row['kind']} | {threads} | {c['simdbvh_mrays_s']:.2f} | {c['open3d_mrays_s']:.2f} | {c['ratio']:.2f} |")
    print("\n| rays | " + " | ".join(report["rows"][0]["hits"]) + " |")
    print("|---|" + "---:|" * len(report["rows"][0]["hits"]))
    for row in report["rows"]:
        print(f"| {row['kind']} | " + " | ".join(str(v) for v in row["hits"].values()) + " |")
    if args.chart:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        labels, ours_v, o3d_v = [], [], []
        for row in report["rows"]:
            for threads in args.threads:
                labels.append(f"{row['kind']}\n{threads} thread{'s' if threads > 1 else ''}")
                ours_v.append(row[f"t{threads}"]["simdbvh_mrays_s"])
                o3d_v.append(row[f"t{threads}"]["open3d_mrays_s"])
        x = np.arange(len(labels))
        fig, ax = plt.subplots(figsize=(9, 4))
        ax.bar(x - 0.2, ours_v, 0.4, label="simdbvh (Python, bvh8)")
        ax.bar(x + 0.2, o3d_v, 0.4, label=f"Open3D {o3d['version']} RaycastingScene")
        ax.set_xticks(x, labels)
        ax.set_ylabel("Mrays/s")
        ax.set_title(f"{args.scene}, {args.count} rays per kind, closest hit ({report['machine']})", fontsize=9)
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.chart, dpi=110)
        print(f"wrote {args.chart}")


if __name__ == "__main__":
    main()
