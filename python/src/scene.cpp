// simdbvh.Scene: the two-level scene (scene/) (geometries: meshes, sphere
// sets, box sets; instances with 3x4 affine transforms; planes) from numpy
// arrays, a built-in name or a JSON file, and its batched closest-hit and
// any-hit queries with the GIL released. Every path (bvh4, bvh8, bvh16, brute)
// returns the library's SceneHit bits; ids come back as int64 with -1 for "none".
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "arrays.h"
#include "simdbvh/accel/cost_model.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/scene/scene.h"

namespace simdbvh::python {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// numpy's ndim of obj, or -1 when numpy cannot read it as an array.
int ndim_of(const py::handle& obj) {
    const py::array a = try_numpy(obj);
    if (a) return int(a.ndim());
    PyErr_Clear();
    return -1;
}

// `obj` is one (n, cols) array, or a list/tuple of them (one geometry each).
std::vector<F32> row_sets(const py::handle& obj, py::ssize_t cols, const std::string& what) {
    if (obj.is_none()) return {};
    if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
        const auto seq = py::reinterpret_borrow<py::sequence>(obj);
        if (seq.size() > 0) {
            if (ndim_of(seq[0]) == 2) {
                std::vector<F32> out;
                for (std::size_t i = 0; i < seq.size(); ++i)
                    out.push_back(as_rows(seq[i], cols, what + "[" + std::to_string(i) + "]"));
                return out;
            }
        }
    }
    return {as_rows(obj, cols, what)};
}

Vec3 row3(const float* p) { return Vec3{p[0], p[1], p[2]}; }

Mesh mesh_item(const py::handle& item, std::size_t i) {
    const std::string at = "meshes[" + std::to_string(i) + "]";
    if (py::isinstance<Mesh>(item)) return item.cast<Mesh>();
    if (!py::isinstance<py::sequence>(item) || py::isinstance<py::str>(item) ||
        py::reinterpret_borrow<py::sequence>(item).size() != 2)
        throw Error(at + ": expected a simdbvh.Mesh or a (vertices, faces) pair");
    const auto pair = py::reinterpret_borrow<py::sequence>(item);
    try {
        return mesh_from_arrays(pair[0], pair[1]);
    } catch (const Error& e) {
        throw Error(at + ": " + e.what());
    }
}

// A (3, 4) [A | b] or a (4, 4) matrix whose last row is 0 0 0 1.
Affine3 transform_item(const py::handle& obj, const std::string& at) {
    const py::array in = as_numpy(obj, at);
    check_dtype(in, Numbers::reals, at);
    if (in.ndim() != 2 || in.shape(1) != 4 || (in.shape(0) != 3 && in.shape(0) != 4))
        throw Error(at + ": expected shape (3, 4) or (4, 4), got " + shape_of(in));
    const F32 a = convert<float>(in, at);
    const float* p = a.data();
    if (a.shape(0) == 4 && !(p[12] == 0.0f && p[13] == 0.0f && p[14] == 0.0f && p[15] == 1.0f))
        throw Error(at + ": a (4, 4) transform must have the last row 0, 0, 0, 1 (affine)");
    Affine3 t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = p[4 * r + c];
    return t;
}

Instance instance_item(const py::handle& item, std::size_t i) {
    const std::string at = "instances[" + std::to_string(i) + "]";
    if (!py::isinstance<py::sequence>(item) || py::isinstance<py::str>(item) ||
        py::reinterpret_borrow<py::sequence>(item).size() != 2)
        throw Error(at + ": expected a (geometry_index, transform) pair");
    const auto pair = py::reinterpret_borrow<py::sequence>(item);
    // An integer of any integer type (bool, a float or a string refused, as for faces).
    const py::array index = as_numpy(pair[0], at + ".geometry");
    const char kind = index.dtype().kind();
    if (index.ndim() != 0 || (kind != 'i' && kind != 'u'))
        throw Error(at + ".geometry: expected an integer index, got " +
                    (index.ndim() ? "shape " + shape_of(index) : "dtype " + dtype_of(index)));
    const long long g = convert<long long>(index, at + ".geometry").data()[0];
    if (g < 0 || g >= (long long)kNoGeometry) throw Error(at + ".geometry: no geometry " + std::to_string(g));
    return Instance{std::uint32_t(g), transform_item(pair[1], at + ".transform")};
}

// Geometries in the order meshes, sphere sets, box sets; without `instances`
// (None) every geometry gets one identity instance.
SceneDesc desc_from_python(const py::handle& meshes, const py::handle& spheres, const py::handle& boxes,
                           const py::handle& instances, const py::handle& planes) {
    SceneDesc d;
    if (py::isinstance<Mesh>(meshes)) {
        d.geometries.emplace_back(meshes.cast<Mesh>());
    } else if (!meshes.is_none()) {
        if (!py::isinstance<py::sequence>(meshes) || py::isinstance<py::str>(meshes))
            throw Error("meshes: expected a list of simdbvh.Mesh or (vertices, faces) pairs");
        const auto seq = py::reinterpret_borrow<py::sequence>(meshes);
        for (std::size_t i = 0; i < seq.size(); ++i) d.geometries.emplace_back(mesh_item(seq[i], i));
    }
    for (const F32& a : row_sets(spheres, 4, "spheres")) {
        SphereSet s;
        for (py::ssize_t i = 0; i < a.shape(0); ++i) s.spheres.push_back({row3(a.data(i, 0)), *a.data(i, 3)});
        d.geometries.emplace_back(std::move(s));
    }
    for (const F32& a : row_sets(boxes, 6, "boxes")) {
        BoxSet b;
        for (py::ssize_t i = 0; i < a.shape(0); ++i) b.boxes.push_back(Aabb{row3(a.data(i, 0)), row3(a.data(i, 3))});
        d.geometries.emplace_back(std::move(b));
    }
    if (instances.is_none()) {
        for (std::size_t g = 0; g < d.geometries.size(); ++g) d.instances.push_back({std::uint32_t(g), Affine3{}});
    } else {
        if (!py::isinstance<py::sequence>(instances) || py::isinstance<py::str>(instances))
            throw Error("instances: expected a list of (geometry_index, transform) pairs");
        const auto seq = py::reinterpret_borrow<py::sequence>(instances);
        for (std::size_t i = 0; i < seq.size(); ++i) d.instances.push_back(instance_item(seq[i], i));
    }
    if (!planes.is_none()) {
        const F32 a = as_rows(planes, 6, "planes");
        for (py::ssize_t i = 0; i < a.shape(0); ++i) d.planes.push_back({row3(a.data(i, 0)), row3(a.data(i, 3))});
    }
    return d;
}

std::size_t primitives_of(const Geometry& g) {
    if (const Mesh* m = std::get_if<Mesh>(&g)) return m->size();
    if (const SphereSet* s = std::get_if<SphereSet>(&g)) return s->spheres.size();
    return std::get<BoxSet>(g).boxes.size();
}

std::int64_t id(std::uint32_t x) { return x == kInvalidPrim ? -1 : std::int64_t(x); }

class Scene {
public:
    Scene(SceneDesc desc, const std::string& method, const std::optional<std::string>& isa)
        : desc_(std::move(desc)), method_(method) {
        const auto m = parse_accel_method(method_);
        if (!m || !(is_wide(*m) || *m == AccelMethod::brute))
            throw Error("method must be " +
                        method_names([](AccelMethod a) { return is_wide(a) || a == AccelMethod::brute; }) + " (got '" +
                        method_ + "')");
        const auto parsed = isa_arg(isa);
        isa_ = parsed ? *parsed : active_isa();
        py::gil_scoped_release nogil;
        if (is_wide(*m))
            with_width(tree_width(*m), [&](auto n) { bvh_ = SceneBvhN<decltype(n)::value>::build(desc_); });
        else brute_stats();  // validates
        std::visit(
            [&](const auto& b) {
                if constexpr (!std::is_same_v<std::decay_t<decltype(b)>, std::monostate>) stats_ = b.stats();
            },
            bvh_);
    }

    py::dict intersect(const py::handle& o, const py::handle& d, const py::handle& tmin, const py::handle& tmax,
                       int threads, bool normals) const {
        const RayArrays rays(o, d, tmin, tmax);
        const std::size_t n = rays.size();
        auto hit = empty_array<bool>(n);
        auto t = empty_array<float>(n), u = empty_array<float>(n), v = empty_array<float>(n);
        auto prim = empty_array<std::int64_t>(n), geom = empty_array<std::int64_t>(n);
        auto inst = empty_array<std::int64_t>(n);
        py::array_t<float> nrm = normals ? empty_points(n) : empty_points(0);
        bool* phit = hit.mutable_data();
        float *pt = t.mutable_data(), *pu = u.mutable_data(), *pv = v.mutable_data(), *pn = nrm.mutable_data();
        std::int64_t *pprim = prim.mutable_data(), *pgeom = geom.mutable_data(), *pinst = inst.mutable_data();
        const int nthreads = check_threads(threads);
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            for_ray_chunks<SceneHit, kSceneChunkRays>(
                rays, nthreads, interrupt, [&](std::span<const Ray> r, std::span<SceneHit> hs, std::size_t b) {
                    trace(r, hs, false);
                    for (std::size_t k = 0; k < hs.size(); ++k) {
                        const SceneHit& h = hs[k];
                        const std::size_t i = b + k;
                        phit[i] = h.hit();
                        pt[i] = h.t;
                        pu[i] = h.u;
                        pv[i] = h.v;
                        pprim[i] = id(h.prim);
                        pgeom[i] = h.hit() ? id(h.geom) : -1;
                        pinst[i] = h.hit() ? id(h.inst) : -1;
                        if (!normals) continue;
                        // Unit, in double, rounded once; a zero normal (a degenerate primitive) stays zero; misses NaN.
                        float* p = pn + 3 * i;
                        if (!h.hit()) {
                            p[0] = p[1] = p[2] = std::numeric_limits<float>::quiet_NaN();
                            continue;
                        }
                        const Vec3 m = hit_normal(desc_, r[k], h);
                        const double x = m.x, y = m.y, z = m.z, len = std::sqrt(x * x + y * y + z * z);
                        p[0] = len > 0 ? float(x / len) : 0.0f;
                        p[1] = len > 0 ? float(y / len) : 0.0f;
                        p[2] = len > 0 ? float(z / len) : 0.0f;
                    }
                });
        }
        interrupt.raise_if_stopped();
        py::dict out("hit"_a = hit, "t"_a = t, "u"_a = u, "v"_a = v, "prim"_a = prim, "geom"_a = geom, "inst"_a = inst);
        if (normals) out["normals"] = nrm;
        return out;
    }

    py::array_t<bool> occluded(const py::handle& o, const py::handle& d, const py::handle& tmin, const py::handle& tmax,
                               int threads) const {
        const RayArrays rays(o, d, tmin, tmax);
        auto out = empty_array<bool>(rays.size());
        bool* p = out.mutable_data();
        const int nthreads = check_threads(threads);
        Interrupt interrupt;
        {
            py::gil_scoped_release nogil;
            for_ray_chunks<SceneHit, kSceneChunkRays>(
                rays, nthreads, interrupt, [&](std::span<const Ray> r, std::span<SceneHit> hs, std::size_t b) {
                    trace(r, hs, true);
                    for (std::size_t k = 0; k < hs.size(); ++k) p[b + k] = hs[k].hit();
                });
        }
        interrupt.raise_if_stopped();
        return out;
    }

    std::size_t num_geometries() const { return desc_.geometries.size(); }
    std::size_t num_instances() const { return desc_.instances.size(); }
    std::size_t num_planes() const { return desc_.planes.size(); }
    const std::string& method() const { return method_; }
    std::string isa() const { return std::string(name(method_ == "brute" ? Isa::scalar : isa_)); }

    py::dict stats() const {
        py::dict d;
        d["geometries"] = stats_.geometries;
        d["instances"] = stats_.instances;
        d["planes"] = stats_.planes;
        d["primitives"] = stats_.primitives;
        d["instanced_primitives"] = stats_.instanced_primitives;
        if (method_ == "brute") return d;  // no trees: only the counts
        d["build_ms"] = stats_.build_ms;
        d["bytes"] = stats_.bytes;
        d["bytes_per_instance"] = stats_.bytes_per_instance;
        d["volume_corners"] = stats_.volume_corners;
        d["volume_child_corners"] = stats_.volume_child_corners;
        d["max_cond"] = stats_.max_cond;
        return d;
    }

    py::array_t<float> bounds() const {
        const Aabb b = world_bounds(desc_);
        py::array_t<float> a({py::ssize_t(2), py::ssize_t(3)});
        for (int k = 0; k < 3; ++k) {
            a.mutable_data()[k] = b.lo[k];
            a.mutable_data()[3 + k] = b.hi[k];
        }
        return a;
    }

    std::string repr() const {
        return "<simdbvh.Scene: " + std::to_string(num_geometries()) + " geometries, " +
               std::to_string(num_instances()) + " instances, " + std::to_string(num_planes()) + " planes, " + method_ +
               "/" + isa() + ">";
    }

private:
    void brute_stats() {
        validate(desc_);
        stats_.geometries = desc_.geometries.size();
        stats_.instances = desc_.instances.size();
        stats_.planes = desc_.planes.size();
        for (const Geometry& g : desc_.geometries) stats_.primitives += primitives_of(g);
        for (const Instance& in : desc_.instances)
            stats_.instanced_primitives += primitives_of(desc_.geometries[in.geometry]);
    }

    // One chunk of rays on the calling thread (for_ray_chunks spreads the chunks over the threads). Chunks
    // of kSceneChunkRays (scene.h), the library's largest wavefront chunk, so each call is one chunk there;
    // against for_ray_chunks' 16,384 (AMD EPYC Zen 4, 262,144 random rays in the bounds, medians of 7 calls,
    // two processes per module alternating), Mrays/s closest / any, one thread: instances-1000 2.11-2.25 /
    // 2.28-2.38 -> 2.30-2.38 / 2.45-2.57, instances-100 5.30-5.37 / 5.62-5.68 -> 5.47-5.50 / 5.80-5.84,
    // spheres-1000 level. Called
    // without the GIL. The brute force validates the scene and inverts its transforms once per chunk.
    void trace(std::span<const Ray> rays, std::span<SceneHit> hits, bool any) const {
        std::visit(
            [&](const auto& b) {
                if constexpr (std::is_same_v<std::decay_t<decltype(b)>, std::monostate>) {
                    any ? brute_force_occluded(desc_, rays, hits) : brute_force_intersect(desc_, rays, hits);
                } else {
                    if (any) simdbvh::occluded(b, rays, hits, {.isa = isa_, .threads = 1});
                    else simdbvh::intersect(b, rays, hits, {.isa = isa_, .threads = 1});
                }
            },
            bvh_);
    }

    SceneDesc desc_;
    std::string method_;
    Isa isa_ = Isa::scalar;
    std::variant<std::monostate, SceneBvhN<4>, SceneBvhN<8>, SceneBvhN<16>> bvh_;
    SceneStats stats_;
};

}  // namespace

void bind_scene(py::module_& m) {
    py::class_<Scene>(m, "Scene",
                      "Several geometries (triangle meshes, sphere sets, box sets) placed by instances (a geometry "
                      "and a 3x4 affine transform, object -> world), plus unbounded planes; a bottom-level tree per "
                      "geometry and a top-level BVH2 over the instances. Every method returns the same bits as "
                      "method='brute'. Queries release the GIL; on Python's main thread they stop for Ctrl-C "
                      "(KeyboardInterrupt) between chunks of 32,768 rays.")
        .def(py::init([](const py::object& meshes, const py::object& spheres, const py::object& boxes,
                         const py::object& instances, const py::object& planes, const std::string& method,
                         const std::optional<std::string>& isa) {
                 return Scene(desc_from_python(meshes, spheres, boxes, instances, planes), method, isa);
             }),
             py::kw_only(), py::arg("meshes") = py::none(), py::arg("spheres") = py::none(),
             py::arg("boxes") = py::none(), py::arg("instances") = py::none(), py::arg("planes") = py::none(),
             py::arg("method") = "bvh8", py::arg("isa") = py::none(),
             "Builds a scene from arrays (all copied; real numbers converted to float32, faces and geometry "
             "indices integers, as simdbvh.Mesh). Geometry indices run over meshes, "
             "then sphere sets, then box sets, in the order given.\n"
             "meshes: a list of simdbvh.Mesh or (vertices (n, 3), faces (m, 3)) pairs.\n"
             "spheres: an (n, 4) array of center x, y, z and radius (one geometry), or a list of them.\n"
             "boxes: an (n, 6) array of min x, y, z and max x, y, z (one geometry), or a list of them.\n"
             "instances: a list of (geometry_index, transform) with transform a (3, 4) [A | b] (x_world = A x + b) "
             "or a (4, 4) affine matrix; None (the default) places every geometry once, untransformed.\n"
             "planes: an (n, 6) array of a point x, y, z on the plane and its normal x, y, z (any non-zero "
             "length), as the library's Plane.\n"
             "method: 'bvh8' (default), 'bvh4', 'bvh16' (the width of the meshes' bottom trees) or 'brute' "
             "(every instance, primitive and plane per ray); isa: 'scalar', 'avx2', 'avx512' or None (the active "
             "ISA: the best this CPU has, or SIMDBVH_ISA). The trees are built with the GIL released. Raises "
             "simdbvh.Error naming the item for bad shapes, non-finite values, a negative radius, min > max, a zero "
             "plane normal, a singular transform or a missing geometry.")
        .def_property_readonly("num_geometries", &Scene::num_geometries, "Meshes, sphere sets and box sets.")
        .def_property_readonly("num_instances", &Scene::num_instances, "Placed geometries (planes not included).")
        .def_property_readonly("num_planes", &Scene::num_planes, "Planes (their hits have inst >= num_instances).")
        .def_property_readonly("method", &Scene::method, "'bvh4', 'bvh8', 'bvh16' or 'brute'.")
        .def_property_readonly("isa", &Scene::isa, "The bottom-level traversal's ISA ('scalar' for 'brute').")
        .def_property_readonly("stats", &Scene::stats,
                               "Build statistics (SceneStats): counts, build_ms, bytes, bytes_per_instance, summed "
                               "instance box volumes, max_cond; 'brute' has only the counts.")
        .def_property_readonly("bounds", &Scene::bounds,
                               "The union of the instances' world boxes, (2, 3) float32 [min, max] (planes are "
                               "unbounded and not included; empty: +inf / -inf).")
        .def("intersect", &Scene::intersect, py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f,
             py::arg("tmax") = kInf, py::arg("threads") = 1, py::arg("normals") = false,
             "Closest hits (smaller t, then lower inst, then lower prim): dict of hit (bool), t, u, v (float32, "
             "world t: directions need not be unit), prim, geom, inst (int64). A miss: t = inf, u = v = 0, ids -1. "
             "u, v: triangles the barycentrics of v1, v2; spheres longitude and colatitude of the object-space "
             "normal in [0, 1]; boxes the hit face's coordinates in [0, 1]; planes 0, 0. Plane k reports "
             "prim = k, geom = -1 and inst = num_instances + k. normals=True adds 'normals' (n, 3): the unit "
             "world-space geometric normal (triangles by winding, spheres outward, boxes the outward axis of the hit "
             "face, planes their normal; not turned toward the ray), NaN rows for misses.")
        .def("occluded", &Scene::occluded, py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f,
             py::arg("tmax") = kInf, py::arg("threads") = 1, "Any hit in [tmin, tmax]: a bool per ray.")
        .def("__repr__", &Scene::repr);

    m.def(
        "load_scene",
        [](const std::string& name, const std::string& method, const std::optional<std::string>& isa) {
            path_arg(name, "name");
            SceneDesc desc;
            {
                py::gil_scoped_release nogil;
                desc = workloads::load_scene_desc(name);
            }
            // A mesh name or file (not a built-in scene, not JSON) with no triangles is refused, as simdbvh.load does.
            if (!workloads::is_builtin_scene(name) && std::filesystem::path(name).extension() != ".json" &&
                desc.geometries.size() == 1) {
                const Mesh* mesh = std::get_if<Mesh>(&desc.geometries[0]);
                if (mesh && mesh->triangles.empty()) throw Error(name + ": no triangles (an empty mesh)");
            }
            return Scene(std::move(desc), method, isa);
        },
        py::arg("name"), py::arg("method") = "bvh8", py::arg("isa") = py::none(),
        "A scene from a built-in name (room, spheres-N, instances-N: N dragons), a .json scene file (docs/scenes.md, "
        "'Scene files (JSON)') or any mesh simdbvh.load() takes (one geometry, one identity instance). Raises "
        "simdbvh.Error for a missing file, bad JSON, an uncached mesh, a mesh with no triangles or a name containing a "
        "NUL byte.");
}

}  // namespace simdbvh::python
