# SPDX-License-Identifier: MIT
"""Builds embree_mask_shim.c (next to this file) into `tmpdir` and returns the
environment that preloads it: Debian 12's Open3D then answers ray queries
(docs/open3d.md). Used by scripts/compare_rays.py and scripts/compare_points.py."""
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def preload_env(tmpdir):
    so = os.path.join(tmpdir, "embree_mask_shim.so")
    subprocess.run(["cc", "-O2", "-shared", "-fPIC", os.path.join(HERE, "embree_mask_shim.c"), "-o", so, "-ldl"],
                   check=True)
    return dict(os.environ, LD_PRELOAD=so)
