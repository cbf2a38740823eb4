#pragma once
// numpy <-> simdbvh conversions for the Python module (shared by module.cpp
// and scene.cpp): N x 3 point arrays, meshes, rays from origins and
// directions, and output arrays; argument checks for threads and isa. Inputs
// are converted to float32 (a copy when the dtype or layout requires it, as
// the docstrings say).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/parallel.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/mesh.h"

namespace simdbvh::python {

namespace py = pybind11;
using namespace pybind11::literals;  // "name"_a = value: the result dicts
using F32 = py::array_t<float, py::array::c_style | py::array::forcecast>;

// A C-contiguous float32 (n, 3) array (forcecast copies other dtypes and layouts).
inline F32 as_points(const py::handle& obj, const char* what) {
    F32 a = F32::ensure(obj);
    if (!a) throw Error(std::string(what) + ": expected an array of numbers");
    if (a.ndim() == 1 && a.shape(0) == 3) a = a.reshape({py::ssize_t(1), py::ssize_t(3)});
    if (a.ndim() != 2 || a.shape(1) != 3) {
        std::string shape;
        for (py::ssize_t k = 0; k < a.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(a.shape(k));
        throw Error(std::string(what) + ": expected shape (n, 3), got (" + shape + ")");
    }
    return a;
}

inline const Vec3* vec3s(const F32& a) { return reinterpret_cast<const Vec3*>(a.data()); }

inline int check_threads(int threads) {
    if (threads < 1 || threads > 1024) throw Error("threads must be 1..1024 (got " + std::to_string(threads) + ")");
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

// A validated mesh from (n, 3) vertices and (m, 3) integer faces (copied).
inline Mesh mesh_from_arrays(const py::handle& vertices, const py::handle& faces) {
    const F32 v = as_points(vertices, "vertices");
    using I64 = py::array_t<long long, py::array::c_style | py::array::forcecast>;
    const I64 f = I64::ensure(faces);
    if (!f || f.ndim() != 2 || f.shape(1) != 3) throw Error("faces: expected an integer array of shape (m, 3)");
    Mesh m;
    m.positions.assign(vec3s(v), vec3s(v) + v.shape(0));
    m.triangles.resize(std::size_t(f.shape(0)));
    const long long* idx = f.data();
    const auto nv = static_cast<long long>(m.positions.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const long long i = idx[3 * t + k];
            if (i < 0 || i >= nv)
                throw Error("faces: triangle " + std::to_string(t) + " has vertex index " + std::to_string(i) +
                            " out of range (" + std::to_string(nv) + " vertices)");
            m.triangles[t][k] = std::uint32_t(i);
        }
    validate(m);
    return m;
}

// One float per ray: a scalar, or an array of n.
inline std::vector<float> per_ray(const py::handle& obj, std::size_t n, const char* what) {
    F32 a = F32::ensure(obj);
    if (!a) throw Error(std::string(what) + ": expected a number or an array of numbers");
    if (a.ndim() == 0) return std::vector<float>(n, a.data()[0]);
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
        throw Error(std::string(what) + ": expected a number or shape (" + std::to_string(n) + ",)");
    return std::vector<float>(a.data(), a.data() + n);
}

inline std::vector<Ray> make_rays(const py::handle& origins, const py::handle& directions, const py::handle& tmin,
                                  const py::handle& tmax) {
    const F32 o = as_points(origins, "origins"), d = as_points(directions, "directions");
    if (o.shape(0) != d.shape(0))
        throw Error("origins and directions differ in length (" + std::to_string(o.shape(0)) + " and " +
                    std::to_string(d.shape(0)) + ")");
    const auto n = std::size_t(o.shape(0));
    const auto lo = per_ray(tmin, n, "tmin"), hi = per_ray(tmax, n, "tmax");
    std::vector<Ray> rays(n);
    for (std::size_t i = 0; i < n; ++i) rays[i] = Ray{vec3s(o)[i], lo[i], vec3s(d)[i], hi[i]};
    return rays;
}

// The rays of origins, directions, tmin and tmax as views of the caller's
// arrays (converted to float32 only when their dtype or layout requires it):
// a batch is traced in chunks built from these views (for_ray_chunks), so no
// array of n Ray records is ever allocated.
class RayArrays {
public:
    RayArrays(const py::handle& origins, const py::handle& directions, const py::handle& tmin,
              const py::handle& tmax)
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
        F32 a = F32::ensure(obj);
        if (!a) throw Error(std::string(what) + ": expected a number or an array of numbers");
        if (a.ndim() == 0) {
            one = a.data()[0];
            return nullptr;
        }
        if (a.ndim() != 1 || std::size_t(a.shape(0)) != n_)
            throw Error(std::string(what) + ": expected a number or shape (" + std::to_string(n_) + ",)");
        keep_.push_back(a);
        return keep_.back().data();
    }
    F32 o_, d_;
    std::vector<F32> keep_;  // tmin, tmax arrays (lo_ and hi_ point into the arrays, not into this vector)
    std::size_t n_ = 0;
    const float *lo_ = nullptr, *hi_ = nullptr;
    float lo1_ = 0.0f, hi1_ = 0.0f;
};

// Rays per chunk: 512 KiB of Ray records and 384 KiB of hits per thread, and at
// least kIsaCalibrationRays (bvh8.h), so a first chunk can still calibrate.
inline constexpr std::size_t kRayChunk = 16384;

// Calls chunk(rays, hits, begin) for consecutive chunks of at most kChunk
// rays (rays[k] is ray begin + k; hits has the same length, for the caller to
// fill and read), spread over `threads`. Call without the GIL; chunk must not
// touch Python objects. Each thread reuses one buffer pair across its chunks.
template <class HitT = Hit, std::size_t kChunk = kRayChunk, class Chunk>
void for_ray_chunks(const RayArrays& in, int threads, Chunk&& chunk) {
    ParallelOptions po;
    po.grain = kChunk;
    parallel_for(in.size(), threads, [&](std::size_t b, std::size_t e) {
        thread_local std::vector<Ray> rays;
        thread_local std::vector<HitT> hits;
        for (std::size_t c = b; c < e; c += kChunk) {
            const std::size_t m = std::min(kChunk, e - c);
            rays.resize(m);
            hits.resize(m);
            for (std::size_t k = 0; k < m; ++k) rays[k] = in[c + k];
            chunk(std::span<const Ray>(rays.data(), m), std::span<HitT>(hits.data(), m), c);
        }
    }, po);
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
// batch (hits[k] is ray begin + k). Call without the GIL; trace and write must
// not touch Python objects.
template <class HitT = Hit, class Trace, class Write>
void for_ray_batches(const RayArrays& in, int threads, Trace&& trace, Write&& write) {
    thread_local std::vector<Ray> rays_kept;
    thread_local std::vector<HitT> hits_kept;
    for (std::size_t c = 0; c < in.size(); c += kRayBatch) {
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
        parallel_for(m, threads, [&](std::size_t b, std::size_t e) {
            write(std::span<const HitT>(hits + b, e - b), c + b);
        });
    }
}

template <class T>
py::array_t<T> empty_array(std::size_t n) {
    return py::array_t<T>(py::ssize_t(n));
}

inline py::array_t<float> empty_points(std::size_t n) {
    return py::array_t<float>({py::ssize_t(n), py::ssize_t(3)});
}

}  // namespace simdbvh::python
