#!/usr/bin/python3
"""Charts for the simdbvh bench report, from the bench JSON (matplotlib)."""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def num(v):
    """A JSON number; null (the report layer writes non-finite numbers as null) is NaN: not drawn."""
    return float("nan") if v is None else v


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
            vals = [next((num(r["mrays_per_s"]) for r in one if label(r) == m and r["ray_kind"] == k and r["query"] == query), 0)
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

    # 2. Speed against accuracy: Mrays/s vs disagreements on the hard accuracy families (the bench's own rays
    # agree for every method), log axis with 0 at 0.5, Pareto front. Without that section: the bench sample.
    fig, ax = plt.subplots(figsize=(7, 5))
    pts = []
    hard = {m["bench_label"]: m for m in data.get("hard_families", {}).get("methods", []) if m.get("bench_label")}
    for m in methods:
        rs = [r for r in one if label(r) == m and r["query"] == "closest"]
        if not rs:
            continue
        speed = sum(num(r["mrays_per_s"]) for r in rs) / len(rs)
        if hard:
            if m not in hard:
                continue
            dis = hard[m]["disagreements"]
        else:
            dis = sum(sum(r["disagreements"][c] for c in ("leak", "false_hit", "wrong_triangle", "t_error")) for r in rs)
            dis = dis / (sum(r["sample"] for r in rs) or 1) * 1e6
        x = max(dis, 0.5)  # 0 plotted at 0.5 on the log axis
        pts.append((speed, x, m))
        ax.scatter(x, speed, s=40)
        ax.annotate(m, (x, speed), fontsize=7, xytext=(4, 2), textcoords="offset points")
    front = []
    for s, p, m in sorted(pts, key=lambda t: (t[1], -t[0])):
        if not front or s > front[-1][0]:
            front.append((s, p, m))
    if front:
        ax.plot([p for _, p, _ in front], [s for s, _, _ in front], "k--", lw=0.8, label="Pareto front")
        ax.legend(fontsize=8)
    ax.set_xscale("log")
    if hard:
        ax.set_title("hard families: " + ", ".join(data["hard_families"]["families"]), fontsize=9)
        ax.set_xlabel("disagreements with the reference on the hard families (0 shown at 0.5)")
    else:
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
            b2 = next((num(r["mrays_per_s"]) for r in one if r["method"] == "bvh2" and r["ray_kind"] == k and r["query"] == "closest"), 0)
            b8 = next((num(r["mrays_per_s"]) for r in one if r["method"] == "bvh8" and r["isa"] == isa and r["ray_kind"] == k and r["query"] == "closest"), 0)
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
    x = range(len(names))
    axes[0].bar([i - 0.27 for i in x], [seen[n]["build_ms"] for n in names], 0.27, label="1 thread, cold (first)")
    axes[0].bar(x, [seen[n].get("build_ms_warm", 0) for n in names], 0.27, label="1 thread, warm (median)")
    axes[0].bar([i + 0.27 for i in x], [seen[n].get("build_ms_all_cores_warm", 0) for n in names], 0.27,
                label="all cores, warm (median)")
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

    widths_chart(data, out)
    refit_chart(data, out)


KIND_COLORS = {"primary": "tab:blue", "incoherent": "tab:orange", "diffuse": "tab:green"}
ISA_STYLES = {"scalar": ":", "avx2": "--", "avx512": "-"}


def widths_chart(data, out):
    """Wide vs binary: one row of panels per scene, x = node width (2 = BVH2, scalar)."""
    rows = [r for r in data.get("widths", []) if r["threads"] == 1 and r["width"]]
    scenes = [s["scene"] for s in data.get("width_scenes", [])]
    if not rows or not scenes:
        return
    isas = [i for i in ISA_STYLES if any(r["isa"] == i for r in rows if r["width"] > 2)]
    cols = [("mrays_per_s", "closest", "Mrays/s, closest hit"), ("mrays_per_s", "any", "Mrays/s, any hit"),
            ("nodes_per_ray", "closest", "nodes visited / ray (closest)"),
            ("box_tests_per_ray", "closest", "box tests (lanes) / ray (closest)")]
    fig, axes = plt.subplots(len(scenes), len(cols) + 1, figsize=(4.2 * (len(cols) + 1), 3.6 * len(scenes)),
                             squeeze=False)
    for si, scene in enumerate(scenes):
        rs = [r for r in rows if r["scene"] == scene]
        tris = next((s["triangles"] for s in data["width_scenes"] if s["scene"] == scene), 0)
        for ci, (key, query, title) in enumerate(cols):
            ax = axes[si][ci]
            counters = key != "mrays_per_s"
            for kind, color in KIND_COLORS.items():
                for isa in (isas[:1] if counters else isas):
                    pts = []
                    for w in (2, 4, 8, 16):
                        want = "scalar" if w == 2 else isa
                        v = next((num(r[key]) for r in rs if r["width"] == w and r["isa"] == want
                                  and r["ray_kind"] == kind and r["query"] == query), None)
                        if v is not None:
                            pts.append((w, v))
                    if pts:
                        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", color=color,
                                ls="-" if counters else ISA_STYLES[isa], label=kind if counters else f"{kind} {isa}")
            ax.set_xscale("log", base=2)
            ax.set_xticks([2, 4, 8, 16], ["2", "4", "8", "16"])
            ax.set_title(f"{scene}: {title}", fontsize=9)
            ax.set_xlabel("node width (2 = BVH2)")
            ax.grid(alpha=0.3)
            if si == 0 and ci in (0, 2):
                ax.legend(fontsize=6)
        ax = axes[si][len(cols)]
        per_w = {}
        for r in rs:
            per_w.setdefault(r["width"], r)
        ws = sorted(per_w)
        ax.bar([str(w) for w in ws], [per_w[w]["bytes_per_triangle"] for w in ws], color="tab:gray", label="bytes/triangle")
        ax.set_ylabel("bytes / triangle")
        ax2 = ax.twinx()
        # The collapse does not depend on the ISA: the median over the width's rows.
        coll = [sorted(r["collapse_ms"] for r in rs if r["width"] == w and r["ray_kind"] == "primary"
                       and r["query"] == "closest") for w in ws]
        ax2.plot([str(w) for w in ws], [c[len(c) // 2] if w > 2 and c else 0 for w, c in zip(ws, coll)], "ko-",
                 label="collapse ms")
        ax2.set_ylabel("collapse ms (warm, median over ISAs)")
        ax.set_title(f"{scene} ({tris:,} triangles): memory, collapse", fontsize=9)
    fig.suptitle("Wide vs binary, one thread (median of timed traces after a warm-up; line style = ISA)")
    fig.tight_layout()
    fig.savefig(out / "widths.png", dpi=100)
    plt.close(fig)


def refit_chart(data, out):
    """The refit sequence: ms per frame (log) and Mrays/s per frame, ours and Embree's, refit and rebuild."""
    frames = data.get("refit") or []
    if not frames:
        return
    x = [f["frame"] for f in frames]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    ax = axes[0]
    for key, lab, style in [("refit_ms", "BVH8 refit, 1 thread", "C0-"), ("refit_ms_all_cores", "BVH8 refit, all cores", "C0:"),
                            ("rebuild_ms", "BVH8 rebuild, 1 thread", "C0--"), ("embree_refit_ms", "Embree refit, 1 thread", "C3-"),
                            ("embree_rebuild_ms", "Embree medium rebuild, 1 thread", "C3--")]:
        ax.plot(x, [num(f[key]) for f in frames], style, marker="o", ms=3, label=lab)
    ax.set_yscale("log")
    ax.set_xlabel("frame (0.1 rad more twist per frame)")
    ax.set_ylabel("ms (median)")
    ax.set_title("time to update the structure", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    for k, kind in enumerate(["primary", "incoherent"]):
        ax = axes[1 + k]
        for key, lab, style in [("mrays_refit", "BVH8 after refit", "C0-"), ("mrays_rebuild", "BVH8 after rebuild", "C0--"),
                                ("mrays_embree_refit", "Embree after refit", "C3-"),
                                ("mrays_embree_rebuild", "Embree after rebuild", "C3--")]:
            ax.plot(x, [num(f[key][k]) for f in frames], style, marker="o", ms=3, label=lab)
        ax.set_xlabel("frame")
        ax.set_ylabel("Mrays/s, closest hit, 1 thread")
        ax.set_title(f"{kind} rays after the update", fontsize=9)
        ax.set_ylim(bottom=0)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.suptitle(f"Refit against rebuild on {data.get('scene', '')}: when does a rebuild pay?")
    fig.tight_layout()
    fig.savefig(out / "refit.png", dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
