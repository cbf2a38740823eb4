#!/usr/bin/python3
"""Charts for the simdbvh build-quality panel (simdbvh panel), from its JSON.

usage: plot_panel.py PANEL.json OUT_DIR
Writes OUT_DIR/build_vs_trace.png (build time against trace speed, a point per
builder), OUT_DIR/sah_vs_mrays.png (SAH cost against measured Mrays/s) and
OUT_DIR/leaf_hist.png (leaf-size histogram per builder).
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

KINDS = ["primary", "incoherent", "diffuse"]
MARKERS = {"primary": "o", "incoherent": "s", "diffuse": "^"}


def num(v):
    """A JSON number; null (the report layer writes non-finite numbers as null) is NaN: not drawn."""
    return float("nan") if v is None else v


def mean(xs):
    return sum(num(x) for x in xs) / len(xs) if xs else 0.0


def main(json_file, out_dir):
    data = json.loads(Path(json_file).read_text())
    rows = [r for r in data["rows"] if not r["skipped"]]
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    title = f"{data['scene']} ({data['triangles']:,} triangles)"
    colors = {r["name"]: plt.cm.tab10(i % 10) for i, r in enumerate(rows)}

    # 1. Build time (1 thread) against trace speed: one point per builder, BVH2
    #    and BVH8 (mean Mrays/s over the three ray kinds), plus the frame time.
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    ax = axes[0]
    for r in rows:
        c = colors[r["name"]]
        x = r["build_ms_1"]
        ax.scatter(x, mean(r["mrays_bvh2"]), color=c, marker="o", s=45)
        ax.annotate(r["name"], (x, mean(r["mrays_bvh2"])), fontsize=7, xytext=(4, 3), textcoords="offset points")
        if r["name"] != "spheres":
            ax.scatter(x, mean(r["mrays_bvh8"]), color=c, marker="D", s=45)
            ax.plot([x, x], [mean(r["mrays_bvh2"]), mean(r["mrays_bvh8"])], color=c, alpha=0.3)
    ax.scatter([], [], color="gray", marker="o", label="BVH2")
    ax.scatter([], [], color="gray", marker="D", label=f"BVH8 ({data['bvh8_isa']})")
    ax.set_xscale("log")
    ax.set_xlabel("build time, 1 thread (ms, log)")
    ax.set_ylabel("Mrays/s, 1 thread (mean of primary/incoherent/diffuse)")
    ax.set_title("build time against trace speed")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1]
    for r in rows:
        c = colors[r["name"]]
        ax.scatter(r["build_ms_1"], num(r["frame_ms"]), color=c, s=45)
        ax.annotate(r["name"], (r["build_ms_1"], num(r["frame_ms"])), fontsize=7, xytext=(4, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("build time, 1 thread (ms, log)")
    ax.set_ylabel("frame time, BVH2 (ms, log)")
    ax.set_title(f"build time against one frame ({data['frame']})")
    ax.grid(alpha=0.3, which="both")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out / "build_vs_trace.png", dpi=110)
    plt.close(fig)

    # 2. SAH cost against measured Mrays/s per ray kind (BVH2 and BVH8).
    fig, axes = plt.subplots(1, 2, figsize=(13, 5), sharex=True)
    for ax, key, lab in [(axes[0], "mrays_bvh2", "BVH2"), (axes[1], "mrays_bvh8", f"BVH8 ({data['bvh8_isa']})")]:
        for r in rows:
            if key == "mrays_bvh8" and r["name"] == "spheres":
                continue
            for k, kind in enumerate(KINDS):
                ax.scatter(r["sah_cost"], num(r[key][k]), color=colors[r["name"]], marker=MARKERS[kind], s=40)
            ax.annotate(r["name"], (r["sah_cost"], r[key][0]), fontsize=7, xytext=(4, 3), textcoords="offset points")
        for kind in KINDS:
            ax.scatter([], [], color="gray", marker=MARKERS[kind], label=kind)
        ax.set_yscale("log")
        ax.set_xlabel("SAH cost of the BVH2 (spheres: its AABB topology)")
        ax.set_ylabel("Mrays/s, 1 thread, closest hit (log)")
        ax.set_title(lab)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.suptitle(title + ": SAH cost against measured speed")
    fig.tight_layout()
    fig.savefig(out / "sah_vs_mrays.png", dpi=110)
    plt.close(fig)

    # 3. Leaf-size histograms (fraction of leaves per bucket).
    buckets = data["leaf_buckets"]
    fig, ax = plt.subplots(figsize=(11, 4.5))
    w = 0.8 / max(1, len(rows))
    for i, r in enumerate(rows):
        total = sum(r["leaf_hist"]) or 1
        ax.bar([x + i * w for x in range(len(buckets))], [c / total for c in r["leaf_hist"]], w, label=r["name"],
               color=colors[r["name"]])
    ax.set_xticks([x + 0.4 - w / 2 for x in range(len(buckets))], buckets)
    ax.set_xlabel("triangles per leaf")
    ax.set_ylabel("fraction of leaves")
    ax.set_title(title + ": leaf sizes")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(out / "leaf_hist.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
