#include "methods.h"

#include <chrono>

#include "simdbvh/bvh2/spheres.h"
#include "simdbvh/accel/accel.h"
#include "simdbvh/accel/brute_force8.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh::cli {

bool is_wide(const std::string& method) {
    const auto m = parse_accel_method(method);
    return m && simdbvh::is_wide(*m);
}

std::vector<std::string> wide_methods() {
    std::vector<std::string> names;
    for (AccelMethod m : kAccelMethods)
        if (simdbvh::is_wide(m)) names.emplace_back(name(m));
    return names;
}

int MethodSpec::width() const { return is_wide(method) ? tree_width(*parse_accel_method(method)) : 0; }

std::string MethodSpec::label() const {
    // The wide trees without --isa choose per query when they trace: the ISA is reported apart (isa_name).
    if (is_wide(method) || method == "brute8") {
        std::string l = method;
        if (wide.quantized_nodes) l += "q";
        if (!(is_wide(method) && isa_auto)) {
            l += "/";
            l += name(isa);
        }
        if (test == TriangleTest::moller) l += "/moller";
        return l;
    }
    if (method == "auto") return "auto/" + std::string(name(isa));
    if (method == "embree") return "embree/" + quality + (robust ? "/robust" : "/default");
    // Non-default variants are named: bvh2/moller, bvh2/plain-box, brute/moller.
    std::string l = method;
    if (test == TriangleTest::moller) l += "/moller";
    if (box == BoxTest::plain) l += "/plain-box";
    return l;
}
std::string MethodSpec::isa_name(bool any_hit) const {
    if (is_wide(method) && isa_auto) return std::string(name(traversal_isa_choice(width(), any_hit).isa));
    if (is_wide(method) || method == "brute8" || method == "auto") return std::string(name(isa));
    if (method == "embree") return "embree-internal";
    return "scalar";
}
std::string MethodSpec::isa_note(bool any_hit) const {
    if (!is_wide(method) || !isa_auto) return "";
    const TraversalIsaChoice c = traversal_isa_choice(width(), any_hit);
    if (c.forced) return " (forced)";
    if (c.calibrated) return std::string(" (timed on ") + (any_hit ? "any-hit" : "closest-hit") + " traces)";
    return " (the widest detected, not timed: batches of " + std::to_string(kIsaCalibrationRays) +
           " rays or more are timed with every ISA)";
}
std::string MethodSpec::builder_name() const {
    if (method == "bvh2") return std::string(name(build.builder));
    if (is_wide(method)) return std::string(name(build.builder)) + "+" + std::string(name(wide.collapse));
    if (method == "embree") return "embree-" + quality;
    if (method == "spheres") return "variance";
    return "-";
}

void add_method_options(std::set<std::string>& valued, std::set<std::string>& flags) {
    for (const char* k : {"method", "isa", "builder", "bins", "collapse", "nodes", "test", "box", "quality", "threads",
                          "packets", "reorder"})
        valued.insert(k);
    flags.insert("robust");
}

namespace {
// --packets, --reorder: auto | off | on, for the wide trees and auto only.
template <class Choice>
Choice parse_wide_choice(const Options& o, const std::string& key, const std::string& method) {
    const std::string v = o.get(key, "auto");
    Choice c;
    if (v == "auto") c = Choice::automatic;
    else if (v == "off") c = Choice::off;
    else if (v == "on") c = Choice::on;
    else throw UsageError("unknown --" + key + " '" + v + "' (auto, off, on)");
    if (o.has(key) && !is_wide(method) && method != "auto")
        throw UsageError("--" + key + " applies to the wide trees (bvh4, bvh8, bvh16) and auto (not " + method + ")");
    return c;
}
}  // namespace

MethodSpec parse_method(const Options& o, const std::string& fallback) {
    MethodSpec s;
    s.method = o.get("method", fallback);
    // The library's methods (the registry of cost_model.h) and the CLI's own: auto, embree, spheres.
    if (s.method != "auto" && !parse_accel_method(s.method) && s.method != "embree" && s.method != "spheres")
        throw UsageError("unknown --method '" + s.method + "' ('auto', " +
                         method_names([](AccelMethod) { return true; }) + ", 'embree' or 'spheres')");
    if (o.has("isa")) {
        auto isa = parse_isa(o.get("isa"));
        if (!isa) throw UsageError("unknown --isa '" + o.get("isa") + "' (scalar, avx2, avx512)");
        require(*isa);
        s.isa = *isa;  // passed to every trace; the process-wide choice is left alone
    } else {
        s.isa = active_isa();
        s.isa_auto = true;
    }
    if (o.has("builder")) {
        auto b = parse_builder(o.get("builder"));
        if (!b)
            throw UsageError("unknown --builder '" + o.get("builder") +
                             "' (sah-binned, sah-sweep, midpoint, median, variance)");
        s.build.builder = *b;
    }
    s.build.bins = int(o.get_int("bins", 16, 2, 256));
    if (o.has("collapse")) {
        auto c = parse_collapse(o.get("collapse"));
        if (!c) throw UsageError("unknown --collapse '" + o.get("collapse") + "' (sah, greedy)");
        s.wide.collapse = *c;
    }
    const std::string nodes = o.get("nodes", "full");
    if (nodes == "quantized") s.wide.quantized_nodes = true;
    else if (nodes != "full") throw UsageError("unknown --nodes '" + nodes + "' (full, quantized)");
    if (s.wide.quantized_nodes && (!is_wide(s.method) || s.method == "bvh4"))  // a QNode4 would be as large as a Node4
        throw UsageError("--nodes quantized is a bvh8 / bvh16 variant only (not " + s.method + ")");
    const std::string test = o.get("test", "watertight");
    if (test == "watertight") s.test = TriangleTest::watertight;
    else if (test == "moller") s.test = TriangleTest::moller;
    else throw UsageError("unknown --test '" + test + "' (watertight, moller)");
    s.packets = parse_wide_choice<Packets>(o, "packets", s.method);
    s.reorder = parse_wide_choice<Reorder>(o, "reorder", s.method);
    const std::string box = o.get("box", "conservative");
    if (box == "conservative") s.box = BoxTest::conservative;
    else if (box == "plain") s.box = BoxTest::plain;
    else throw UsageError("unknown --box '" + box + "' (conservative, plain)");
    if (s.box == BoxTest::plain && s.method != "bvh2")
        throw UsageError("--box plain is a bvh2 variant only (" + s.method + " uses the conservative box test)");
    s.quality = o.get("quality", "medium");
    if (s.quality != "medium" && s.quality != "high")
        throw UsageError("unknown --quality '" + s.quality + "' (medium, high)");
    s.robust = o.has("robust");
    // Options of one kind of method are refused on the others, never ignored.
    for (const char* k : {"quality", "robust"})
        if (o.has(k) && s.method != "embree")
            throw UsageError(std::string("--") + k + " applies to --method embree (not " + s.method + ")");
    if (o.has("test") && s.method == "embree")
        throw UsageError("--test applies to our methods (Embree has its own triangle test)");
    s.threads = int(o.get_int("threads", 1, 1, 1024));
    s.build.threads = s.threads;
    return s;
}

TraceOptions trace_options(const MethodSpec& s, TraceStats* stats) {
    return TraceOptions{.test = s.test,
                        .box = s.box,
                        .stats = stats,
                        .threads = stats ? 1 : s.threads,
                        .packets = s.packets,
                        .reorder = s.reorder,
                        .isa = s.isa_auto ? std::nullopt : std::optional<Isa>(s.isa)};
}

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

class BruteTracer final : public Tracer {
public:
    BruteTracer(const Mesh& m, const MethodSpec& s) : mesh_(m), spec_(s) {}
    void trace(std::span<const Ray> rays, std::span<Hit> hits, bool any, TraceStats*) override {
        parallel_for(
            rays.size(), spec_.threads,
            [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i)
                    hits[i] = any ? brute_force_occluded(mesh_, rays[i], spec_.test)
                                  : brute_force_intersect(mesh_, rays[i], spec_.test);
            },
            options_for_cost(mesh_.size()));
    }

private:
    const Mesh& mesh_;
    MethodSpec spec_;
};

// SIMD brute force (bvh8/brute_force8.h): Tri8 blocks, no tree, the ISA of --isa.
class Brute8Tracer final : public Tracer {
public:
    Brute8Tracer(const Mesh& m, const MethodSpec& s) : spec_(s), brute_(BruteForce8::build(m)) {
        build_ms = brute_.build_ms();
        bytes_per_triangle = m.size() ? double(brute_.blocks().size() * sizeof(Tri8)) / double(m.size()) : 0.0;
    }
    void trace(std::span<const Ray> rays, std::span<Hit> hits, bool any, TraceStats*) override {
        TraceOptions o;
        o.test = spec_.test;
        o.threads = spec_.threads;
        any ? occluded(brute_, rays, hits, with_isa(o, spec_.isa))
            : intersect(brute_, rays, hits, with_isa(o, spec_.isa));
    }

private:
    MethodSpec spec_;
    BruteForce8 brute_;
};

// What a user of the library waits for: the wide tree's build is timed whole (its stats time collapse + pack).
template <int N>
std::unique_ptr<Tracer> make_wide_tracer(const Mesh& m, const MethodSpec& s) {
    const auto t0 = std::chrono::steady_clock::now();
    WideOptions wo = s.wide;
    wo.threads = s.build.threads;  // collapse + pack on the build's threads too
    BvhN<N> bvh = BvhN<N>::build(m, s.build, wo);
    const double collapse_ms = bvh.stats().build_ms;
    auto t = std::make_unique<TreeTracer<BvhN<N>>>(std::move(bvh), s, ms_since(t0));
    t->collapse_ms = collapse_ms;
    return t;
}

// auto: Accel (bvh8/accel.h) with the cost model of the ISA, for spec.expected_rays rays.
class AutoTracer final : public Tracer {
public:
    AutoTracer(const Mesh& m, const MethodSpec& s) : spec_(s) {
        AccelOptions o;
        o.threads = s.threads;
        o.isa = s.isa;
        o.build = s.build;
        o.wide = s.wide;
        accel_ = Accel::build(m, s.expected_rays, o);
        build_ms = accel_.build_ms();
        chosen = describe(accel_.choice());
    }
    void trace(std::span<const Ray> rays, std::span<Hit> hits, bool any, TraceStats* stats) override {
        const TraceOptions o = trace_options(spec_, stats);
        any ? occluded(accel_, rays, hits, o) : intersect(accel_, rays, hits, o);
    }
    // brute and bvh2 run scalar; brute8 and the wide trees with the ISA Accel was built for.
    std::string ran_isa(const MethodSpec&, bool) const override {
        const AccelMethod m = accel_.method();
        return m == AccelMethod::brute || m == AccelMethod::bvh2 ? "scalar" : std::string(name(accel_.isa()));
    }

private:
    MethodSpec spec_;
    Accel accel_;
};

class EmbreeTracer final : public Tracer {
public:
    EmbreeTracer(const Mesh& m, const MethodSpec& s) : spec_(s) {
        reference::EmbreeOptions eo;
        eo.quality = s.quality == "high" ? reference::EmbreeQuality::high : reference::EmbreeQuality::medium;
        eo.robust = s.robust;
        eo.threads = s.threads;
        scene_ = std::make_unique<reference::EmbreeScene>(m, eo);
        const reference::EmbreeStats& st = scene_->stats();
        build_ms = st.setup_ms + st.build_ms;
        bytes_per_triangle = st.bytes_per_triangle;
    }
    // Embree's rtcOccluded1 tells hit or miss only: an any-hit "hit" is
    // reported as prim 0, t 0 (only hit() is meaningful).
    void trace(std::span<const Ray> rays, std::span<Hit> hits, bool any, TraceStats*) override {
        parallel_for(rays.size(), spec_.threads, [&](std::size_t b, std::size_t e) {
            auto r = rays.subspan(b, e - b);
            auto h = hits.subspan(b, e - b);
            if (!any) return scene_->intersect(r, h);
            std::vector<std::uint8_t> occ(r.size());
            scene_->occluded(r, occ);
            for (std::size_t i = 0; i < r.size(); ++i) h[i] = occ[i] ? Hit{0.0f, 0.0f, 0.0f, 0u} : Hit{};
        });
    }

private:
    MethodSpec spec_;
    std::unique_ptr<reference::EmbreeScene> scene_;
};

}  // namespace

std::unique_ptr<Tracer> make_tracer(const Mesh& mesh, const MethodSpec& spec) {
    if (spec.method == "auto") return std::make_unique<AutoTracer>(mesh, spec);
    if (spec.method == "brute") return std::make_unique<BruteTracer>(mesh, spec);
    if (spec.method == "brute8") return std::make_unique<Brute8Tracer>(mesh, spec);
    if (spec.method == "bvh2") return std::make_unique<TreeTracer<Bvh2>>(Bvh2::build(mesh, spec.build), spec);
    if (const int w = spec.width())
        return with_width(
            w, [&](auto n) -> std::unique_ptr<Tracer> { return make_wide_tracer<decltype(n)::value>(mesh, spec); });
    if (spec.method == "embree") return std::make_unique<EmbreeTracer>(mesh, spec);
    if (spec.method == "spheres")  // seed 002's bounding-sphere hierarchy (variance splits; --builder is ignored)
        return std::make_unique<TreeTracer<SphereBvh>>(SphereBvh::build(mesh, spec.build), spec);
    throw Error("unknown method " + spec.method);
}

}  // namespace simdbvh::cli
