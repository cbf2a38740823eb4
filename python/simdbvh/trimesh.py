"""trimesh's ray interface on simdbvh, switched on in one line:

    mesh.ray = simdbvh.trimesh.RayMeshIntersector(mesh)

Any object with float `vertices` (n, 3) and integer `faces` (m, 3) will do; trimesh itself is not imported.
What differs from trimesh's own engines (docs/python.md, "trimesh"):
- every crossing is counted once: a ray through an edge or a vertex shared by several triangles reports one of
  them (the lowest id at equal t), where stepping past each hit can report two or miss the next surface;
- contains_points is exact (winding number, one ray per point), not a vote of rays;
- coincident duplicate faces are separate crossings at the same t, each reported (sorted by id);
- the mesh and the rays are traced in float32 relative to the mesh's lowest corner, so precision follows the
  mesh's extent, not its distance from the origin; locations are the hit triangle's plane met by the float64
  ray (t in float32 when the ray runs along the plane).
"""
import numpy as np

from ._simdbvh import BVH, Mesh

__all__ = ["RayMeshIntersector"]


def _rays(origins, directions):
    o = np.asarray(origins, dtype=np.float64)
    d = np.asarray(directions, dtype=np.float64)
    if o.ndim == 1:
        o = o.reshape(1, -1)
    if d.ndim == 1:
        d = d.reshape(1, -1)
    if o.shape != d.shape or o.ndim != 2 or o.shape[1] != 3:
        raise ValueError(f"ray origins {o.shape} and directions {d.shape} must both be (n, 3)")
    length = np.linalg.norm(d, axis=1)
    unit = np.divide(d, length[:, None], out=np.zeros_like(d), where=length[:, None] > 0)
    return o, unit


class RayMeshIntersector:
    """Ray queries on a mesh with trimesh's interface. method: the tree ('bvh8', 'bvh4', 'bvh16', 'bvh2',
    'brute'); threads: for every query (0: every core)."""

    def __init__(self, geometry, method="bvh8", threads=0):
        self.mesh = geometry
        self._method = method
        self._threads = int(threads)
        vertices = np.asarray(geometry.vertices, dtype=np.float64)
        faces = np.asarray(geometry.faces, dtype=np.int64)
        if vertices.ndim != 2 or vertices.shape[1] != 3 or len(vertices) == 0:
            raise ValueError(f"vertices: expected a non-empty (n, 3) array, got shape {vertices.shape}")
        self._origin = vertices.min(axis=0)
        self._vertices = vertices
        self._faces = faces
        self._bvh = BVH(Mesh(vertices - self._origin, faces), method=method)

    def __repr__(self):
        return f"simdbvh.trimesh.RayMeshIntersector({len(self._faces)} triangles, method={self._method!r})"

    def __getstate__(self):
        return {"mesh": self.mesh, "method": self._method, "threads": self._threads}

    def __setstate__(self, state):
        self.__init__(state["mesh"], state["method"], state["threads"])

    def _local(self, points):
        return (points - self._origin).astype(np.float32)

    def _locations(self, o, d, tri, t):
        # The hit triangle's plane met by the float64 ray; the traced t where the ray runs along the plane.
        v0, v1, v2 = (self._vertices[self._faces[tri, k]] for k in range(3))
        n = np.cross(v1 - v0, v2 - v0)
        den = np.einsum("ij,ij->i", n, d)
        num = np.einsum("ij,ij->i", n, v0 - o)
        along = np.abs(den) <= 1e-12 * np.linalg.norm(n, axis=1)
        t64 = np.where(along, t.astype(np.float64), num / np.where(along, 1.0, den))
        return o + t64[:, None] * d

    def intersects_id(self, ray_origins, ray_directions, multiple_hits=True, max_hits=100, return_locations=False):
        """Triangles hit: (index_tri, index_ray) int64, plus locations (m, 3) with return_locations. With
        multiple_hits, every hit of a ray up to max_hits, nearest first; else the first."""
        o, d = _rays(ray_origins, ray_directions)
        lo, ld = self._local(o), d.astype(np.float32)
        if multiple_hits:
            if max_hits < 1:
                raise ValueError(f"max_hits must be >= 1 (got {max_hits})")
            r = self._bvh.intersect_all(lo, ld, max_hits=int(max_hits), threads=self._threads)
            index_ray, index_tri, t = r["ray"], r["prim"], r["t"]
        else:
            r = self._bvh.intersect(lo, ld, threads=self._threads)
            index_ray = np.flatnonzero(r["hit"]).astype(np.int64)
            index_tri, t = r["prim"][index_ray], r["t"][index_ray]
        if not return_locations:
            return index_tri, index_ray
        return index_tri, index_ray, self._locations(o[index_ray], d[index_ray], index_tri, t)

    def intersects_location(self, ray_origins, ray_directions, multiple_hits=True):
        """(locations (m, 3), index_ray, index_tri) of the hits."""
        index_tri, index_ray, locations = self.intersects_id(
            ray_origins, ray_directions, multiple_hits=multiple_hits, return_locations=True)
        return locations, index_ray, index_tri

    def intersects_first(self, ray_origins, ray_directions):
        """The first triangle each ray hits, -1 for a miss (int64 per ray)."""
        o, d = _rays(ray_origins, ray_directions)
        return self._bvh.intersect(self._local(o), d.astype(np.float32), threads=self._threads)["prim"]

    def intersects_any(self, ray_origins, ray_directions):
        """Whether each ray hits the mesh (bool per ray)."""
        o, d = _rays(ray_origins, ray_directions)
        return self._bvh.occluded(self._local(o), d.astype(np.float32), threads=self._threads)

    def contains_points(self, points):
        """Exactly inside (winding number; a point on the surface is not inside): bool per point."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        return self._bvh.contains(self._local(p), threads=self._threads)
