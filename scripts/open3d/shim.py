# SPDX-License-Identifier: MIT
"""Builds embree_mask_shim.c (next to this file) and returns the environment
that preloads it: Debian 12's Open3D then answers ray queries
(docs/open3d.md). Used by scripts/compare_rays.py, scripts/compare_points.py
and scripts/open3d/inside_worker.py."""
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def build_shim(tmpdir):
    """The shim's path in `tmpdir`, compiled with cc unless it is there already."""
    so = os.path.join(tmpdir, "embree_mask_shim.so")
    if not os.path.exists(so):
        part = so + ".part"
        subprocess.run(["cc", "-O2", "-shared", "-fPIC", os.path.join(HERE, "embree_mask_shim.c"), "-o", part,
                        "-ldl"], check=True)
        os.replace(part, so)
    return so


def preload_env(tmpdir):
    return dict(os.environ, LD_PRELOAD=build_shim(tmpdir))
