#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Accuracy families side by side: simdbvh and Open3D's RaycastingScene against the exact reference.

Every case of the ray families (`simdbvh gen-rays --kind F`: rays through vertices and edges of closed
meshes, growing offsets, axis-aligned rays, rays starting on the surface, grazing rays, needle triangles,
degenerate triangles, tiny and huge directions, random rays) is given to both libraries on the same float32
mesh, and each library's closest hits are classified ray by ray by `simdbvh classify` against the
double-precision reference, with the labels of `simdbvh accuracy` (docs/accuracy.md): agree, tie (another
triangle of the tie-set), leak (the reference hits, the library misses), false_hit, wrong_triangle, t_error;
`marginal` counts the disagreements within float rounding of the reference.

Open3D's cast_rays has no tmin or tmax (it always traces [0, inf)), so every ray is traced on [0, inf) by
every library here; the families' own intervals are used by `simdbvh accuracy`, not here. Open3D runs in a
child process with scripts/open3d/embree_mask_shim.c preloaded (docs/open3d.md: without it, Debian 12's
Open3D misses every ray). A third row, Embree 3 called directly by the simdbvh CLI (`trace --method embree
--robust`: rtcIntersect1 with RTC_SCENE_FLAG_ROBUST, as Open3D sets it), separates Embree's arithmetic from
Open3D's wrapping.

    /usr/bin/python3 scripts/compare_accuracy_open3d.py --out out/o3d-accuracy \\
        --chart docs/python/open3d_accuracy.png

Writes DIR/compare_accuracy_open3d.json and DIR/compare_accuracy_open3d.md.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "open3d"))
sys.path.insert(0, os.path.join(ROOT, "build", "release", "python"))
from compare_rays import machine  # noqa: E402
from shim import preload_env  # noqa: E402  (scripts/open3d/shim.py)

FAMILIES = ("watertight", "offsets", "axis-aligned", "surface-start", "grazing", "needles", "degenerate",
            "direction-scale", "random")
LABELS = ("agree", "tie", "leak", "false_hit", "wrong_triangle", "t_error", "marginal")
LIBS = ("simdbvh", "open3d", "embree")
EMBREE_FLT_LARGE = np.float32(1.844e18)  # Embree's RayK::valid(): |org|, |dir| components at most this
HIT = np.dtype([("t", "<f4"), ("u", "<f4"), ("v", "<f4"), ("prim", "<u4")])


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"compare_accuracy_open3d: {' '.join(cmd)} failed:\n{r.stdout}{r.stderr}")
    return r.stdout


def cases_of(cli, family, quick, tmp):
    """The family's case names (gen-rays prints them after writing its first case)."""
    out = run([cli, "gen-rays", "--kind", family, "--mesh-out", os.path.join(tmp, "probe.ply"),
               "--out", os.path.join(tmp, "probe.rays")] + (["--quick"] if quick else []))
    for line in out.splitlines():
        if line.startswith("cases:"):
            return [c.strip() for c in line.split(":", 1)[1].split(",")]
    sys.exit(f"compare_accuracy_open3d: gen-rays --kind {family} listed no cases:\n{out}")


def open3d_worker(manifest):
    """Child process (shim preloaded): Open3D's closest hits for every case, written as simdbvh hit files."""
    import open3d as o3d
    import simdbvh

    for case in json.load(open(manifest)):
        mesh = simdbvh.load(case["mesh"])
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(np.ascontiguousarray(mesh.vertices, np.float32)),
                            o3d.core.Tensor(np.ascontiguousarray(mesh.faces, np.uint32)))
        r = np.fromfile(case["rays"], dtype="<f4").reshape(-1, 8)
        rays = np.ascontiguousarray(np.c_[r[:, 0:3], r[:, 4:7]], np.float32)
        ans = scene.cast_rays(o3d.core.Tensor(rays), nthreads=1)
        h = np.empty(len(rays), HIT)
        h["t"] = ans["t_hit"].numpy()
        uv = ans["primitive_uvs"].numpy()
        h["u"], h["v"] = uv[:, 0], uv[:, 1]
        h["prim"] = ans["primitive_ids"].numpy()
        miss = h["prim"] == 0xFFFFFFFF
        h["t"][miss], h["u"][miss], h["v"][miss] = np.inf, 0, 0
        h.tofile(case["hits"]["open3d"])
    print(o3d.__version__)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--quick", action="store_true", help="gen-rays --quick (fewer rays per case)")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1, help="for the reference (classify)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "o3d-accuracy"))
    ap.add_argument("--chart", default=None, help="PNG path for the chart")
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "release", "simdbvh"))
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return open3d_worker(args.worker)
    try:
        import simdbvh
    except ImportError:
        sys.exit("compare_accuracy_open3d: the simdbvh module is not importable (set PYTHONPATH=build/release/python)")
    probe = subprocess.run([sys.executable, "-c", "import open3d"], capture_output=True, text=True)
    if probe.returncode != 0:
        sys.exit("compare_accuracy_open3d: Open3D is not importable (Debian: apt-get install python3-open3d)")
    if not os.access(args.cli, os.X_OK):
        sys.exit(f"compare_accuracy_open3d: no simdbvh CLI at {args.cli} (build it, or pass --cli)")
    os.makedirs(args.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        cases = []
        for family in args.families.split(","):
            if family not in FAMILIES:
                sys.exit(f"compare_accuracy_open3d: unknown family '{family}' (one of {', '.join(FAMILIES)})")
            for name in cases_of(args.cli, family, args.quick, tmp):
                k = len(cases)
                c = {"family": family, "case": name, "mesh": os.path.join(tmp, f"{k}.ply"),
                     "rays": os.path.join(tmp, f"{k}.rays"),
                     "hits": {lib: os.path.join(tmp, f"{k}.{lib}.hits") for lib in LIBS}}
                run([args.cli, "gen-rays", "--kind", family, "--case", name, "--mesh-out", c["mesh"],
                     "--out", c["rays"]] + (["--quick"] if args.quick else []))
                # Every library traces [0, inf): Open3D has no tmin or tmax. Rays Embree rejects are left
                # out for all three (Debian's Embree is built with assertions: Open3D's process aborts on
                # them): a coordinate of the origin or the direction above FLT_LARGE (1.844e18) or NaN.
                r = np.fromfile(c["rays"], dtype="<f4").reshape(-1, 8)
                r[:, 3], r[:, 7] = 0.0, np.inf
                with np.errstate(invalid="ignore"):
                    ok = np.all(np.abs(np.c_[r[:, 0:3], r[:, 4:7]]) <= EMBREE_FLT_LARGE, axis=1)
                c["excluded"] = int((~ok).sum())
                r[ok].tofile(c["rays"])
                cases.append(c)
        for c in cases:  # simdbvh: the Python module (bvh8, the default ISA)
            mesh = simdbvh.load(c["mesh"])
            r = np.fromfile(c["rays"], dtype="<f4").reshape(-1, 8)
            got = simdbvh.BVH(mesh, method="bvh8").intersect(r[:, 0:3], r[:, 4:7])
            h = np.empty(len(r), HIT)
            h["t"], h["u"], h["v"] = got["t"], got["u"], got["v"]
            h["prim"] = np.where(got["prim"] < 0, 0xFFFFFFFF, got["prim"]).astype(np.uint32)
            h.tofile(c["hits"]["simdbvh"])
            run([args.cli, "trace", "--scene", c["mesh"], "--rays", c["rays"], "--out", c["hits"]["embree"],
                 "--method", "embree", "--robust"])
        manifest = os.path.join(tmp, "cases.json")
        json.dump(cases, open(manifest, "w"))
        env = preload_env(tmp)
        env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
        o3d_version = run([sys.executable, os.path.abspath(__file__), "--worker", manifest], env=env).strip()
        rows = []
        for c in cases:
            row = {"family": c["family"], "case": c["case"], "excluded": c["excluded"]}
            for lib in LIBS:
                jf = os.path.join(tmp, "classify.json")
                run([args.cli, "classify", "--scene", c["mesh"], "--rays", c["rays"], "--hits", c["hits"][lib],
                     "--threads", str(args.threads), "--json", jf])
                row[lib] = json.load(open(jf))
            row["rays"] = row["simdbvh"]["rays"]
            row["triangles"] = row["simdbvh"]["triangles"]
            rows.append(row)
    families = {}
    for row in rows:
        f = families.setdefault(row["family"], {"cases": 0, "rays": 0, "excluded": 0,
                                                **{lib: {k: 0 for k in LABELS} for lib in LIBS}})
        f["cases"] += 1
        f["excluded"] += row["excluded"]
        f["rays"] += row["rays"]
        for lib in LIBS:
            for k in LABELS:
                f[lib][k] += row[lib][k]
    doc = {"machine": machine(), "open3d": o3d_version, "quick": args.quick, "families": families, "cases": rows,
           "command": " ".join([os.path.relpath(sys.argv[0], ROOT)] + sys.argv[1:])}
    json.dump(doc, open(os.path.join(args.out, "compare_accuracy_open3d.json"), "w"), indent=1)

    def wrong(c):
        return c["leak"] + c["false_hit"] + c["wrong_triangle"] + c["t_error"]

    def cell(c):
        return f"{wrong(c)} ({c['marginal']})"

    lines = [f"Accuracy families, every ray on [0, inf); {machine()}; Open3D {o3d_version} with the mask shim; "
             f"Embree = Embree 3 direct (rtcIntersect1, robust flag){'; --quick' if args.quick else ''}", "",
             "| family | cases | rays | left out | simdbvh wrong (marginal) | Open3D wrong (marginal) "
             "| Embree wrong (marginal) | Open3D leaks | Open3D false hits | Open3D wrong triangle | Open3D t error |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, f in families.items():
        o = f["open3d"]
        lines.append(f"| {name} | {f['cases']} | {f['rays']} | {f['excluded']} | {cell(f['simdbvh'])} | "
                     f"{cell(o)} | {cell(f['embree'])} | {o['leak']} | {o['false_hit']} | "
                     f"{o['wrong_triangle']} | {o['t_error']} |")
    tot = {lib: {k: sum(f[lib][k] for f in families.values()) for k in LABELS} for lib in LIBS}
    lines.append(f"| all | {sum(f['cases'] for f in families.values())} | "
                 f"{sum(f['rays'] for f in families.values())} | {sum(f['excluded'] for f in families.values())} | "
                 f"{cell(tot['simdbvh'])} | {cell(tot['open3d'])} | {cell(tot['embree'])} | {tot['open3d']['leak']} | "
                 f"{tot['open3d']['false_hit']} | {tot['open3d']['wrong_triangle']} | {tot['open3d']['t_error']} |")
    lines += ["", "rays: traced by all three; left out: rays Embree rejects (a coordinate above 1.844e18; Open3D's "
              "process aborts on them), traced by none here. wrong = leak + false_hit + wrong_triangle + t_error "
              "against the double reference (`simdbvh classify`); (marginal): how many of those lie within float "
              "rounding of the reference (a ray grazing an edge or vertex, an ill-conditioned t); the rest are "
              "hard errors."]
    text = "\n".join(lines) + "\n"
    open(os.path.join(args.out, "compare_accuracy_open3d.md"), "w").write(text)
    print(text)
    if args.chart:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        names = list(families)
        x = np.arange(len(names))
        fig, ax = plt.subplots(figsize=(10, 4))
        colors = ("tab:blue", "tab:orange", "tab:green")
        for k, lib in enumerate(LIBS):
            allw = [max(wrong(families[n][lib]), 0.5) for n in names]
            hard = [max(wrong(families[n][lib]) - families[n][lib]["marginal"], 0.5) for n in names]
            ax.bar(x + (k - 1) * 0.27, allw, 0.27, color=colors[k], alpha=0.35)
            ax.bar(x + (k - 1) * 0.27, hard, 0.27, color=colors[k], label=lib)
        ax.set_yscale("log")
        ax.set_xticks(x, names, rotation=20)
        ax.set_ylabel("wrong answers (log; 0 drawn as 0.5)")
        ax.set_title("Closest hits against the exact reference: hard errors (solid) and all (light, incl. marginal)")
        ax.legend()
        fig.tight_layout()
        os.makedirs(os.path.dirname(os.path.abspath(args.chart)), exist_ok=True)
        fig.savefig(args.chart, dpi=110)


if __name__ == "__main__":
    main()
