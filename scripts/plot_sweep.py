#!/usr/bin/python3
"""Charts for simdbvh bench --sweep, from its JSON (matplotlib): the winner map over (triangles, rays) with the
cost model's crossover lines, and time to answer against triangles for a few ray counts."""
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

METHODS = ["brute", "brute8", "bvh2", "bvh4", "bvh8", "bvh16"]
COLORS = {"brute": "tab:gray", "brute8": "tab:olive", "bvh2": "tab:blue", "bvh4": "tab:green", "bvh8": "tab:red",
          "bvh16": "tab:purple", "embree": "black"}


def predict(model, m, n, rays, threads):
    """cost_model.h's formula (the same terms as build_size_term / ray_size_term)."""
    c = model[m]
    tree = m not in ("brute", "brute8")
    g = 0.0 if m == "brute" else (n if m == "brute8" else n * math.log2(n + 1))
    f = math.log2(n + 1) if tree else n
    return c["build0"] + c["build1"] * g + c["call"] + rays * (c["ray0"] + c["ray1"] * f) / threads


def winners(rows, threads, kind, held_out):
    best = {}
    for r in rows:
        if r["threads"] != threads or r["ray_kind"] != kind or r["held_out"] != held_out or r["method"] == "embree":
            continue
        k = (r["triangles"], r["rays"])
        if k not in best or r["total_ms"] < best[k]["total_ms"]:
            best[k] = r
    return best


def winner_map(data, out):
    rows, model = data["rows"], data["model"]
    configs = [(k, t) for k in ("incoherent", "primary") for t in sorted({1, data["threads_all"]})]
    fig, axes = plt.subplots(1, len(configs), figsize=(5 * len(configs), 4.6), sharey=True, squeeze=False)
    ns = np.logspace(0, 6.3, 160)
    rs = np.logspace(0, 6.3, 160)
    for ax, (kind, threads) in zip(axes[0], configs):
        grid = np.array([[METHODS.index(min(METHODS, key=lambda m: predict(model, m, n, r, threads))) for n in ns]
                         for r in rs])
        cmap = matplotlib.colors.ListedColormap([COLORS[m] for m in METHODS])
        ax.pcolormesh(ns, rs, grid, cmap=cmap, vmin=-0.5, vmax=len(METHODS) - 0.5, alpha=0.18, shading="auto")
        ax.contour(ns, rs, grid, levels=np.arange(0.5, len(METHODS)), colors="k", linewidths=0.8)
        for held in (False, True):
            for (n, r), row in winners(rows, threads, kind, held).items():
                ax.scatter(n, r, s=46, marker="o" if not held else "D", color=COLORS[row["method"]],
                           edgecolors="k" if held else "none", linewidths=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("triangles")
        ax.set_title(f"{kind}, {threads} thread{'s' if threads > 1 else ''}")
    axes[0][0].set_ylabel("rays")
    handles = [plt.Line2D([], [], marker="o", ls="", color=COLORS[m], label=m) for m in METHODS]
    handles.append(plt.Line2D([], [], marker="D", ls="", color="w", markeredgecolor="k", label="held out"))
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), frameon=False)
    fig.suptitle("fastest time to answer (build + trace): dots measured, shading and lines the fitted model",
                 y=0.02, fontsize=9)
    fig.tight_layout(rect=(0, 0.04, 1, 0.92))
    fig.savefig(out / "sweep_winners.png", dpi=110)
    plt.close(fig)


def time_curves(data, out):
    rows = [r for r in data["rows"] if r["threads"] == 1 and r["ray_kind"] == "incoherent" and not r["held_out"]
            and r["scene"].startswith("soup")]
    counts = [c for c in (10, 1000, 100000) if any(r["rays"] == c for r in rows)]
    fig, axes = plt.subplots(1, len(counts), figsize=(5 * len(counts), 4.2), sharey=True, squeeze=False)
    for ax, c in zip(axes[0], counts):
        for m in METHODS + ["embree"]:
            pts = sorted((r["triangles"], r["total_ms"]) for r in rows if r["rays"] == c and r["method"] == m)
            if pts:
                ax.plot(*zip(*pts), marker="o", ms=3, color=COLORS[m], label=m, ls="--" if m == "embree" else "-")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("triangles (soup-N)")
        ax.set_title(f"{c} incoherent rays, 1 thread")
    axes[0][0].set_ylabel("time to answer, ms")
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "sweep_time.png", dpi=110)
    plt.close(fig)


def main(json_file, out_dir):
    data = json.loads(Path(json_file).read_text())
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    winner_map(data, out)
    time_curves(data, out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
