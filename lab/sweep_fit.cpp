// SPDX-License-Identifier: MIT
// The cost model fitted to the sweep (cost_model.h): per method, the build
// time against [1, g(n)] over the fit scenes and the trace time against
// [1, rays, rays f(n), rays h(n)] over the fit rows, both at one thread, by least squares
// on the relative error (weights 1/y^2: the times span nine decades), with no
// negative coefficient (a feature whose coefficient comes out negative is
// dropped and the rest refitted). Then the check: at every held-out point,
// the method the fitted model picks against the best measured one.
#include <algorithm>
#include <cmath>
#include <map>

#include "lab.h"
#include "sweep_run.h"

namespace simdbvh::lab {

namespace {

using Features = std::vector<double>;

// Weighted least squares min sum ((x.c - y) / y)^2 over the features in `use`;
// the others stay 0. Normal equations, Gaussian elimination (at most 4 unknowns).
std::vector<double> solve(const std::vector<Features>& x, const std::vector<double>& y, const std::vector<bool>& use) {
    const std::size_t k = use.size();
    std::vector<std::size_t> idx;
    for (std::size_t j = 0; j < k; ++j)
        if (use[j]) idx.push_back(j);
    const std::size_t m = idx.size();
    std::vector<std::vector<double>> a(m, std::vector<double>(m + 1, 0.0));
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (!(y[i] > 0)) continue;
        const double w = 1.0 / (y[i] * y[i]);
        for (std::size_t p = 0; p < m; ++p) {
            for (std::size_t q = 0; q < m; ++q) a[p][q] += w * x[i][idx[p]] * x[i][idx[q]];
            a[p][m] += w * x[i][idx[p]] * y[i];
        }
    }
    for (std::size_t p = 0; p < m; ++p) {
        std::size_t piv = p;
        for (std::size_t r = p + 1; r < m; ++r)
            if (std::fabs(a[r][p]) > std::fabs(a[piv][p])) piv = r;
        std::swap(a[p], a[piv]);
        if (a[p][p] == 0) continue;
        for (std::size_t r = 0; r < m; ++r) {
            if (r == p) continue;
            const double f = a[r][p] / a[p][p];
            for (std::size_t q = p; q <= m; ++q) a[r][q] -= f * a[p][q];
        }
    }
    std::vector<double> c(k, 0.0);
    for (std::size_t p = 0; p < m; ++p) c[idx[p]] = a[p][p] != 0 ? a[p][m] / a[p][p] : 0.0;
    return c;
}

std::vector<double> fit_nonnegative(const std::vector<Features>& x, const std::vector<double>& y, std::size_t k) {
    std::vector<bool> use(k, true);
    for (;;) {
        const auto c = solve(x, y, use);
        const auto worst = std::min_element(c.begin(), c.end());
        if (*worst >= 0) return c;
        use[std::size_t(worst - c.begin())] = false;
    }
}

// Amdahl's parallel fraction p of a method's build: the all-core build of
// each fit scene of at least kParMin triangles against its one-thread build,
// b_t / b_1 = 1 - p (1 - 1/t), least squares over the scenes, clamped to [0, 1].
// Smaller builds are dominated by fixed costs and thread start-up. The trees
// share one p (every tree is the same BVH2 build, the wide ones plus a
// collapse): fitted over all of their rows, it is less noisy than per method.
constexpr std::size_t kParMin = 50000;
double fit_build_par(const std::vector<SweepRow>& rows, AccelMethod m) {
    std::map<std::string, double> one, all;  // by method + scene
    std::map<std::string, int> threads;
    for (const SweepRow& r : rows) {
        const auto rm = parse_accel_method(r.method);
        if (!rm || (is_tree(m) ? !is_tree(*rm) : *rm != m)) continue;
        if (r.held_out || r.triangles < kParMin || !(r.build_ms > 0)) continue;
        const std::string key = r.method + " " + r.scene;
        if (r.threads == 1) one[key] = r.build_ms;
        else {
            all[key] = r.build_ms;
            threads[key] = r.threads;
        }
    }
    double sxx = 0, sxy = 0;
    for (const auto& [scene, b1] : one) {
        const auto it = all.find(scene);
        if (it == all.end()) continue;
        const double x = 1.0 - 1.0 / double(threads[scene]);  // 1 - ratio = p x
        sxx += x * x;
        sxy += x * (1.0 - it->second / b1);
    }
    return sxx > 0 ? std::clamp(sxy / sxx, 0.0, 1.0) : 0.0;
}

}  // namespace

CostModel fit_cost_model(const std::vector<SweepRow>& rows, Isa isa) {
    CostModel model;
    model.isa = isa;
    for (AccelMethod m : kAccelMethods) {
        std::vector<Features> bx, tx;
        std::vector<double> by, ty;
        std::map<std::string, bool> seen;  // one build sample per scene
        for (const SweepRow& r : rows) {
            if (r.held_out || r.threads != 1 || r.method != name(m)) continue;
            if (!seen[r.scene]) {
                seen[r.scene] = true;
                bx.push_back({1.0, build_size_term(m, r.triangles)});
                by.push_back(r.build_ms);
            }
            const double n_rays = double(r.rays);
            tx.push_back(
                {1.0, n_rays, n_rays * ray_size_term(m, r.triangles), n_rays * ray_cache_term(m, r.triangles)});
            ty.push_back(r.trace_ms);
        }
        MethodCost& c = model.cost[std::size_t(m)];
        if (m != AccelMethod::brute) {  // the scalar brute force builds nothing
            const auto b = fit_nonnegative(bx, by, 2);
            c.build0 = b[0];
            c.build1 = b[1];
        }
        const auto t = fit_nonnegative(tx, ty, 4);  // ray_cache_term is 0 for the trees: c.ray2 = 0 there
        c.call = t[0];
        c.ray0 = t[1];
        c.ray1 = t[2];
        c.ray2 = t[3];
        c.build_par = fit_build_par(rows, m);
    }
    return model;
}

std::vector<SweepCheck> check_auto(const std::vector<SweepRow>& rows, const CostModel& model) {
    // One point per (scene, rays, threads, kind): its rows by method.
    std::map<std::tuple<std::string, std::size_t, int, std::string>, std::vector<const SweepRow*>> points;
    for (const SweepRow& r : rows)
        if (r.held_out) points[{r.scene, r.rays, r.threads, r.ray_kind}].push_back(&r);
    std::vector<SweepCheck> out;
    for (const auto& [key, rs] : points) {
        SweepCheck ck;
        std::tie(ck.scene, ck.rays, ck.threads, ck.ray_kind) = key;
        ck.triangles = rs.front()->triangles;
        const AccelChoice choice = choose(model, ck.triangles, ck.rays, ck.threads);
        ck.chosen = std::string(name(choice.method));
        ck.predicted_ms = choice.predicted_ms[std::size_t(choice.method)];
        for (const SweepRow* r : rs) {
            if (r->method == "embree") {
                ck.embree_ms = r->total_ms();
                continue;
            }
            if (r->method == ck.chosen) ck.chosen_ms = r->total_ms();
            if (ck.best.empty() || r->total_ms() < ck.best_ms) {
                ck.best = r->method;
                ck.best_ms = r->total_ms();
            }
        }
        out.push_back(ck);
    }
    return out;
}

}  // namespace simdbvh::lab
