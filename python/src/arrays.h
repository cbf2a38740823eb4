#pragma once
// numpy <-> simdbvh conversions for the Python module (shared by module.cpp
// and scene.cpp): N x 3 point arrays, meshes, rays from origins and
// directions, and output arrays; argument checks for threads, isa and paths.
// Inputs are converted to float32 (a copy when the dtype or layout requires
// it, as the docstrings say).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <new>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "interrupt.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"
#include "simdbvh/platform/topology.h"

namespace simdbvh::python {

namespace py = pybind11;
using namespace pybind11::literals;  // "name"_a = value: the result dicts
using F32 = py::array_t<float, py::array::c_style | py::array::forcecast>;

// Every array argument goes through numpy.asarray and is checked before it is
// converted: real numbers (any integer or floating dtype) for coordinates and
// bounds, integers (any integer dtype) for faces; bool, complex, string and
// object arrays are refused rather than cast (a cast truncates floats to
// indices, drops imaginary parts, parses strings), and a conversion that runs
// out of memory is reported as such, naming the argument.

inline std::string shape_of(const py::array& a) {
    std::string s;
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
    return "(" + s + (a.ndim() == 1 ? ",)" : ")");
}

inline std::string dtype_of(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

// "12.0 GB" for a byte count (the size a conversion or an allocation needed).
inline std::string bytes_text(double bytes) {
    const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
    int u = 0;
    while (bytes >= 1000.0 && u < 6) bytes /= 1000.0, ++u;
    char buf[32];
    std::snprintf(buf, sizeof buf, u ? "%.1f %s" : "%.0f %s", bytes, units[u]);
    return buf;
}

// numpy.asarray(obj) (numpy's PyArray_FromAny, without a dtype: nothing cast),
// or nullptr with the Python error set.
inline py::array try_numpy(const py::handle& obj) {
    namespace d = py::detail;
    return py::reinterpret_steal<py::array>(
        d::npy_api::get().PyArray_FromAny_(obj.ptr(), nullptr, 0, 0, d::npy_api::NPY_ARRAY_ENSUREARRAY_, nullptr));
}

// numpy.asarray(obj), its errors (a ragged list, an object numpy cannot read) as simdbvh.Error naming `what`.
inline py::array as_numpy(const py::handle& obj, const std::string& what) {
    py::array a = try_numpy(obj);
    if (a) return a;
    py::error_already_set e;
    if (e.matches(PyExc_MemoryError)) throw Error(what + ": out of memory reading it as an array");
    throw Error(what + ": not an array of numbers (" + py::str(e.value()).cast<std::string>() + ")");
}

enum class Numbers { reals, integers };

// Refuses a dtype whose conversion would lose or invent information.
inline void check_dtype(const py::array& a, Numbers want, const std::string& what) {
    const char k = a.dtype().kind();
    if (k == 'i' || k == 'u' || (k == 'f' && want == Numbers::reals)) return;
    const char* why = k == 'f'               ? " (indices would be truncated)"
                      : k == 'c'             ? " (the imaginary parts would be dropped)"
                      : k == 'b'             ? ""
                      : k == 'U' || k == 'S' ? " (strings are not parsed)"
                      : k == 'O'             ? " (objects: a ragged or mixed list?)"
                                             : "";
    throw Error(what + ": expected " + (want == Numbers::integers ? "integers" : "real numbers") + ", got dtype " +
                dtype_of(a) + why);
}

// a as a C-contiguous array of T (a itself when it already is one), an allocation failure reported naming `what`.
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> convert(const py::array& a, const std::string& what) {
    using Out = py::array_t<T, py::array::c_style | py::array::forcecast>;
    try {
        return Out(a);
    } catch (py::error_already_set& e) {
        if (!e.matches(PyExc_MemoryError)) throw;
        throw Error(what + ": out of memory converting " + shape_of(a) + " " + dtype_of(a) + " to C-contiguous " +
                    py::str(py::dtype::of<T>()).cast<std::string>() + " (" + bytes_text(double(a.size()) * sizeof(T)) +
                    ")");
    }
}

// A C-contiguous float32 (n, cols) array of real numbers; a 1-D array of cols numbers is one row.
inline F32 as_rows(const py::handle& obj, py::ssize_t cols, const std::string& what) {
    const py::array a = as_numpy(obj, what);
    check_dtype(a, Numbers::reals, what);
    const bool one_row = a.ndim() == 1 && a.shape(0) == cols;
    if (!one_row && (a.ndim() != 2 || a.shape(1) != cols))
        throw Error(what + ": expected shape (n, " + std::to_string(cols) + "), got " + shape_of(a));
    F32 f = convert<float>(a, what);
    if (one_row) f = f.reshape({py::ssize_t(1), cols});
    return f;
}

// A C-contiguous float32 (n, 3) array (a copy when the dtype or layout requires it).
inline F32 as_points(const py::handle& obj, const std::string& what) { return as_rows(obj, 3, what); }

// One float per ray: a number (0-d) or an array of n, C-contiguous float32.
inline F32 as_per_ray(const py::handle& obj, std::size_t n, const std::string& what) {
    const py::array a = as_numpy(obj, what);
    check_dtype(a, Numbers::reals, what);
    if (a.ndim() != 0 && (a.ndim() != 1 || std::size_t(a.shape(0)) != n))
        throw Error(what + ": expected a number or shape (" + std::to_string(n) + ",), got " + shape_of(a));
    return convert<float>(a, what);
}

// A real number (e.g. max_distance) under the array arguments' rules.
inline float real_arg(const py::handle& obj, const std::string& what) {
    const py::array a = as_numpy(obj, what);
    check_dtype(a, Numbers::reals, what);
    if (a.ndim() != 0) throw Error(what + ": expected a number, got shape " + shape_of(a));
    return convert<float>(a, what).data()[0];
}

inline const Vec3* vec3s(const F32& a) { return reinterpret_cast<const Vec3*>(a.data()); }

// threads= of every query: 1..1024, or 0 for every hardware thread of the
// machine (as Open3D reads it).
inline int check_threads(int threads) {
    if (threads == 0) return std::clamp(topology().logical_cpus, 1, 1024);
    if (threads < 1 || threads > 1024)
        throw Error("threads must be 0 (every core) or 1..1024 (got " + std::to_string(threads) + ")");
    return threads;
}

// A path or name for the C++ loaders: they read it as a C string, which would
// end at an embedded NUL (Python strings may hold one) and open another file.
inline const std::string& path_arg(const std::string& path, const char* what) {
    if (const auto at = path.find('\0'); at != std::string::npos)
        throw Error(std::string(what) + " contains a NUL byte (at character " + std::to_string(at) + ")");
    return path;
}

// isa=None -> nullopt (the caller's default); a name -> that ISA, checked against the CPU.
inline std::optional<Isa> isa_arg(const std::optional<std::string>& isa) {
    if (!isa) return std::nullopt;
    const auto parsed = parse_isa(*isa);
    if (!parsed) throw Error("isa must be 'scalar', 'avx2' or 'avx512' (got '" + *isa + "')");
    require(*parsed);
    return parsed;
}

// The (m, 3) faces of any integer dtype read in place through their strides
// (a broadcast array is not copied), each index checked against nv vertices.
template <class I>
void read_faces(const py::array& f, std::size_t nv, std::vector<Triangle>& out) {
    const auto* base = static_cast<const char*>(f.data());
    const py::ssize_t s0 = f.strides(0), s1 = f.strides(1);
    for (std::size_t t = 0; t < out.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            I i;
            std::memcpy(&i, base + py::ssize_t(t) * s0 + k * s1, sizeof i);
            bool bad = std::uint64_t(i) >= nv;
            if constexpr (std::is_signed_v<I>) bad = i < 0 || bad;
            if (bad)
                throw Error("faces: triangle " + std::to_string(t) + " has vertex index " + std::to_string(i) +
                            " out of range (" + std::to_string(nv) + " vertices)");
            out[t][k] = std::uint32_t(i);
        }
}

// A validated mesh from (n, 3) vertices of real numbers and (m, 3) faces of integers (copied).
inline Mesh mesh_from_arrays(const py::handle& vertices, const py::handle& faces) {
    const F32 v = as_points(vertices, "vertices");
    py::array f = as_numpy(faces, "faces");
    check_dtype(f, Numbers::integers, "faces");
    if (f.ndim() != 2 || f.shape(1) != 3) throw Error("faces: expected shape (m, 3), got " + shape_of(f));
    const auto m = std::size_t(f.shape(0));
    if (m >= kMaxTriangles)
        throw Error("faces: " + std::to_string(m) + " rows, more than a mesh's " + std::to_string(kMaxTriangles - 1) +
                    " triangles");
    if (!f.dtype().attr("isnative").cast<bool>()) {  // another byte order: converted (rare)
        if (f.dtype().kind() == 'u') f = convert<std::uint64_t>(f, "faces");
        else f = convert<std::int64_t>(f, "faces");
    }
    Mesh mesh;
    try {
        mesh.positions.assign(vec3s(v), vec3s(v) + v.shape(0));
    } catch (const std::bad_alloc&) {
        throw Error("vertices: out of memory for " + std::to_string(v.shape(0)) + " vertices (" +
                    bytes_text(double(v.shape(0)) * sizeof(Vec3)) + ")");
    }
    try {
        mesh.triangles.resize(m);
    } catch (const std::bad_alloc&) {
        throw Error("faces: out of memory for " + std::to_string(m) + " triangles (" +
                    bytes_text(double(m) * sizeof(Triangle)) + ")");
    }
    const std::size_t nv = mesh.positions.size();
    const bool u = f.dtype().kind() == 'u';
    auto& tris = mesh.triangles;
    switch (f.itemsize()) {
    case 1: u ? read_faces<std::uint8_t>(f, nv, tris) : read_faces<std::int8_t>(f, nv, tris); break;
    case 2: u ? read_faces<std::uint16_t>(f, nv, tris) : read_faces<std::int16_t>(f, nv, tris); break;
    case 4: u ? read_faces<std::uint32_t>(f, nv, tris) : read_faces<std::int32_t>(f, nv, tris); break;
    case 8: u ? read_faces<std::uint64_t>(f, nv, tris) : read_faces<std::int64_t>(f, nv, tris); break;
    default: throw Error("faces: unsupported integer dtype " + dtype_of(f));
    }
    validate(mesh);
    return mesh;
}

// The rays of origins, directions, tmin and tmax as views of the caller's
// arrays (converted to float32 only when their dtype or layout requires it):
// a batch is traced in chunks built from these views (for_ray_chunks), so no
// array of n Ray records is ever allocated.
class RayArrays {
public:
    RayArrays(const py::handle& origins, const py::handle& directions, const py::handle& tmin, const py::handle& tmax)
        : o_(as_points(origins, "origins")), d_(as_points(directions, "directions")) {
        if (o_.shape(0) != d_.shape(0))
            throw Error("origins and directions differ in length (" + std::to_string(o_.shape(0)) + " and " +
                        std::to_string(d_.shape(0)) + ")");
        n_ = std::size_t(o_.shape(0));
        lo_ = bound(tmin, "tmin", lo1_);
        hi_ = bound(tmax, "tmax", hi1_);
    }
    std::size_t size() const { return n_; }
    // Safe without the GIL (reads the arrays' memory only).
    Ray operator[](std::size_t i) const {
        return Ray{vec3s(o_)[i], lo_ ? lo_[i] : lo1_, vec3s(d_)[i], hi_ ? hi_[i] : hi1_};
    }

private:
    // A scalar (returns nullptr, the value in `one`) or an array of n (kept alive in keep_).
    const float* bound(const py::handle& obj, const char* what, float& one) {
        if (PyFloat_CheckExact(obj.ptr())) {  // the defaults and most calls: as numpy would cast it, no array made
            one = float(PyFloat_AS_DOUBLE(obj.ptr()));
            return nullptr;
        }
        F32 a = as_per_ray(obj, n_, what);
        if (a.ndim() == 0) {
            one = a.data()[0];
            return nullptr;
        }
        keep_.push_back(a);
        return keep_.back().data();
    }
    F32 o_, d_;
    std::vector<F32> keep_;  // tmin, tmax arrays (lo_ and hi_ point into the arrays, not into this vector)
    std::size_t n_ = 0;
    const float *lo_ = nullptr, *hi_ = nullptr;
    float lo1_ = 0.0f, hi1_ = 0.0f;
};

// The rays as one vector of Ray records (the queries that take all of them at once).
inline std::vector<Ray> make_rays(const py::handle& origins, const py::handle& directions, const py::handle& tmin,
                                  const py::handle& tmax) {
    const RayArrays in(origins, directions, tmin, tmax);
    std::vector<Ray> rays(in.size());
    for (std::size_t i = 0; i < rays.size(); ++i) rays[i] = in[i];
    return rays;
}

// Rays per chunk: 512 KiB of Ray records and 384 KiB of hits per thread, and at
// least kIsaCalibrationRays (bvh8.h), so a first chunk can still calibrate.
inline constexpr std::size_t kRayChunk = 16384;

// Rays per chunk of a brute-force trace: each ray tests every triangle, so
// interrupts are checked after a few hundred rays.
inline constexpr std::size_t kBruteChunk = 256;

// Calls chunk(rays, hits, begin) for consecutive chunks of at most kChunk
// rays (rays[k] is ray begin + k; hits has the same length, for the caller to
// fill and read), spread over `threads`; none after `interrupt` stops. Call
// without the GIL; chunk must not touch Python objects. Each thread reuses one
// buffer pair across its chunks.
template <class HitT = Hit, std::size_t kChunk = kRayChunk, class Chunk>
void for_ray_chunks(const RayArrays& in, int threads, Interrupt& interrupt, Chunk&& chunk) {
    ParallelOptions po;
    po.grain = kChunk;
    parallel_for(
        in.size(), threads,
        [&](std::size_t b, std::size_t e) {
            thread_local std::vector<Ray> rays;
            thread_local std::vector<HitT> hits;
            for (std::size_t c = b; c < e; c += kChunk) {
                if (interrupt.stop()) return;
                const std::size_t m = std::min(kChunk, e - c);
                rays.resize(m);
                hits.resize(m);
                for (std::size_t k = 0; k < m; ++k) rays[k] = in[c + k];
                chunk(std::span<const Ray>(rays.data(), m), std::span<HitT>(hits.data(), m), c);
            }
        },
        po);
}

// Rays per batch of for_ray_batches: 32 MiB of Ray records and 16 MiB of
// hits, kept by the calling thread for its next call (made per call, their
// page faults cost the dragon's 2^20 bounces 12% on two threads), the
// library's largest sorted segment.
inline constexpr std::size_t kRayBatch = std::size_t(1) << 20;

// For a wide tree's batch that the library sorts (traces_sorted,
// simdbvh/bvh8/batch_order.h; in for_ray_chunks' 16,384-ray chunks diffuse
// bounces are too sparse to gain from it): for consecutive batches of at most
// kRayBatch rays, the Ray records built from the views (over `threads`),
// trace(rays, hits) once on the calling thread (the library spreads the batch
// over the threads), then write(hits, begin) over `threads` for ranges of the
// batch (hits[k] is ray begin + k); none after `interrupt` stops (checked
// between batches). Call without the GIL; trace and write must not touch
// Python objects.
template <class HitT = Hit, class Trace, class Write>
void for_ray_batches(const RayArrays& in, int threads, Interrupt& interrupt, Trace&& trace, Write&& write) {
    thread_local std::vector<Ray> rays_kept;
    thread_local std::vector<HitT> hits_kept;
    for (std::size_t c = 0; c < in.size() && !interrupt.stop(); c += kRayBatch) {
        const std::size_t m = std::min(kRayBatch, in.size() - c);
        rays_kept.resize(m);
        hits_kept.resize(m);
        // The calling thread's buffers (a thread_local named inside the workers' lambdas would be theirs).
        Ray* const rays = rays_kept.data();
        HitT* const hits = hits_kept.data();
        parallel_for(m, threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t k = b; k < e; ++k) rays[k] = in[c + k];
        });
        trace(std::span<const Ray>(rays, m), std::span<HitT>(hits, m));
        parallel_for(m, threads,
                     [&](std::size_t b, std::size_t e) { write(std::span<const HitT>(hits + b, e - b), c + b); });
    }
}

template <class T>
py::array_t<T> empty_array(std::size_t n) {
    return py::array_t<T>(py::ssize_t(n));
}

inline py::array_t<float> empty_points(std::size_t n) { return py::array_t<float>({py::ssize_t(n), py::ssize_t(3)}); }

}  // namespace simdbvh::python
