"""simdbvh: exact, fast ray and point queries against triangle meshes.

    import numpy as np, simdbvh
    mesh = simdbvh.Mesh(vertices, faces)          # or simdbvh.load("bunny.ply")
    bvh = simdbvh.BVH(mesh)                       # method="bvh8" | "bvh4" | "bvh16" | "bvh2" | "brute", isa=None | "avx2" | ...
    hits = bvh.intersect(origins, directions)     # dict: hit, t, prim, u, v
    inside = bvh.contains(points)                 # exact, one ray per point
    d = bvh.signed_distance(points)               # negative inside

    scene = simdbvh.load_scene("room")            # or simdbvh.Scene(meshes=[mesh], spheres=..., instances=..., planes=...)
    hits = scene.intersect(origins, directions)   # dict: hit, t, u, v, prim, geom, inst

Errors raise simdbvh.Error (a ValueError) with the library's message. Array arguments take real numbers
(faces: integers) of any numpy dtype of that kind; bool, complex, string and object arrays are refused, not cast.
"""
from ._simdbvh import BVH, Error, Mesh, Scene, isas, load, load_bvh, load_scene

__all__ = ["BVH", "Error", "Mesh", "Scene", "isas", "load", "load_bvh", "load_scene"]
