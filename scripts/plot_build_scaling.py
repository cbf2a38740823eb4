#!/usr/bin/python3
"""Build charts from simdbvh_bench_build's Google Benchmark JSON, against the build targets
(docs/results.md#the-targets).

usage: plot_build_scaling.py OUT_DIR RUN.json [RUN.json ...]

Reads the _median rows of build/<scene>/<bvh8|embree_medium>/<t1|tall> (one file
per run: the one-thread run pinned, the all-cores run unpinned) and draws
build_scaling.png:
  1. build ms against triangles, log-log: ours (Bvh8::build(mesh)) and Embree 3
     medium, one thread and all cores, one line per scene family (soup-N,
     icosphere-N);
  2. ns per triangle against triangles (the linearity the build targets ask for);
  3. the time split of Bvh8::build(mesh): the BVH2 (the rest) and collapse + pack
     (the collapse_pack_ms counter), one thread, per scene of >= 100,000 triangles;
  4. peak resident bytes per triangle above the mesh during the build, ours and
     Embree's, against the build targets' memory bound, same scenes (smaller builds stay within
     the pages already resident).
It prints the same figures as a markdown table on stdout.
"""
import json
import re
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROW = re.compile(r"^build/(?P<scene>[^/]+)/(?P<row>bvh8|embree_medium)/(?P<thr>t1|tall)")


def triangles(scene):
    m = re.match(r"^(soup|icosphere)-(\d+)$", scene)
    if not m:
        return None
    n = int(m.group(2))
    return n if m.group(1) == "soup" else 20 * 4**n


def family(scene):
    return scene.split("-")[0]


def load(files):
    rows = {}
    for f in files:
        for b in json.loads(Path(f).read_text())["benchmarks"]:
            if b.get("aggregate_name") != "median":
                continue
            m = ROW.match(b["run_name"] if "run_name" in b else b["name"])
            if not m or triangles(m["scene"]) is None:
                continue
            rows[(m["scene"], m["row"], m["thr"])] = b
    return rows


def main(out_dir, files):
    rows = load(files)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    scenes = sorted({k[0] for k in rows}, key=lambda s: (family(s), triangles(s)))
    fams = sorted({family(s) for s in scenes})
    fig, axes = plt.subplots(1, 4, figsize=(22, 4.8))
    styles = {("bvh8", "t1"): ("C0", "-", "ours, 1 thread"), ("bvh8", "tall"): ("C0", ":", "ours, all cores"),
              ("embree_medium", "t1"): ("C3", "-", "Embree medium, 1 thread"),
              ("embree_medium", "tall"): ("C3", ":", "Embree medium, all cores")}
    markers = {"soup": "o", "icosphere": "s"}
    for (row, thr), (color, ls, lab) in styles.items():
        for fam in fams:
            pts = [(triangles(s), rows[(s, row, thr)]["real_time"]) for s in scenes
                   if family(s) == fam and (s, row, thr) in rows]
            if not pts:
                continue
            xs, ms = zip(*pts)
            axes[0].plot(xs, ms, color=color, ls=ls, marker=markers[fam], label=f"{lab} ({fam})")
            axes[1].plot(xs, [m * 1e6 / x for x, m in pts], color=color, ls=ls, marker=markers[fam],
                         label=f"{lab} ({fam})")
    axes[0].set_xscale("log")
    axes[0].set_yscale("log")
    axes[0].set_xlabel("triangles")
    axes[0].set_ylabel("build ms (median)")
    axes[0].set_title("Build time")
    axes[0].legend(fontsize=6)
    axes[1].set_xscale("log")
    axes[1].set_xlabel("triangles")
    axes[1].set_ylabel("ns per triangle")
    axes[1].set_title("Per triangle (flat = linear)")
    # 3. Split, one thread.
    split = [s for s in scenes if (s, "bvh8", "t1") in rows and triangles(s) >= 100000]  # peaks: page granularity
    total = [rows[(s, "bvh8", "t1")]["real_time"] for s in split]
    cp = [rows[(s, "bvh8", "t1")].get("collapse_pack_ms", float("nan")) for s in split]
    share = [c / t * 100 for c, t in zip(cp, total)]
    axes[2].bar(range(len(split)), [100 - x for x in share], label="BVH2")
    axes[2].bar(range(len(split)), share, bottom=[100 - x for x in share], label="collapse + pack")
    axes[2].axhline(85, color="k", lw=0.8, ls="--")
    axes[2].set_xticks(range(len(split)), split, rotation=35, ha="right", fontsize=7)
    axes[2].set_ylabel("% of Bvh8::build(mesh), 1 thread")
    axes[2].set_title("Time split (dashed: collapse + pack = 15%)")
    axes[2].legend(fontsize=7)
    # 4. Peak memory per triangle.
    w = 0.27
    for i, (row, lab, color) in enumerate([("bvh8", "ours: peak over the mesh", "C0"),
                                           ("embree_medium", "Embree: peak over the mesh", "C3")]):
        vals = [rows.get((s, row, "t1"), {}).get("peak_B_per_tri", float("nan")) for s in split]
        axes[3].bar([x + (i - 1) * w for x in range(len(split))], vals, w, label=lab, color=color)
    fin = [rows[(s, "bvh8", "t1")].get("final_B_per_tri", float("nan")) for s in split]
    mesh = [rows[(s, "bvh8", "t1")].get("mesh_B_per_tri", float("nan")) for s in split]
    axes[3].bar([x + w for x in range(len(split))], [0.5 * m + 1.5 * f for m, f in zip(mesh, fin)], w,
                label="the target's bound: 1.5 (mesh + BVH8) - mesh", color="0.7")
    axes[3].set_xticks(range(len(split)), split, rotation=35, ha="right", fontsize=7)
    axes[3].set_ylabel("bytes per triangle")
    axes[3].set_title("Peak resident memory during the build, 1 thread")
    axes[3].legend(fontsize=7)
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(out / "build_scaling.png", dpi=100)

    print("| scene | triangles | ours 1 thread ms (ns/tri) | Embree 1 thread ms (ns/tri) | ours / Embree | "
          "ours all cores ms | Embree all cores ms | ours / Embree | collapse + pack, 1 thread | "
          "ours peak B/tri | Embree peak B/tri |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for s in scenes:
        n = triangles(s)

        def ms(row, thr):
            b = rows.get((s, row, thr))
            return b["real_time"] if b else float("nan")

        o1, e1, oa, ea = ms("bvh8", "t1"), ms("embree_medium", "t1"), ms("bvh8", "tall"), ms("embree_medium", "tall")
        b = rows.get((s, "bvh8", "t1"), {})
        eb = rows.get((s, "embree_medium", "t1"), {})
        def peak(r):  # below 100,000 triangles a build stays within pages already resident
            v = r.get("peak_B_per_tri", float("nan"))
            return f"{v:.1f}" if n >= 100000 and v > 0 else "-"

        print(f"| {s} | {n:,} | {o1:,.1f} ({o1 * 1e6 / n:.0f}) | {e1:,.1f} ({e1 * 1e6 / n:.0f}) | {o1 / e1:.2f} | "
              f"{oa:,.1f} | {ea:,.1f} | {oa / ea:.2f} | {b.get('collapse_pack_ms', float('nan')) / o1 * 100:.1f}% | "
              f"{peak(b)} | {peak(eb)} |")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit("usage: plot_build_scaling.py OUT_DIR RUN.json [RUN.json ...]")
    main(sys.argv[1], sys.argv[2:])
