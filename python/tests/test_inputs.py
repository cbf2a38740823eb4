"""Every array argument of every function under one rule: real numbers (any integer or floating dtype) for
coordinates, bounds and transforms, integers (any integer dtype, in range) for faces and geometry indices; bool,
complex, string and object arrays are refused with simdbvh.Error naming the argument, never cast (a cast truncates
float indices, drops imaginary parts, parses strings); a conversion that cannot get its memory says so, naming the
argument; an empty built-in mesh is refused like an empty file."""
import os
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import simdbvh

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
F = np.array([[0, 1, 2]])
O = np.array([[0.2, 0.2, 1.0]])
D = np.array([[0.0, 0.0, -1.0]])
SPHERE = np.array([[0.0, 0.0, 0.0, 1.0]])

BAD_REALS = [
    (V + 0j, "complex128", "imaginary"),
    (np.array([["0", "0", "0"]] * 3), "<U1", "strings"),
    (np.ones((3, 3), dtype=bool), "bool", ""),
    (np.array([[0, 0, None]] * 3, dtype=object), "object", "object"),
]


def bvh():
    return simdbvh.BVH(simdbvh.Mesh(V, F))


def scene():
    return simdbvh.Scene(meshes=[(V, F)])


def real_arguments(bad):
    """(label, argument name, call) for every argument that takes real numbers, fed `bad` (3 rows of 3 values)."""
    b4 = np.c_[bad, bad[:, :1]]  # 4 and 6 columns of the same dtype
    b6 = np.c_[bad, bad]
    one = bad[0, 2]  # one value of the dtype (None for the object array)
    row = bad[:1]
    return [
        ("Mesh", "vertices", lambda: simdbvh.Mesh(bad, F)),
        ("BVH.refit", "vertices", lambda: bvh().refit(bad)),
        ("BVH.intersect", "origins", lambda: bvh().intersect(row, D)),
        ("BVH.intersect", "directions", lambda: bvh().intersect(O, row)),
        ("BVH.intersect", "tmin", lambda: bvh().intersect(O, D, tmin=bad[0, :1])),
        ("BVH.intersect", "tmax", lambda: bvh().intersect(O, D, tmax=one)),
        ("BVH.occluded", "origins", lambda: bvh().occluded(row, D)),
        ("BVH.occluded", "tmax", lambda: bvh().occluded(O, D, tmax=bad[0, :1])),
        ("BVH.count_crossings", "directions", lambda: bvh().count_crossings(O, row)),
        ("BVH.count_crossings", "tmin", lambda: bvh().count_crossings(O, D, tmin=one)),
        ("BVH.intersect_all", "origins", lambda: bvh().intersect_all(row, D)),
        ("BVH.intersect_all", "tmax", lambda: bvh().intersect_all(O, D, tmax=one)),
        ("BVH.closest_point", "points", lambda: bvh().closest_point(bad)),
        ("BVH.closest_point", "max_distance", lambda: bvh().closest_point(O, max_distance=one)),
        ("BVH.sides", "points", lambda: bvh().sides(bad)),
        ("BVH.contains", "points", lambda: bvh().contains(bad)),
        ("BVH.signed_distance", "points", lambda: bvh().signed_distance(bad)),
        ("Scene.intersect", "origins", lambda: scene().intersect(row, D)),
        ("Scene.intersect", "tmin", lambda: scene().intersect(O, D, tmin=one)),
        ("Scene.occluded", "directions", lambda: scene().occluded(O, row)),
        ("Scene.occluded", "tmax", lambda: scene().occluded(O, D, tmax=bad[0, :1])),
        ("Scene", r"meshes\[0\]: vertices", lambda: simdbvh.Scene(meshes=[(bad, F)])),
        ("Scene", "spheres", lambda: simdbvh.Scene(spheres=b4)),
        ("Scene", r"spheres\[1\]", lambda: simdbvh.Scene(spheres=[SPHERE, b4])),
        ("Scene", "boxes", lambda: simdbvh.Scene(boxes=b6)),
        ("Scene", "planes", lambda: simdbvh.Scene(spheres=SPHERE, planes=b6)),
        ("Scene", r"instances\[0\].transform",
         lambda: simdbvh.Scene(spheres=SPHERE, instances=[(0, np.c_[bad, bad[:, :1]])])),
    ]


@pytest.mark.parametrize("bad,dtype,why", BAD_REALS, ids=[b[1] for b in BAD_REALS])
def test_real_arguments_refuse_other_kinds(bad, dtype, why):
    """Coordinates, bounds, max_distance and transforms: a bool, complex, string or object array is refused by
    name, not cast to float32 (numpy would drop the imaginary part with a warning, parse the strings, read
    True as 1)."""
    for label, name, call in real_arguments(bad):
        with pytest.raises(simdbvh.Error, match=f"^{name}: expected real numbers, got dtype {re.escape(dtype)}.*{why}"):
            call()
            pytest.fail(f"{label}: {name} of dtype {dtype} accepted")


@pytest.mark.parametrize("bad,dtype,why", [
    (np.array([[0.9, 1.9, 2.9]]), "float64", "truncated"),  # cast: [0, 1, 2], a valid triangle
    (np.array([[0.0, 1.0, 2.0]], dtype=np.float32), "float32", "truncated"),
    (np.array([[0, 1, 2]]) + 0j, "complex128", "imaginary"),
    (np.array([["0", "1", "2"]]), "<U1", "strings"),
    (np.array([[b"0", b"1", b"2"]]), "|S1", "strings"),
    (np.array([[False, True, True]]), "bool", ""),
    (np.array([[0, 1, 2]], dtype=object), "object", "object"),
], ids=["float", "integral-float", "complex", "str", "bytes", "bool", "object"])
def test_faces_must_be_integers(bad, dtype, why):
    for call in (lambda: simdbvh.Mesh(V, bad), lambda: simdbvh.Scene(meshes=[(V, bad)])):
        with pytest.raises(simdbvh.Error, match=f"faces: expected integers, got dtype {re.escape(dtype)}.*{why}"):
            call()


def test_geometry_indices_must_be_integers():
    for index, got in ((0.0, "float64"), (np.float32(0), "float32"), (True, "bool"), ("0", "<U1"), ([0], "shape")):
        with pytest.raises(simdbvh.Error, match=rf"instances\[0\].geometry: expected an integer index, got.*{got}"):
            simdbvh.Scene(spheres=SPHERE, instances=[(index, np.eye(4))])
    for index in (np.uint8(0), np.int16(0), 0):
        assert simdbvh.Scene(spheres=SPHERE, instances=[(index, np.eye(4))]).num_instances == 1


def test_every_integer_dtype_and_layout_is_read_exactly():
    """Faces of any integer dtype, byte order and layout (strided, broadcast, Fortran) give the same mesh;
    vertices and rays of any real dtype are converted to float32 as numpy's astype does."""
    rng = np.random.default_rng(4)
    v = rng.uniform(-1, 1, (200, 3))
    f = rng.integers(0, 120, (300, 3))  # fits int8 .. uint64
    want = simdbvh.Mesh(v, f)
    for dt in ("i1", "u1", "<i2", ">i2", "<u2", ">u4", "<i4", "<i8", ">i8", "<u8", ">u8"):
        m = simdbvh.Mesh(v, f.astype(dt))
        np.testing.assert_array_equal(m.faces, f, err_msg=dt)
        np.testing.assert_array_equal(m.vertices, want.vertices, err_msg=dt)
    np.testing.assert_array_equal(simdbvh.Mesh(v, np.asfortranarray(f)).faces, f)
    np.testing.assert_array_equal(simdbvh.Mesh(v, np.repeat(f, 2, axis=0)[::2]).faces, f)  # strided rows
    np.testing.assert_array_equal(simdbvh.Mesh(v, f[:, ::-1]).faces, f[:, ::-1])  # negative strides
    np.testing.assert_array_equal(simdbvh.Mesh(v, np.broadcast_to(f[7], (5, 3))).faces, np.tile(f[7], (5, 1)))
    for dt in (np.float16, np.float32, ">f8", np.int32, np.uint16, np.longdouble):
        vi = (v * 100).astype(dt)
        np.testing.assert_array_equal(simdbvh.Mesh(vi, f).vertices, vi.astype(np.float32), err_msg=str(dt))
    b = simdbvh.BVH(simdbvh.Mesh(V, F))
    h = b.intersect(np.array([[0.25, 0.25, 1]], dtype=np.float16), np.array([[0, 0, -2]], dtype=np.int8),
                    tmin=np.uint8(0), tmax=np.array([1], dtype=np.float16))
    assert h["hit"][0] and h["t"][0] == 0.5 and h["prim"][0] == 0


def test_indices_out_of_range_are_refused_at_every_width():
    for dt in (np.int8, np.int64, np.uint8, np.uint64):
        big = np.array([[0, 1, 3]], dtype=dt)
        with pytest.raises(simdbvh.Error, match="triangle 0 has vertex index 3 out of range"):
            simdbvh.Mesh(V, big)
    with pytest.raises(simdbvh.Error, match="vertex index -1 out of range"):
        simdbvh.Mesh(V, np.array([[0, 1, -1]], dtype=np.int8))
    with pytest.raises(simdbvh.Error, match="vertex index 18446744073709551615 out of range"):
        simdbvh.Mesh(V, np.array([[0, 1, 2**64 - 1]], dtype=np.uint64))  # not wrapped to -1
    with pytest.raises(simdbvh.Error, match="vertex index 9223372036854775808 out of range"):
        simdbvh.Mesh(V, [[2**63, 2**63, 2**63]])  # a list: numpy reads it as uint64


def test_numpy_cannot_read_it():
    with pytest.raises(simdbvh.Error, match="faces: not an array of numbers"):
        simdbvh.Mesh(V, [[0, 1, 2], [0, 1]])
    with pytest.raises(simdbvh.Error, match="origins: not an array of numbers"):
        bvh().intersect([[0, 0, 1], [0, 0]], D)


def test_conversions_out_of_memory_name_the_argument():
    """10^14 rows of a broadcast array (24 bytes of memory) need petabytes as float32: numpy's MemoryError is
    reported as such, naming the argument (it was 'expected an array of numbers')."""
    huge = np.broadcast_to(np.zeros(3), (10**14, 3))
    huge4 = np.broadcast_to(np.zeros(4), (10**14, 4))
    cases = [
        ("vertices", lambda: simdbvh.Mesh(huge, F)),
        ("vertices", lambda: bvh().refit(huge)),
        ("origins", lambda: bvh().intersect(huge, huge)),
        ("origins", lambda: scene().occluded(huge, huge)),
        ("points", lambda: bvh().contains(huge)),
        ("points", lambda: bvh().closest_point(huge)),
        ("spheres", lambda: simdbvh.Scene(spheres=huge4)),
    ]
    for name, call in cases:
        with pytest.raises(simdbvh.Error, match=rf"^{name}: out of memory converting \(100000000000000, [34]\) "
                                                r"float64 to C-contiguous float32 \(1\.[26] PB\)"):
            call()
    with pytest.raises(simdbvh.Error, match="faces: 100000000000000 rows, more than a mesh's 4294967294 triangles"):
        simdbvh.Mesh(V, np.broadcast_to(np.array([0, 1, 2]), (10**14, 3)))


def test_broadcast_faces_beyond_the_memory_limit(tmp_path):
    """10^9 broadcast face rows (the mesh would need 12 GB) in a process whose address space is limited to
    1.5 GB more than it uses: a simdbvh.Error naming faces and the memory (it was 'expected an integer array of
    shape (m, 3)'), as for 10^9 rows of vertices, origins and points; the process goes on."""
    script = textwrap.dedent("""
        import resource, numpy as np, simdbvh
        vm = next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmSize:")) * 1024
        resource.setrlimit(resource.RLIMIT_AS, (vm + (1500 << 20), resource.getrlimit(resource.RLIMIT_AS)[1]))
        V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
        rows = np.broadcast_to(np.array([0, 1, 2]), (10**9, 3))
        pts = np.broadcast_to(np.zeros(3), (10**9, 3))
        bvh = simdbvh.BVH(simdbvh.Mesh(V, [[0, 1, 2]]))
        for call in (lambda: simdbvh.Mesh(V, rows), lambda: simdbvh.Mesh(pts, [[0, 1, 2]]),
                     lambda: bvh.intersect(pts, pts), lambda: bvh.sides(pts)):
            try:
                call()
                print("accepted")
            except simdbvh.Error as e:
                print(e)
        print(bvh.intersect([[0.2, 0.2, 1]], [[0, 0, -1]])["t"][0])
    """)
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60,
                       env=dict(os.environ))
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    assert lines[0] == "faces: out of memory for 1000000000 triangles (12.0 GB)", r.stdout
    assert lines[1] == "vertices: out of memory converting (1000000000, 3) float64 to C-contiguous float32 (12.0 GB)"
    assert lines[2].startswith("origins: out of memory converting (1000000000, 3) float64"), r.stdout
    assert lines[3].startswith("points: out of memory converting (1000000000, 3) float64"), r.stdout
    assert lines[4] == "1.0"


def test_an_empty_mesh_is_refused_like_an_empty_file(tmp_path):
    """soup-0 built an empty mesh without a word; a file with vertices and no face likewise. An empty file was
    already refused. Meshes from arrays may be empty (every ray misses)."""
    (tmp_path / "empty.obj").write_text("")
    (tmp_path / "points.obj").write_text("v 0 0 0\nv 1 0 0\n")
    for load in (simdbvh.load, simdbvh.load_scene):
        with pytest.raises(simdbvh.Error, match="empty"):
            load(str(tmp_path / "empty.obj"))
        with pytest.raises(simdbvh.Error, match="^soup-0: no triangles"):
            load("soup-0")
        with pytest.raises(simdbvh.Error, match="points.obj: no triangles"):
            load(str(tmp_path / "points.obj"))
    assert len(simdbvh.load("soup-5")) == 5
    assert simdbvh.load_scene("soup-5").num_geometries == 1
    empty = simdbvh.BVH(simdbvh.Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int32)))
    assert not empty.intersect(O, D)["hit"][0]
