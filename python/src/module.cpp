// simdbvh for Python: meshes from numpy arrays, batched ray and point queries
// on numpy arrays with the GIL released. Errors raise simdbvh.Error (a
// ValueError) with the library's message. Scenes (instances, spheres, boxes,
// planes) are bound in scene.cpp.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <variant>
#include <vector>

#include "arrays.h"
#include "point_blocks.h"
#include "rw_lock.h"
#include "simdbvh/accel/cost_model.h"
#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/crossings.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/bvh8/batch_order.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/query/closest_point_wide.h"
#include "simdbvh/query/inside_wide.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/io/output.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/store/store.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::python {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// At most this many points (or rays) per library call of a batched point
// query or crossing count when interrupts are checked between the calls
// (for_blocks: blocks of about a quarter of a second; each call spreads its
// block over the threads and ends when its last chunk does; point blocks are
// runs of the batch's Morton order, point_blocks.h).
constexpr std::size_t kPointBlock = std::size_t(1) << 20;

InsideOptions::Rule parse_rule(const std::string& r) {
    if (r == "winding") return InsideOptions::Rule::winding;
    if (r == "parity") return InsideOptions::Rule::parity;
    throw Error("rule must be 'winding' or 'parity' (got '" + r + "')");
}

class Bvh {
public:
    Bvh(Mesh mesh, const std::string& method, const std::optional<std::string>& isa)
        : mesh_(std::move(mesh)), method_(method) {
        const auto m = parse_accel_method(method_);
        if (!m || *m == AccelMethod::brute8)
            throw Error("method must be " + method_names([](AccelMethod a) { return a != AccelMethod::brute8; }) +
                        " (got '" + method_ + "')");
        width_ = tree_width(*m);
        if (const auto parsed = isa_arg(isa)) {
            isa_ = *parsed;
        } else {
            isa_ = active_isa();
            isa_auto_ = true;
        }
        py::gil_scoped_release nogil;
        // The wide trees build straight from the mesh (Bvh8::build(mesh), the build docs/results.md measures), not from a
        // BVH2 built first and kept: docs/open3d.md has the dragon's build through this module both ways.
        if (width_ > 2) with_width(width_, [&](auto n) { wide_ = BvhN<decltype(n)::value>::build(mesh_); });
        else if (width_ == 2) bvh2();
    }

    // A tree saved by save() (docs/saved_format.md), from a file (mapped) or from pickled bytes: nothing is
    // built; the mesh comes from the file.
    static std::unique_ptr<Bvh> load_saved(const std::string& path, const py::bytes* bytes,
                                           const std::optional<std::string>& isa, bool verify) {
        std::span<const unsigned char> data;
        if (bytes) {
            char* p = nullptr;
            Py_ssize_t n = 0;
            if (PyBytes_AsStringAndSize(bytes->ptr(), &p, &n) != 0) throw py::error_already_set();
            data = {reinterpret_cast<const unsigned char*>(p), std::size_t(n)};
        }
        const std::string what = bytes ? std::string("pickled BVH") : path;
        const LoadOptions opts{.map = true, .verify = verify};
        std::unique_ptr<Bvh> b;
        {
            py::gil_scoped_release nogil;
            const SavedInfo info = bytes ? inspect_bytes(data, what) : inspect(path);
            b.reset(new Bvh("bvh" + std::to_string(info.width), isa));
            auto take = [&](auto saved) {
                b->mesh_ = std::move(saved.mesh);
                return std::move(saved.bvh);
            };
            if (info.width == 2) {
                b->bvh2_ = take(bytes ? load_bytes<Bvh2>(data, what, opts) : load_with_mesh<Bvh2>(path, opts));
                std::call_once(b->bvh2_once_, [] {});
                b->bvh2_built_ = true;
            } else {
                with_width(info.width, [&](auto n) {
                    using Tree = BvhN<decltype(n)::value>;
                    b->wide_ = take(bytes ? load_bytes<Tree>(data, what, opts) : load_with_mesh<Tree>(path, opts));
                });
            }
        }
        return b;
    }

    // The saved bytes of this BVH's tree and mesh (docs/saved_format.md); 'brute' has no tree.
    std::vector<unsigned char> saved_bytes() const {
        if (method_ == "brute") throw Error("a 'brute' BVH has no tree to save (use method 'bvh8', 'bvh2', ...)");
        py::gil_scoped_release nogil;
        const std::shared_lock<RwLock> hold(lock_);  // the tree and the vertices of one refit
        if (width_ <= 2) return save_bytes(bvh2(), mesh_);
        std::vector<unsigned char> out;
        visit_wide([&](const auto& tree) { out = save_bytes(tree, mesh_); });
        return out;
    }
    std::optional<std::string> isa_arg_given() const {
        return isa_auto_ ? std::nullopt : std::optional<std::string>(std::string(name(isa_)));
    }

    // The BVH2 of count and all (and of method 'bvh2'): built on first use, once, from the current vertices.
    const Bvh2& bvh2() const {
        std::call_once(bvh2_once_, [&] {
            bvh2_ = Bvh2::build(mesh_);
            bvh2_built_ = true;
        });
        return bvh2_;
    }

    py::dict intersect(const py::handle& o, const py::handle& d, const py::handle& tmin, const py::handle& tmax,
                       int threads, bool any, bool points = false, bool normals = false) const {
        const RayArrays rays(o, d, tmin, tmax);
        const std::size_t n = rays.size();
        auto t = empty_array<float>(n), u = empty_array<float>(n), v = empty_array<float>(n);
        auto prim = empty_array<std::int64_t>(n);
        auto hit = empty_array<bool>(n);
        float *pt = t.mutable_data(), *pu = u.mutable_data(), *pv = v.mutable_data();
        std::int64_t* pprim = prim.mutable_data();
        bool* phit = hit.mutable_data();
        std::vector<Hit> all(points || normals ? n : 0);  // the rows below need every hit
        py::array_t<float> pts = empty_points(points ? n : 0), nrm = empty_points(normals ? n : 0);
        const int nthreads = check_threads(threads);
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            const std::shared_lock<RwLock> hold(lock_);
            auto write = [&](std::span<const Hit> h, std::size_t b) {
                for (std::size_t k = 0; k < h.size(); ++k) {
                    const std::size_t i = b + k;
                    pt[i] = h[k].t;
                    pu[i] = h[k].u;
                    pv[i] = h[k].v;
                    pprim[i] = h[k].hit() ? std::int64_t(h[k].prim) : -1;
                    phit[i] = h[k].hit();
                }
                if (!all.empty()) std::copy(h.begin(), h.end(), all.begin() + std::ptrdiff_t(b));
            };
            if (width_ > 2) {
                auto wide = [&](const auto& bvh) {
                    auto trace = [&](std::span<const Ray> r, std::span<Hit> h, const TraceOptions& opts) {
                        if (any) occluded(bvh, r, h, opts);
                        else simdbvh::intersect(bvh, r, h, opts);
                    };
                    TraceOptions opts;  // automatic order: the library's rule, asked once here
                    // isa=None: chosen by speed (bvh8.h), or the forced SIMDBVH_ISA.
                    if (!isa_auto_) opts.isa = isa_;
                    if (traces_sorted(
                            bvh, n, [&](std::size_t i) { return rays[i]; }, opts)) {
                        // Whole batches, sorted (decided: not asked again per batch) and spread over the
                        // threads by the library.
                        opts.reorder = Reorder::on;
                        opts.threads = nthreads;
                        for_ray_batches(
                            rays, nthreads, interrupt,
                            [&](std::span<const Ray> r, std::span<Hit> h) { trace(r, h, opts); }, write);
                    } else {
                        // Chunks spread over the threads, each traced on one, converted just before.
                        opts.reorder = Reorder::off;
                        for_ray_chunks(rays, nthreads, interrupt,
                                       [&](std::span<const Ray> r, std::span<Hit> h, std::size_t b) {
                                           trace(r, h, opts);
                                           write(h, b);
                                       });
                    }
                };
                visit_wide(wide);
            } else if (method_ == "bvh2") {
                // The chunks are spread over the threads; each traces on one.
                for_ray_chunks(rays, nthreads, interrupt, [&](std::span<const Ray> r, std::span<Hit> h, std::size_t b) {
                    if (any) simdbvh::occluded(bvh2(), r, h);
                    else simdbvh::intersect(bvh2(), r, h);
                    write(h, b);
                });
            } else {
                for_ray_chunks<Hit, kBruteChunk>(
                    rays, nthreads, interrupt, [&](std::span<const Ray> r, std::span<Hit> h, std::size_t b) {
                        for (std::size_t i = 0; i < r.size(); ++i)
                            h[i] = any ? brute_force_occluded(mesh_, r[i]) : brute_force_intersect(mesh_, r[i]);
                        write(h, b);
                    });
            }
            // The rows read the vertices: under the same hold as the trace.
            if (points && !interrupt.stop()) hit_points(all, pts.mutable_data());
            if (normals && !interrupt.stop()) hit_normals(all, nrm.mutable_data());
        }
        interrupt.raise_if_stopped();
        py::dict out("hit"_a = hit, "t"_a = t, "prim"_a = prim, "u"_a = u, "v"_a = v);
        if (points) out["points"] = pts;
        if (normals) out["normals"] = nrm;
        return out;
    }

    // Rows of 3 floats from `out`: row(hit, out) for each hit, NaN rows for misses.
    template <class Row>
    static void hit_rows(const std::vector<Hit>& hits, float* p, Row row) {
        for (std::size_t i = 0; i < hits.size(); ++i, p += 3) {
            if (hits[i].hit()) row(hits[i], p);
            else p[0] = p[1] = p[2] = std::numeric_limits<float>::quiet_NaN();
        }
    }
    // (1 - u - v) v0 + u v1 + v v2 in double, rounded once: on the hit triangle
    // (origin + t * direction can miss its plane by the rounding of t).
    void hit_points(const std::vector<Hit>& hits, float* out) const {
        hit_rows(hits, out, [&](const Hit& h, float* p) {
            const double w = 1.0 - double(h.u) - double(h.v);
            for (int k = 0; k < 3; ++k)
                p[k] = float(w * mesh_.vertex(h.prim, 0)[k] + double(h.u) * mesh_.vertex(h.prim, 1)[k] +
                             double(h.v) * mesh_.vertex(h.prim, 2)[k]);
        });
    }
    // Unit geometric normal (v1 - v0) x (v2 - v0) in double, by the triangle's
    // winding (not turned toward the ray).
    void hit_normals(const std::vector<Hit>& hits, float* out) const {
        hit_rows(hits, out, [&](const Hit& h, float* p) {
            double e1[3], e2[3];
            for (int k = 0; k < 3; ++k) {
                e1[k] = double(mesh_.vertex(h.prim, 1)[k]) - mesh_.vertex(h.prim, 0)[k];
                e2[k] = double(mesh_.vertex(h.prim, 2)[k]) - mesh_.vertex(h.prim, 0)[k];
            }
            const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
            const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int k = 0; k < 3; ++k) p[k] = len > 0 ? float(n[k] / len) : 0.0f;
        });
    }

    // Without the GIL, holding lock_: the closest points of p, in blocks (interrupts checked between them).
    void closest_points(const F32& p, float max_distance, int threads, std::vector<ClosestPoint>& res,
                        Interrupt& interrupt) const {
        const auto n = std::size_t(p.shape(0));
        PointQueryOptions o;
        o.max_distance = max_distance;
        o.threads = threads;
        if (method_ == "brute") {
            for_blocks(n, kPointBlock, interrupt, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) res[i] = brute_force_closest_point(mesh_, vec3s(p)[i], o);
            });
            return;
        }
        for_point_blocks(std::span<const Vec3>(vec3s(p), n), std::span<ClosestPoint>(res), kPointBlock, interrupt,
                         [&](std::span<const Vec3> in, std::span<ClosestPoint> out) {
                             with_tree([&](const auto& t) { closest_point(t, in, out, o); });
                         });
    }

    // Without the GIL, holding lock_: the sides of p, in blocks (interrupts checked between them).
    void classify(const F32& p, const InsideOptions& o, std::vector<PointSide>& res, Interrupt& interrupt) const {
        const auto n = std::size_t(p.shape(0));
        if (method_ == "brute") {
            for_blocks(n, kPointBlock, interrupt, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) res[i] = brute_force_classify_point(mesh_, vec3s(p)[i], o);
            });
            return;
        }
        for_point_blocks(std::span<const Vec3>(vec3s(p), n), std::span<PointSide>(res), kPointBlock, interrupt,
                         [&](std::span<const Vec3> in, std::span<PointSide> out) {
                             with_tree([&](const auto& t) { classify_points(t, in, out, o); });
                         });
    }

    py::dict closest(const py::handle& points, const py::handle& max_distance, int threads) const {
        const F32 p = as_points(points, "points");
        const float max_d = real_arg(max_distance, "max_distance");
        const int nthreads = check_threads(threads);
        const auto n = std::size_t(p.shape(0));
        std::vector<ClosestPoint> res(n);
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            const std::shared_lock<RwLock> hold(lock_);
            closest_points(p, max_d, nthreads, res, interrupt);
        }
        interrupt.raise_if_stopped();
        auto dist = empty_array<float>(n), u = empty_array<float>(n), v = empty_array<float>(n);
        auto prim = empty_array<std::int64_t>(n);
        auto pts = empty_points(n);
        for (std::size_t i = 0; i < n; ++i) {
            dist.mutable_data()[i] = res[i].distance;
            prim.mutable_data()[i] = res[i].found() ? std::int64_t(res[i].prim) : -1;
            u.mutable_data()[i] = res[i].u;
            v.mutable_data()[i] = res[i].v;
            for (int k = 0; k < 3; ++k) pts.mutable_data()[3 * i + k] = res[i].point[k];
        }
        return py::dict("distance"_a = dist, "prim"_a = prim, "points"_a = pts, "u"_a = u, "v"_a = v);
    }

    // The point queries' tree: the mesh's wide tree when it has one (the same
    // answers as the BVH2, faster: bench/bvh8), else the BVH2.
    template <class F>
    void with_tree(F&& f) const {
        if (width_ > 2) visit_wide(f);
        else f(bvh2());
    }

    static InsideOptions inside_options(const std::string& rule, int threads, const std::string& ray) {
        InsideOptions o;
        o.rule = parse_rule(rule);
        o.ray = count_ray_named(ray);
        o.threads = check_threads(threads);
        return o;
    }

    std::vector<PointSide> side_list(const py::handle& points, const std::string& rule, int threads,
                                     const std::string& ray) const {
        const InsideOptions o = inside_options(rule, threads, ray);
        const F32 p = as_points(points, "points");
        std::vector<PointSide> res(std::size_t(p.shape(0)));
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            const std::shared_lock<RwLock> hold(lock_);
            classify(p, o, res, interrupt);
        }
        interrupt.raise_if_stopped();
        return res;
    }

    py::array_t<std::uint8_t> sides(const py::handle& points, const std::string& rule, int threads,
                                    const std::string& ray) const {
        const auto res = side_list(points, rule, threads, ray);
        auto out = empty_array<std::uint8_t>(res.size());
        for (std::size_t i = 0; i < res.size(); ++i) out.mutable_data()[i] = std::uint8_t(res[i].side);
        return out;
    }

    py::array_t<bool> contains(const py::handle& points, const std::string& rule, int threads,
                               const std::string& ray) const {
        const auto res = side_list(points, rule, threads, ray);
        auto out = empty_array<bool>(res.size());
        for (std::size_t i = 0; i < res.size(); ++i) out.mutable_data()[i] = res[i].side == Side::inside;
        return out;
    }

    py::array_t<float> signed_distance(const py::handle& points, const std::string& rule, int threads,
                                       const std::string& ray) const {
        const InsideOptions o = inside_options(rule, threads, ray);
        const F32 p = as_points(points, "points");
        const auto n = std::size_t(p.shape(0));
        std::vector<ClosestPoint> near(n);
        std::vector<PointSide> res(n);
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            const std::shared_lock<RwLock> hold(lock_);  // both answers for the same vertices
            closest_points(p, kInf, o.threads, near, interrupt);
            classify(p, o, res, interrupt);
        }
        interrupt.raise_if_stopped();
        auto out = empty_array<float>(n);
        for (std::size_t i = 0; i < n; ++i) {
            const float v = near[i].distance;
            out.mutable_data()[i] = res[i].side == Side::surface ? 0.0f : (res[i].side == Side::inside ? -v : v);
        }
        return out;
    }

    py::dict count(const py::handle& o, const py::handle& d, const py::handle& tmin, const py::handle& tmax,
                   int threads) const {
        const std::vector<Ray> rays = make_rays(o, d, tmin, tmax);
        std::vector<CrossingCount> res(rays.size());
        const int nthreads = check_threads(threads);
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            const std::shared_lock<RwLock> hold(lock_);
            const bool brute = method_ == "brute";
            for_blocks(rays.size(), kPointBlock, interrupt, [&](std::size_t b, std::size_t e) {
                if (brute) {
                    for (std::size_t i = b; i < e; ++i) res[i] = brute_force_count_crossings(mesh_, rays[i]);
                } else {
                    count_crossings(bvh2(), std::span<const Ray>(rays.data() + b, e - b),
                                    std::span<CrossingCount>(res.data() + b, e - b), nthreads);
                }
            });
        }
        interrupt.raise_if_stopped();
        auto w = empty_array<std::int32_t>(res.size());
        auto c = empty_array<std::uint32_t>(res.size());
        for (std::size_t i = 0; i < res.size(); ++i) {
            w.mutable_data()[i] = res[i].winding;
            c.mutable_data()[i] = res[i].crossings;
        }
        return py::dict("winding"_a = w, "crossings"_a = c);
    }

    py::dict all(const py::handle& o, const py::handle& d, const py::handle& tmin, const py::handle& tmax,
                 std::size_t max_hits, int threads) const {
        if (max_hits < 1) throw Error("max_hits must be >= 1");
        const int nthreads = check_threads(threads);
        const std::vector<Ray> rays = make_rays(o, d, tmin, tmax);
        std::vector<AllHits> res(rays.size());
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            const std::shared_lock<RwLock> hold(lock_);
            const bool brute = method_ == "brute";
            const Bvh2* tree = brute ? nullptr : &bvh2();
            // Each ray's hits are its own: the same arrays for every thread count.
            for_blocks(rays.size(), kPointBlock, interrupt, [&](std::size_t b, std::size_t e) {
                parallel_for(e - b, nthreads, [&](std::size_t lo, std::size_t hi) {
                    for (std::size_t i = b + lo; i < b + hi; ++i)
                        res[i] = brute ? brute_force_intersect_all(mesh_, rays[i], max_hits)
                                       : intersect_all(*tree, rays[i], max_hits);
                });
            });
        }
        interrupt.raise_if_stopped();
        std::size_t total = 0;
        for (const AllHits& a : res) total += a.hits.size();
        auto ray = empty_array<std::int64_t>(total), prim = empty_array<std::int64_t>(total);
        auto t = empty_array<float>(total), u = empty_array<float>(total), v = empty_array<float>(total);
        auto facing = empty_array<std::int8_t>(total);
        auto dropped = empty_array<std::int64_t>(res.size());
        std::size_t k = 0;
        for (std::size_t i = 0; i < res.size(); ++i) {
            dropped.mutable_data()[i] = std::int64_t(res[i].dropped);
            for (const Crossing& c : res[i].hits) {
                ray.mutable_data()[k] = std::int64_t(i);
                prim.mutable_data()[k] = c.prim;
                t.mutable_data()[k] = c.t;
                u.mutable_data()[k] = c.u;
                v.mutable_data()[k] = c.v;
                facing.mutable_data()[k] = std::int8_t(c.facing);
                ++k;
            }
        }
        return py::dict("ray"_a = ray, "t"_a = t, "prim"_a = prim, "u"_a = u, "v"_a = v, "facing"_a = facing,
                        "dropped"_a = dropped);
    }

    const Mesh& mesh() const { return mesh_; }
    const std::string& method() const { return method_; }
    // Moved vertices, the same faces: every tree this BVH holds is refitted in
    // place. The new positions are checked before anything changes.
    void refit(const py::handle& vertices, int threads) {
        const F32 v = as_points(vertices, "vertices");
        if (std::size_t(v.shape(0)) != mesh_.positions.size())
            throw Error("vertices: expected " + std::to_string(mesh_.positions.size()) + " rows (the mesh's), got " +
                        std::to_string(v.shape(0)));
        Mesh moved;
        moved.positions.assign(vec3s(v), vec3s(v) + v.shape(0));
        moved.triangles = mesh_.triangles;
        validate(moved);
        threads = check_threads(threads);
        py::gil_scoped_release nogil;
        const std::unique_lock<RwLock> hold(lock_);    // waits for the running queries, holds back new ones
        if (bvh2_built_) bvh2_.refit(moved, threads);  // else built later from the moved vertices
        if (width_ > 2) visit_wide([&](auto& bvh) { bvh.refit(moved, threads); });
        mesh_.positions.swap(moved.positions);
    }

    std::string isa() const {
        if (width_ <= 2) return std::string(name(Isa::scalar));
        return std::string(name(isa_auto_ ? traversal_isa_choice(width_, false).isa : isa_));
    }

private:
    // For load_saved: the method and ISA, nothing built.
    Bvh(const std::string& method, const std::optional<std::string>& isa) : method_(method) {
        width_ = tree_width(*parse_accel_method(method_));
        if (const auto parsed = isa_arg(isa)) isa_ = *parsed;
        else {
            isa_ = active_isa();
            isa_auto_ = true;
        }
    }
    Mesh mesh_;
    std::string method_;
    Isa isa_ = Isa::scalar;
    bool isa_auto_ = false;  // isa=None
    mutable std::once_flag bvh2_once_;
    mutable Bvh2 bvh2_;
    mutable bool bvh2_built_ = false;
    int width_ = 0;    // tree_width(method): 0 brute, 2 bvh2, 4/8/16 the wide tree in wide_
    AnyWideBvh wide_;  // the wide tree of a wide method
    // f(the wide tree), mutable or not as this BVH is.
    template <class F>
    void visit_wide(F&& f) const {
        std::visit(
            [&](const auto& b) {
                if constexpr (!std::is_same_v<std::decay_t<decltype(b)>, std::monostate>) f(b);
            },
            wide_);
    }
    template <class F>
    void visit_wide(F&& f) {
        std::visit(
            [&](auto& b) {
                if constexpr (!std::is_same_v<std::decay_t<decltype(b)>, std::monostate>) f(b);
            },
            wide_);
    }
    // Queries hold it shared, refit alone: a query sees the vertices and boxes before or after a refit.
    mutable RwLock lock_;
};

py::array_t<float> vertices_of(const Mesh& m) {
    auto a = empty_points(m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        for (int k = 0; k < 3; ++k) a.mutable_data()[3 * i + k] = m.positions[i][k];
    return a;
}

py::array_t<std::int64_t> faces_of(const Mesh& m) {
    py::array_t<std::int64_t> a({py::ssize_t(m.triangles.size()), py::ssize_t(3)});
    for (std::size_t i = 0; i < m.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) a.mutable_data()[3 * i + k] = m.triangles[i][k];
    return a;
}

}  // namespace

void bind_scene(py::module_& m);  // scene.cpp: simdbvh.Scene and load_scene

}  // namespace simdbvh::python

PYBIND11_MODULE(_simdbvh, m) {
    using namespace simdbvh;
    using namespace simdbvh::python;
    m.doc() =
        "simdbvh: exact, fast ray and point queries against triangle meshes.\n\n"
        "Array arguments (anything numpy.asarray reads): coordinates, bounds and transforms take real numbers of any "
        "integer or floating dtype (converted to float32); faces and geometry indices take integers of any integer "
        "dtype. Bool, complex, string and object arrays are refused (simdbvh.Error naming the argument), never "
        "cast, and a conversion without memory for its copy raises simdbvh.Error naming the argument.\n\n"
        "Interrupts: a query called from Python's main thread runs the signal handlers between its pieces (chunks "
        "of 16,384 rays, 256 for brute force, 32,768 for scenes; sorted batches of 2^20 rays; for point queries and "
        "crossing counts that would run over a second, blocks of about a quarter of a second), at most every 0.1 s, so "
        "Ctrl-C raises KeyboardInterrupt out of a long "
        "query and its results are dropped. Python runs handlers on the main thread only: a query on another "
        "thread runs to its end.";
    py::register_exception<Error>(m, "Error", PyExc_ValueError);
    g_main_thread_ident = py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
    m.def(
        "_set_block_times",
        [](double scale) {
            if (!(scale >= 0.0 && scale <= 1e6)) throw Error("_set_block_times: scale must be in [0, 1e6]");
            return g_block_time_scale.exchange(scale);
        },
        py::arg("scale"),
        "For tests: scales the time per interruptible block and the work done without blocks (1 = as shipped, 0 = "
        "the smallest blocks); returns the previous scale.");
    m.def(
        "_block_calls", [] { return g_block_calls.load(); },
        "For tests: the library calls the interruptible blocks have made so far in this process.");

    py::class_<Mesh>(m, "Mesh", "A triangle mesh: float32 vertices (n, 3), int faces (m, 3).")
        .def(py::init(&mesh_from_arrays), py::arg("vertices"), py::arg("faces"),
             "Copies the arrays (vertices: real numbers, converted to float32; faces: integers of any integer dtype, "
             "read through their strides, stored as uint32). Raises simdbvh.Error for a bad shape, another dtype "
             "(float faces are not truncated; bool, complex, string and object arrays are refused), a non-finite "
             "vertex used by a face, an out-of-range index, or too little memory.")
        .def_property_readonly("vertices", &vertices_of, "The vertices, (n, 3) float32 (a copy).")
        .def_property_readonly("faces", &faces_of, "The faces, (m, 3) int64 (a copy).")
        .def(py::pickle([](const Mesh& mesh) { return py::make_tuple(vertices_of(mesh), faces_of(mesh)); },
                        [](const py::tuple& t) {
                            if (t.size() != 2) throw Error("a pickled Mesh is (vertices, faces)");
                            return mesh_from_arrays(t[0], t[1]);
                        }))
        .def("__len__", &Mesh::size, "The number of triangles.")
        .def(
            "closure",
            [](const Mesh& mesh) {
                const MeshClosure c = mesh_closure(mesh);
                py::dict d;
                d["edges"] = c.edges;
                d["boundary_edges"] = c.boundary_edges;
                d["nonmanifold_edges"] = c.nonmanifold_edges;
                d["misoriented_edges"] = c.misoriented_edges;
                d["closed"] = c.closed();
                d["consistently_oriented"] = c.consistently_oriented();
                return d;
            },
            "Edge statistics after welding equal vertices: whether the mesh bounds a volume.");

    m.def(
        "load",
        [](const std::string& path) {
            path_arg(path, "path");
            Mesh mesh;
            {
                py::gil_scoped_release nogil;
                mesh = workloads::load_scene(path);
            }
            // As an empty file is refused: a built-in (soup-0) or a file (only vertices) that yields no triangle.
            if (mesh.triangles.empty()) throw Error(path + ": no triangles (an empty mesh)");
            return mesh;
        },
        py::arg("path"),
        "Loads a mesh file (.ply .obj .stl .off, optionally .gz) or a named scene. Raises simdbvh.Error for a "
        "missing or bad file, a mesh with no triangles or a path containing a NUL byte.");

    py::class_<Bvh>(
        m, "BVH",
        "A bounding volume hierarchy over a mesh, and its queries.\n\n"
        "Threads: every query releases the GIL, and queries on one BVH from many threads run side by "
        "side. refit is serialised with them by the object: it waits for the running queries and holds "
        "back new ones until it is done, so each query answers for the vertices before or after a refit, "
        "never a mix. A query on Python's main thread stops for Ctrl-C (KeyboardInterrupt) between its pieces "
        "(see the module's docstring).")
        .def(py::init<Mesh, const std::string&, const std::optional<std::string>&>(), py::arg("mesh"),
             py::arg("method") = "bvh8", py::arg("isa") = py::none(),
             "method: 'bvh8' (default), 'bvh4' or 'bvh16' (SIMD wide trees), 'bvh2' or 'brute'; isa: 'scalar', 'avx2', "
             "'avx512' or None (chosen by speed: the faster SIMD path measured once per process on the first batch of "
             "8192 rays or more, or SIMDBVH_ISA when set). "
             "Point queries (contains, sides, closest_point, signed_distance) walk the wide tree when there is one, "
             "else the BVH2 (the same answers); crossing counts and all hits use the BVH2 (or brute force).")
        .def_property_readonly("method", &Bvh::method)
        .def_property_readonly("isa", &Bvh::isa)
        .def(
            "intersect",
            [](const Bvh& b, const py::handle& o, const py::handle& d, const py::handle& tmin, const py::handle& tmax,
               int threads, bool points,
               bool normals) { return b.intersect(o, d, tmin, tmax, threads, false, points, normals); },
            py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f, py::arg("tmax") = kInf,
            py::arg("threads") = 1, py::arg("points") = false, py::arg("normals") = false,
            "Closest hits: dict of hit (bool), t, prim (-1 for a miss), u, v. Ties at equal t go to the lower id. "
            "points=True adds 'points' (n, 3): (1-u-v) v0 + u v1 + v v2 evaluated in double, rounded to float32 "
            "(on the hit triangle); normals=True adds 'normals' (n, 3): the unit geometric normal "
            "(v1 - v0) x (v2 - v0) by the triangle's winding, not turned toward the ray. Misses: NaN rows. "
            "origins, directions (n, 3) and tmin, tmax (numbers or (n,)) are read in place when they are "
            "C-contiguous float32 and converted (copied) otherwise; the rays are traced in batches of up to 2^20 "
            "(bvh4/8/16, when the library sorts them, e.g. diffuse bounces: traced whole, spread over `threads` by "
            "the library) or chunks of 16,384 spread over `threads`, the answers written straight into the returned "
            "arrays.")
        .def(
            "occluded",
            [](const Bvh& b, const py::handle& o, const py::handle& d, const py::handle& tmin, const py::handle& tmax,
               int threads) -> py::object {
                // An owning reference made while the dict lives (a returned item accessor outlived it: the
                // conversion then read a freed dict, which corrupted the heap on large batches).
                const py::dict r = b.intersect(o, d, tmin, tmax, threads, true);
                return r["hit"];
            },
            py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f, py::arg("tmax") = kInf,
            py::arg("threads") = 1, "Any hit: a bool per ray.")
        .def("refit", &Bvh::refit, py::arg("vertices"), py::arg("threads") = 1,
             "Moves the mesh's vertices ((n, 3), the same n; faces unchanged) and refits the trees in place: "
             "boxes recomputed bottom-up, topology kept, O(n). Results afterwards are those of a BVH built on the "
             "moved mesh, bit for bit. Raises simdbvh.Error (the BVH unchanged) for another shape or a non-finite "
             "vertex. Safe while other threads query this BVH: it waits for their running queries and holds back "
             "new ones while it refits.")
        .def("closest_point", &Bvh::closest, py::arg("points"), py::arg("max_distance") = kInf, py::arg("threads") = 1,
             "Closest points: dict of distance (inf when none within max_distance), prim (-1), points (n, 3), u, v.")
        .def("sides", &Bvh::sides, py::arg("points"), py::arg("rule") = "winding", py::arg("threads") = 1,
             py::arg("ray") = "shortest",
             "Exact inside/outside: uint8 per point, 0 outside, 1 inside, 2 on the surface. ray: the axis ray "
             "counted from each point ('shortest': toward the nearest face of the bounds; or '+x' ... '-z').")
        .def("contains", &Bvh::contains, py::arg("points"), py::arg("rule") = "winding", py::arg("threads") = 1,
             py::arg("ray") = "shortest", "Exact inside test: True for points inside (not on the surface).")
        .def("signed_distance", &Bvh::signed_distance, py::arg("points"), py::arg("rule") = "winding",
             py::arg("threads") = 1, py::arg("ray") = "shortest",
             "Distance to the closest point, negative inside, 0 on the surface.")
        .def("count_crossings", &Bvh::count, py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f,
             py::arg("tmax") = kInf, py::arg("threads") = 1,
             "Signed crossing counts: dict of winding (int32) and crossings (uint32); every crossing once.")
        .def("intersect_all", &Bvh::all, py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f,
             py::arg("tmax") = kInf, py::arg("max_hits") = 1024, py::arg("threads") = 1,
             "Every hit: flat arrays ray, t, prim, u, v, facing sorted by ray, t, prim; dropped per ray. The rays "
             "are spread over `threads`; the arrays are the same for every count.")
        .def(
            "save",
            [](const Bvh& b, const std::string& path) {
                path_arg(path, "path");
                const auto bytes = b.saved_bytes();
                py::gil_scoped_release nogil;
                io::write_file_atomic(path, bytes);
            },
            py::arg("path"),
            "Saves the tree and its mesh to `path` (docs/saved_format.md; written to a temporary file renamed over "
            "it, never a partial file); simdbvh.load_bvh(path) loads it in milliseconds. 'brute' has no tree: an "
            "Error.")
        .def(py::pickle(
            [](const Bvh& b) {
                const auto bytes = b.saved_bytes();
                return py::make_tuple(py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                                      b.isa_arg_given());
            },
            [](const py::tuple& t) {
                if (t.size() != 2) throw Error("a pickled BVH is (bytes, isa)");
                const py::bytes data = t[0];
                return Bvh::load_saved({}, &data, t[1].cast<std::optional<std::string>>(), true);
            }))
        .def("__repr__", [](const Bvh& b) {
            return "<simdbvh.BVH: " + std::to_string(b.mesh().size()) + " triangles, " + b.method() + "/" + b.isa() +
                   ">";
        });

    m.def(
        "load_bvh",
        [](const std::string& path, const std::optional<std::string>& isa, bool verify) {
            path_arg(path, "path");
            return Bvh::load_saved(path, nullptr, isa, verify);
        },
        py::arg("path"), py::arg("isa") = py::none(), py::arg("verify") = true,
        "Loads a BVH saved by BVH.save (or `simdbvh build`): the tree and its mesh, no build. The method is the "
        "file's ('bvh2', 'bvh4', 'bvh8', 'bvh16'). verify=False skips the checksum of the arrays (the header, "
        "bounds and structure are still checked). Raises simdbvh.Error naming the file for a truncated, damaged or "
        "foreign file.");
    m.def(
        "isas",
        [] {
            std::vector<std::string> out;
            for (Isa i : supported_isas()) out.emplace_back(name(i));
            return out;
        },
        "The instruction sets this CPU supports.");

    bind_scene(m);
}
