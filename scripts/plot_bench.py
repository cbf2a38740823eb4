#!/usr/bin/python3
"""Charts for the simdbvh bench report, from the bench JSON (matplotlib)."""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def label(r):
    m = r["method"]
    return f"{m}/{r['isa']}" if m in ("bvh4", "bvh8", "bvh16") else m


def main(json_file, out_dir):
    data = json.loads(Path(json_file).read_text())
    recs = data["records"]
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    kinds = ["primary", "incoherent", "diffuse"]
    one = [r for r in recs if r["threads"] == 1 and r["method"] != "brute"]
    methods = list(dict.fromkeys(label(r) for r in one))

    # 1. Mrays/s per method and ray kind (closest and any hit, one thread).
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    for ax, query in zip(axes, ["closest", "any"]):
        w = 0.8 / max(1, len(methods))
        for i, m in enumerate(methods):
            vals = [next((r["mrays_per_s"] for r in one if label(r) == m and r["ray_kind"] == k and r["query"] == query), 0)
                    for k in kinds]
            ax.bar([x + i * w for x in range(len(kinds))], vals, w, label=m)
        ax.set_xticks([x + 0.4 - w / 2 for x in range(len(kinds))], kinds)
        ax.set_title(f"{query} hit, 1 thread")
        ax.set_ylabel("Mrays/s")
        ax.grid(axis="y", alpha=0.3)
    axes[1].legend(fontsize=7, loc="upper right")
    fig.suptitle(f"{data['scene']} ({data['triangles']:,} triangles)")
    fig.tight_layout()
    fig.savefig(out / "mrays.png", dpi=110)
    plt.close(fig)

    # 2. Speed against accuracy: Mrays/s vs disagreements per million rays (log), Pareto front.
    fig, ax = plt.subplots(figsize=(7, 5))
    pts = []
    for m in methods:
        rs = [r for r in one if label(r) == m and r["query"] == "closest"]
        if not rs:
            continue
        speed = sum(r["mrays_per_s"] for r in rs) / len(rs)
        dis = sum(sum(r["disagreements"][c] for c in ("leak", "false_hit", "wrong_triangle", "t_error")) for r in rs)
        sample = sum(r["sample"] for r in rs) or 1
        ppm = max(dis / sample * 1e6, 0.5)  # 0 plotted at 0.5 ppm on the log axis
        pts.append((speed, ppm, m))
        ax.scatter(ppm, speed, s=40)
        ax.annotate(m, (ppm, speed), fontsize=7, xytext=(4, 2), textcoords="offset points")
    front = []
    for s, p, m in sorted(pts, key=lambda t: (t[1], -t[0])):
        if not front or s > front[-1][0]:
            front.append((s, p, m))
    if front:
        ax.plot([p for _, p, _ in front], [s for s, _, _ in front], "k--", lw=0.8, label="Pareto front")
        ax.legend(fontsize=8)
    ax.set_xscale("log")
    ax.set_xlabel("disagreements with the reference per million rays (0 shown at 0.5)")
    ax.set_ylabel("Mrays/s (closest hit, 1 thread, mean over ray kinds)")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "speed_accuracy.png", dpi=110)
    plt.close(fig)

    # 3. BVH8 over BVH2 speed-up per ISA.
    fig, ax = plt.subplots(figsize=(7, 4))
    isas = list(dict.fromkeys(r["isa"] for r in one if r["method"] == "bvh8"))
    w = 0.8 / max(1, len(isas))
    for i, isa in enumerate(isas):
        vals = []
        for k in kinds:
            b2 = next((r["mrays_per_s"] for r in one if r["method"] == "bvh2" and r["ray_kind"] == k and r["query"] == "closest"), 0)
            b8 = next((r["mrays_per_s"] for r in one if r["method"] == "bvh8" and r["isa"] == isa and r["ray_kind"] == k and r["query"] == "closest"), 0)
            vals.append(b8 / b2 if b2 else 0)
        ax.bar([x + i * w for x in range(len(kinds))], vals, w, label=f"bvh8/{isa}")
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xticks([x + 0.4 - w / 2 for x in range(len(kinds))], kinds)
    ax.set_ylabel("speed-up over bvh2 (closest hit, 1 thread)")
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "speedup.png", dpi=110)
    plt.close(fig)

    # 4. Build time and bytes per triangle per method.
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    seen = {}
    for r in one:
        seen.setdefault(label(r), r)
    names = list(seen)
    axes[0].bar(range(len(names)), [seen[n]["build_ms"] for n in names], label="1 thread")
    axes[0].bar(range(len(names)), [seen[n]["build_ms_all_cores"] for n in names], 0.5, label="all cores")
    axes[0].set_ylabel("build ms")
    axes[0].legend(fontsize=8)
    axes[1].bar(range(len(names)), [seen[n]["bytes_per_triangle"] for n in names])
    axes[1].set_ylabel("bytes per triangle")
    for ax in axes:
        ax.set_xticks(range(len(names)), names, rotation=30, ha="right", fontsize=7)
        ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "build.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
