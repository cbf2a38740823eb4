#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Open3D's RaycastingScene.compute_occupancy for the inside/outside panel of
`simdbvh accuracy` (lab/open3d_inside.cpp runs it), on one thread.

usage: inside_worker.py [--shim-dir DIR] MESH.ply POINTS.bin OUT.bin [MESH.ply POINTS.bin OUT.bin ...]

Each job: MESH a PLY file (float32 coordinates, read by Open3D), POINTS raw
little-endian float32 x y z records. OUT (written atomically, when the job is
done) holds float64 little-endian seconds, then one byte per point: 1 inside,
0 outside. Seconds: the second compute_occupancy call on the points; the first,
untimed, also commits the scene (Embree builds its tree on the first query). A
job whose MESH is the previous job's reuses its scene.

Debian 12's Open3D misses every ray unless embree_mask_shim.c is preloaded
(docs/open3d.md): the worker builds it (into DIR, reused when already there, or
a temporary folder) and re-executes itself with LD_PRELOAD and
OMP_NUM_THREADS=1. Exit 3: /usr/bin/python3 has no open3d module.
"""
import importlib.util
import os
import resource
import shutil
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MARK = "SIMDBVH_O3D_WORKER"  # set in the re-executed worker: the shim is preloaded
NO_OPEN3D = 3


def reexec_with_shim(shim_dir, argv):
    sys.path.insert(0, HERE)
    from shim import build_shim  # scripts/open3d/shim.py

    tmp = None if shim_dir else tempfile.mkdtemp(prefix="simdbvh_o3d_shim_")
    so = build_shim(shim_dir or tmp)
    env = dict(os.environ, OMP_NUM_THREADS="1", **{MARK: tmp or "1"})
    env["LD_PRELOAD"] = so + (" " + env["LD_PRELOAD"] if env.get("LD_PRELOAD") else "")
    os.execve(sys.executable, [sys.executable, os.path.abspath(__file__)] + argv, env)


def write_atomic(path, data):
    part = path + ".part"
    with open(part, "wb") as f:
        f.write(data)
    os.replace(part, path)


def run(jobs):
    import numpy as np
    import open3d as o3d

    scene, scene_mesh = None, None
    for mesh_file, points_file, out in jobs:
        if mesh_file != scene_mesh:
            mesh = o3d.io.read_triangle_mesh(mesh_file)
            verts = np.ascontiguousarray(np.asarray(mesh.vertices), dtype=np.float32)  # float -> double -> float: exact
            tris = np.ascontiguousarray(np.asarray(mesh.triangles), dtype=np.uint32)
            if len(tris) == 0:
                sys.exit(f"inside_worker: {mesh_file}: no triangles")
            scene = o3d.t.geometry.RaycastingScene(nthreads=1)
            scene.add_triangles(o3d.core.Tensor(verts), o3d.core.Tensor(tris))
            scene_mesh = mesh_file
        raw = np.fromfile(points_file, dtype="<f4")
        if raw.size % 3:
            sys.exit(f"inside_worker: {points_file}: size is not a multiple of 12 bytes")
        seconds, inside = 0.0, np.zeros(0, dtype=np.uint8)
        if raw.size:
            q = o3d.core.Tensor(np.ascontiguousarray(raw.reshape(-1, 3)))
            scene.compute_occupancy(q, nthreads=1)  # warm-up; commits the scene
            t0 = time.perf_counter()
            occ = scene.compute_occupancy(q, nthreads=1)
            seconds = time.perf_counter() - t0
            inside = (occ.numpy().reshape(-1) > 0.5).astype(np.uint8)
        write_atomic(out, np.array([seconds], dtype="<f8").tobytes() + inside.tobytes())


def main(argv):
    shim_dir = None
    if argv[:1] == ["--shim-dir"] and len(argv) >= 2:
        shim_dir, argv = argv[1], argv[2:]
    if not argv or len(argv) % 3:
        print(__doc__, file=sys.stderr)
        return 2
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))  # Open3D's aborts leave no core files behind
    if MARK not in os.environ:
        if importlib.util.find_spec("open3d") is None:
            print(f"inside_worker: {sys.executable} cannot import open3d (Debian: python3-open3d)", file=sys.stderr)
            return NO_OPEN3D
        reexec_with_shim(shim_dir, (["--shim-dir", shim_dir] if shim_dir else []) + argv)
    if os.environ[MARK] != "1":
        shutil.rmtree(os.environ[MARK], ignore_errors=True)  # the shim is mapped already
    run([argv[i:i + 3] for i in range(0, len(argv), 3)])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
