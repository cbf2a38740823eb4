#!/usr/bin/python3
"""Charts for `simdbvh accuracy --json FILE` (or --report DIR -> DIR/accuracy.json).

usage: scripts/plot_accuracy.py ACCURACY.json [OUT_DIR]
  speed_vs_accuracy.png  Mrays/s against disagreements per million rays (log),
                         one point per method variant, one panel per family,
                         the Pareto front (faster and more accurate) marked.
  offsets.png            leak rate and max relative t error against the scene
                         offset (1e0..1e7), one line per method.
  inside_outside.png     the inside/outside panel: wrong answers against CGAL and
                         microseconds per point, per mesh, point family and method
                         (ours, Embree hit parity, Open3D compute_occupancy).
Uses Debian's python3-matplotlib (Agg backend, no display needed).
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 0.1  # zero disagreements are drawn here on the log axis


def num(v):
    """A JSON number; null (the report layer writes non-finite numbers as null) is NaN: not drawn."""
    return float("nan") if v is None else v


def pareto(points):
    """Indices of points not dominated (higher Mrays/s and lower dpm is better)."""
    front = []
    for i, (x, y) in enumerate(points):
        dominated = any((x2 <= x and y2 >= y) and (x2 < x or y2 > y) for j, (x2, y2) in enumerate(points) if j != i)
        if not dominated:
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def style(method):
    if method.startswith("bvh8"):
        return "s", {"scalar": "lightsteelblue", "avx2": "tab:blue", "avx512": "navy"}.get(method.split("/")[1], "tab:cyan")
    if method.startswith("bvh2/watertight"):
        return "o", "tab:green" if method.endswith("conservative") else "tab:olive"
    if method.startswith("bvh2/moller"):
        return "^", "tab:red" if method.endswith("conservative") else "tab:orange"
    if method.startswith("embree"):
        return "D", "tab:purple" if "robust" in method else "tab:pink"
    return "x", "tab:gray"


def speed_vs_accuracy(rows, out):
    fam_rows = [r for r in rows if r["level"] == "family"]
    families = []
    for r in fam_rows:
        if r["family"] not in families:
            families.append(r["family"])
    if not families:
        return None
    cols = min(4, len(families))
    nrows = math.ceil(len(families) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.6 * cols, 3.9 * nrows), squeeze=False)
    handles = {}
    for k, fam in enumerate(families):
        ax = axes[k // cols][k % cols]
        rs = [r for r in fam_rows if r["family"] == fam]
        pts = [(max(num(r["disagreements_per_million"]), FLOOR), num(r["mrays_per_s"])) for r in rs]
        for r, (x, y) in zip(rs, pts):
            m, c = style(r["method"])
            h = ax.scatter([x], [y], marker=m, color=c, s=46, zorder=3, label=r["method"])
            handles[r["method"]] = h
        front = pareto(pts)
        ax.plot([pts[i][0] for i in front], [pts[i][1] for i in front], "k--", lw=1, zorder=2)
        for i in front:
            ax.scatter([pts[i][0]], [pts[i][1]], facecolors="none", edgecolors="k", s=140, zorder=4)
        ax.set_xscale("log")
        ax.set_xlim(FLOOR / 2, max(1e6, max(x for x, _ in pts) * 2))
        ax.axvline(FLOOR, color="0.8", lw=0.8, zorder=1)
        ax.set_title(f"{fam} ({rs[0]['rays']} rays)")
        ax.set_xlabel(f"disagreements per million (log; 0 drawn at {FLOOR})")
        ax.set_ylabel("Mrays/s (1 thread)")
        ax.grid(True, which="both", alpha=0.3)
    for k in range(len(families), nrows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=min(5, len(handles)), fontsize=8)
    fig.suptitle("Speed against accuracy (double-precision reference); circled, dashed: Pareto front")
    fig.tight_layout(rect=(0, 0.08, 1, 0.96))
    path = os.path.join(out, "speed_vs_accuracy.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def offsets(rows, out):
    off_rows = [r for r in rows if r["level"] == "offset"]
    if not off_rows:
        return None
    methods = []
    for r in off_rows:
        if r["method"] not in methods:
            methods.append(r["method"])
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.6))
    for m in methods:
        rs = sorted((r for r in off_rows if r["method"] == m), key=lambda r: r["offset"])
        xs = [r["offset"] for r in rs]
        leak = [max(r["leak"] / r["rays"], 1e-6) if r["rays"] else 1e-6 for r in rs]
        terr = [max(num(r["max_rel_t_error"]), 1e-9) for r in rs]
        mk, c = style(m)
        a1.plot(xs, leak, marker=mk, color=c, label=m)
        a2.plot(xs, terr, marker=mk, color=c, label=m)
    a1.set_title("leak rate against the reference (0 drawn at 1e-6)")
    a2.set_title("max relative t error (0 drawn at 1e-9)")
    for a in (a1, a2):
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("scene offset")
        a.grid(True, which="both", alpha=0.3)
    a1.set_ylabel("leaks / rays")
    a2.set_ylabel("|t - t_ref| / t_ref")
    a2.legend(fontsize=7, loc="upper left")
    fig.suptitle("Where methods fail: watertight meshes translated by 1e0..1e7")
    fig.tight_layout()
    path = os.path.join(out, "offsets.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def inside_outside(inside, out):
    """The inside/outside panel: wrong answers (% of compared points, log) and microseconds per point, per method
    (ours, Embree's hit parity, Open3D's compute_occupancy)."""
    if not inside:
        return None
    groups = list(dict.fromkeys((r["mesh"], r["family"]) for r in inside))
    methods = list(dict.fromkeys(r["method"] for r in inside))
    fig, axes = plt.subplots(1, 2, figsize=(14, 4.8))
    w = 0.8 / max(1, len(methods))
    for i, m in enumerate(methods):
        wrong, us = [], []
        failed = []
        for g in groups:
            r = next((r for r in inside if (r["mesh"], r["family"]) == g and r["method"] == m), None)
            # A failed row (Open3D's worker died on those points) has no wrong count and no time.
            ok = r is not None and r.get("wrong") is not None and r["points"]
            wrong.append(100.0 * r["wrong"] / r["points"] if ok else float("nan"))
            us.append(num(r["us_per_point"]) if r else float("nan"))
            failed.append(r is not None and r.get("failed") is not None)
        xs = [x + i * w for x in range(len(groups))]
        # 0 wrong answers would vanish on a log axis: drawn at 1e-4 % and labelled.
        axes[0].bar(xs, [v if v > 0 else 1e-4 if v == 0 else float("nan") for v in wrong], w, label=m)
        for x, v, f in zip(xs, wrong, failed):
            if v == 0:
                axes[0].text(x, 1.2e-4, "0", ha="center", fontsize=6)
            if f:
                axes[0].text(x, 1.2e-4, "failed", ha="center", rotation=90, fontsize=6, color="tab:red")
        axes[1].bar(xs, us, w, label=m)
    labels = [f"{m}\n{f}" for m, f in groups]
    for ax in axes:
        ax.set_xticks([x + 0.4 - w / 2 for x in range(len(groups))], labels, fontsize=6)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_yscale("log")
    axes[0].set_ylabel("wrong inside/outside answers, % of points (0 drawn at 1e-4)")
    axes[0].legend(fontsize=7)
    axes[1].set_ylabel("microseconds per point, one thread")
    fig.suptitle("Inside/outside against CGAL's exact Side_of_triangle_mesh: where methods fail")
    fig.tight_layout()
    path = os.path.join(out, "inside_outside.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) >= 2 else 2
    src = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.dirname(os.path.abspath(src))
    os.makedirs(out, exist_ok=True)
    with open(src) as f:
        data = json.load(f)
    rows = data["rows"]
    for p in (speed_vs_accuracy(rows, out), offsets(rows, out), inside_outside(data.get("inside") or [], out)):
        if p:
            print("wrote", p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
