#!/usr/bin/python3
"""Charts for `simdbvh bench --scene room|instances-N|spheres-N|FILE.json`, from its JSON (matplotlib):
scene_speed.png (Mrays/s per method, ray kind and query), scene_tessellation.png (analytic against tessellated
spheres: bytes, Mrays/s and hit-point error per icosphere level) and sphere_precision.png
(plot_sphere_precision.py)."""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from plot_sphere_precision import sphere_precision_chart  # noqa: E402


def speed_chart(data, out):
    rows = data["speed"]
    methods = list(dict.fromkeys(r["method"] for r in rows))
    groups = [("primary", "closest"), ("primary", "any"), ("incoherent", "closest"), ("incoherent", "any")]
    fig, ax = plt.subplots(figsize=(11, 4.5))
    w = 0.8 / max(1, len(methods))
    for i, m in enumerate(methods):
        vals = [next((r["mrays_per_s"] for r in rows if r["method"] == m and (r["rays"], r["query"]) == g), 0)
                for g in groups]
        ax.bar([x + i * w for x in range(len(groups))], vals, w, label=m)
    ax.set_xticks([x + 0.4 - w / 2 for x in range(len(groups))], [f"{k}\n{q} hit" for k, q in groups])
    ax.set_ylabel("Mrays/s (one thread, median)")
    ax.set_title(f"{data['scene']}: ours against Embree's instanced scene, same rays")
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "scene_speed.png", dpi=100)
    plt.close(fig)


def tessellation_chart(data, out):
    rows = data["tessellation"]
    levels = [r for r in rows if r["level"] >= 0]
    flat = [r for r in rows if r["level"] < 0]
    if not levels:
        return
    xs = [r["level"] for r in levels]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.3))
    panels = [
        ("MB", lambda r: r["bytes"] / 1e6, "structure MB (log)", True),
        ("Mrays/s", lambda r: r["mrays_incoherent"], "incoherent Mrays/s (primary dashed)", False),
        ("error", lambda r: max(r["median_err"], 1e-17), "median relative hit-point error (log; max dotted)", True),
    ]
    for ax, (key, f, ylabel, log) in zip(axes, panels):
        ax.plot(xs, [f(r) for r in levels], "C0o-", label="icosphere (ours, BVH8)")
        if key == "Mrays/s":
            ax.plot(xs, [r["mrays_primary"] for r in levels], "C0o--")
        if key == "error":
            ax.plot(xs, [max(r["max_err"], 1e-17) for r in levels], "C0o:")
        for j, r in enumerate(flat):
            style = ["C2", "C3"][j % 2]
            ax.axhline(f(r), color=style, label=r["method"])
            if key == "Mrays/s":
                ax.axhline(r["mrays_primary"], color=style, ls="--")
            if key == "error":
                ax.axhline(max(r["max_err"], 1e-17), color=style, ls=":")
        if log:
            ax.set_yscale("log")
        ax.set_xlabel("icosphere level (20 * 4^level triangles per sphere)")
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"{data['tessellation_spheres']} spheres: analytic against tessellated (same rays)")
    fig.tight_layout()
    fig.savefig(out / "scene_tessellation.png", dpi=100)
    plt.close(fig)


def main(json_file, out_dir):
    data = json.loads(Path(json_file).read_text())
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    speed_chart(data, out)
    tessellation_chart(data, out)
    if data.get("sphere_precision"):
        sphere_precision_chart(data["sphere_precision"], out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
