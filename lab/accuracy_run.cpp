// SPDX-License-Identifier: MIT
#include "lab.h"
#include "accuracy_run.h"

#include <algorithm>
#include <cmath>

#include "common.h"
#include "simdbvh/reference/reference.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh::lab {

namespace {

constexpr std::uint64_t kNone = std::uint64_t(-1);

double time_trace(Tracer& tr, std::span<const Ray> rays, std::span<Hit> hits, double min_seconds) {
    int reps = 0;
    const auto t0 = std::chrono::steady_clock::now();
    double s = 0;
    do {
        tr.trace(rays, hits, false, nullptr);
        ++reps;
        s = seconds_since(t0);
    } while (s < min_seconds && reps < 100);
    return s / reps;
}

// The family's own expectations and the classification against the reference.
void check_hits(const workloads::FamilyCase& c, const std::vector<reference::Reference>& refs,
                const std::vector<Hit>& hits, AccuracyRow& r) {
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const Hit& h = hits[i];
        r.tally.add(reference::classify(refs[i], h));
        if (h.hit() && (std::isnan(h.t) || std::isnan(h.u) || std::isnan(h.v))) ++r.nan_outputs;
        const workloads::RayExpect& e = c.expect[i];
        if (e.kind == workloads::Expect::hit && !h.hit()) ++r.expect_violations;
        if (e.kind == workloads::Expect::miss && h.hit()) ++r.expect_violations;
        if (e.kind == workloads::Expect::no_self_hit && h.hit() && h.prim == e.source) ++r.self_hits;
        if (h.hit() && refs[i].hit()) {
            const double want = !std::isnan(e.t) ? e.t : refs[i].t;
            if (want > 0) r.max_rel_t_error = std::max(r.max_rel_t_error, std::fabs(double(h.t) - want) / want);
        }
    }
}

AccuracyRow run_case(const workloads::FamilyCase& c, const std::vector<reference::Reference>& refs, const Variant& v,
                     std::vector<Hit>& default_hits, double min_seconds) {
    AccuracyRow r;
    r.family = std::string(workloads::name(c.family));
    r.case_name = c.name;
    r.method = v.name;
    r.offset = c.offset;
    r.rays = c.rays.size();
    r.triangles = c.mesh.size();
    auto tracer = make_tracer(c.mesh, v.spec);
    r.depth = tracer->depth;
    std::vector<Hit> hits(c.rays.size());
    r.seconds = time_trace(*tracer, c.rays, hits, min_seconds);
    if (v.ours) {
        TraceStats st;
        std::vector<Hit> again(c.rays.size());
        tracer->trace(c.rays, again, false, &st);
        r.nodes_per_ray = st.rays ? double(st.nodes_visited) / double(st.rays) : 0.0;
        if (default_hits.empty()) default_hits = hits;  // the first variant is the default path
        r.differ_from_default = 0;
        for (std::size_t i = 0; i < hits.size(); ++i)
            r.differ_from_default += !(hits[i] == default_hits[i]) || !(again[i] == hits[i]);
    }
    check_hits(c, refs, hits, r);
    return r;
}

// Adds `r` into the sum slot `m` of `rows` (resized to n methods); the sum is labelled `label`, `offset`.
void add_into(std::vector<AccuracyRow>& rows, std::size_t m, std::size_t n, const AccuracyRow& r,
              const std::string& label, double offset) {
    if (rows.size() < n) rows.resize(n);
    AccuracyRow& s = rows[m];
    if (s.method.empty()) {
        s = AccuracyRow{};
        s.family = r.family;
        s.case_name = label;
        s.method = r.method;
        s.offset = offset;
    }
    s.add(r);
}

}  // namespace

void AccuracyRow::add(const AccuracyRow& o) {
    rays += o.rays;
    triangles = std::max(triangles, o.triangles);
    seconds += o.seconds;
    tally += o.tally;
    expect_violations += o.expect_violations;
    self_hits += o.self_hits;
    nan_outputs += o.nan_outputs;
    if (o.differ_from_default != kNone)
        differ_from_default = (differ_from_default == kNone ? 0 : differ_from_default) + o.differ_from_default;
    if (o.nodes_per_ray >= 0)
        nodes_per_ray = nodes_per_ray < 0 ? o.nodes_per_ray : std::max(nodes_per_ray, o.nodes_per_ray);
    max_rel_t_error = std::max(max_rel_t_error, o.max_rel_t_error);
    depth = std::max(depth, o.depth);
}

std::vector<Variant> accuracy_variants(bool with_embree) {
    std::vector<Variant> v;
    for (TriangleTest t : {TriangleTest::watertight, TriangleTest::moller})
        for (BoxTest b : {BoxTest::conservative, BoxTest::plain}) {
            Variant x;
            x.spec.method = "bvh2";
            x.spec.test = t;
            x.spec.box = b;
            x.name = std::string("bvh2/") + (t == TriangleTest::watertight ? "watertight" : "moller") + "/" +
                     (b == BoxTest::conservative ? "conservative" : "plain");
            x.ours = true;
            v.push_back(x);
        }
    for (Isa isa : supported_isas()) {
        Variant x;
        x.spec.method = "bvh8";
        x.spec.isa = isa;
        x.name = "bvh8/" + std::string(name(isa)) + "/watertight/conservative";
        x.ours = true;
        v.push_back(x);
    }
    Variant brute;
    brute.spec.method = "brute";
    brute.name = "brute/watertight";
    v.push_back(brute);
    if (with_embree)
        for (bool robust : {false, true}) {
            Variant x;
            x.spec.method = "embree";
            x.spec.robust = robust;
            x.name = robust ? "embree/robust" : "embree/default";
            v.push_back(x);
        }
    return v;
}

AccuracyResults run_accuracy(const AccuracyConfig& c) {
    std::vector<Variant> methods = accuracy_variants(c.embree);
    if (!c.only.empty())
        std::erase_if(
            methods, [&](const Variant& v) { return std::find(c.only.begin(), c.only.end(), v.name) == c.only.end(); });
    const double min_seconds = c.quick ? 0.01 : 0.05;
    AccuracyResults out;
    for (workloads::Family fam : c.which) {
        const std::string fname(workloads::name(fam));
        progress("family " + fname + " ...", true);
        std::vector<AccuracyRow> sum;
        for (const workloads::FamilyCase& fc : workloads::make_family(fam, c.families)) {
            std::vector<reference::Reference> refs(fc.rays.size());
            parallel_for(fc.rays.size(), c.threads, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) refs[i] = reference::reference_intersect(fc.mesh, fc.rays[i]);
            });
            std::vector<Hit> default_hits;
            for (std::size_t m = 0; m < methods.size(); ++m) {
                AccuracyRow r = run_case(fc, refs, methods[m], default_hits, min_seconds);
                add_into(sum, m, methods.size(), r, fname, 0.0);
                if (fam == workloads::Family::offsets)
                    add_into(out.offsets[fc.offset], m, methods.size(), r, fname, fc.offset);
                out.cases.push_back(std::move(r));
            }
        }
        out.families[fname] = std::move(sum);
    }
    return out;
}

}  // namespace simdbvh::lab
