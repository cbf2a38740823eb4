#!/usr/bin/python3
"""Chart of the sphere precision study (lab/sphere_precision.h), from a JSON file with the key
"sphere_precision": one object per ratio (ratio, rays, miss_*, median_err_*, max_err_*).

usage: scripts/plot_sphere_precision.py JSON_FILE OUT_DIR
  sphere_precision.png  left: median (solid) and max (faint, dashed) relative hit-point error
                        | |p - c| - r | / r against the distance/radius ratio (log-log), one line per method;
                        right: the false-miss fraction against the ratio.
Uses Debian's python3-matplotlib (Agg backend, no display needed).
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-17  # a zero error is drawn here on the log axis
METHODS = [("naive", "naive float quadratic", "o", "C3"),
           ("robust", "robust (Haines et al. 2019)", "s", "C0"),
           ("embree", "Embree SPHERE_POINT", "^", "C2")]


def num(v):
    """A JSON number; null (the report layer writes non-finite numbers as null) is NaN: not drawn."""
    return float("nan") if v is None else v


def floored(v):
    v = num(v)
    return v if v != v else max(v, FLOOR)  # NaN stays NaN


def sphere_precision_chart(rows, out_dir):
    """Writes OUT_DIR/sphere_precision.png from the study's rows; returns its path (None without rows)."""
    if not rows:
        return None
    rows = sorted(rows, key=lambda r: r["ratio"])
    xs = [r["ratio"] for r in rows]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.6))
    for key, lab, mk, c in METHODS:
        a1.plot(xs, [floored(r[f"median_err_{key}"]) for r in rows], marker=mk, ms=4, color=c, label=f"{lab}, median")
        a1.plot(xs, [floored(r[f"max_err_{key}"]) for r in rows], "--", color=c, alpha=0.35, label=f"{lab}, max")
        a2.plot(xs, [num(r[f"miss_{key}"]) for r in rows], marker=mk, ms=4, color=c, label=lab)
    # What rounding t to float alone costs: half an ulp of t moves the hit point by up to about ratio * 2^-24 radii.
    a1.plot(xs, [x * 2.0 ** -24 for x in xs], ":", color="0.5",
            label="ratio \u00b7 2\u207b\u00b2\u2074 (t rounded to float)")
    a1.set_yscale("log")
    a1.set_ylabel(f"| |p - c| - r | / r  (0 drawn at {FLOOR:g})")
    a1.set_title("relative hit-point error over the hits (solid median, dashed max)", fontsize=9)
    a1.legend(fontsize=6, loc="upper left")
    a2.set_ylim(-0.02, 1.02)
    a2.set_ylabel("false misses / rays (every ray hits in exact arithmetic)")
    a2.set_title("false-miss fraction", fontsize=9)
    a2.legend(fontsize=7, loc="upper left")
    for a in (a1, a2):
        a.set_xscale("log")
        a.set_xlabel("distance from ray origin to sphere centre / radius")
        a.grid(True, which="both", alpha=0.3)
    n = rows[0]["rays"]
    fig.suptitle(f"Where sphere tests fail: unit spheres at 10^0.25..10^7 radii, {n} rays per distance")
    fig.tight_layout()
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "sphere_precision.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main():
    if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) >= 2 and sys.argv[1] in ("-h", "--help") else 2
    with open(sys.argv[1]) as f:
        data = json.load(f)
    path = sphere_precision_chart(data["sphere_precision"], sys.argv[2])
    if path:
        print("wrote", path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
