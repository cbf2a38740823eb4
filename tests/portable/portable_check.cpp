// The core library's self-check for any target processor: no GoogleTest, no
// Embree, no loaders, so it cross-builds and runs under emulation
// (scripts/aarch64.sh). On a procedural mesh (a bumpy closed sphere and a soup
// of small triangles, from a fixed integer generator, so every processor gets
// the same floats) it compares, bit for bit, against the scalar brute force:
// closest and any hits of the BVH2 and of BVH4/8/16 at every ISA this CPU
// runs (with packets forced on and off), the wide trees after a refit, the
// closest point and inside/outside of every width. Then the brute force's
// hits against a hit file: tests/data/portable/hits.bin, written on x86-64
// (--write; little-endian records), so a target whose arithmetic differs from
// x86's fails here.
// Exit 0 when everything agrees, 1 on the first mismatch (named), 2 on usage.
//   simdbvh_portable_check [--expect HITS.bin | --write HITS.bin]
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "simdbvh/simdbvh.h"

namespace {

using namespace simdbvh;

struct Rng {  // splitmix64: the same sequence everywhere
    std::uint64_t s;
    std::uint64_t next() {
        std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float unit() { return float(next() >> 40) * 0x1p-24f; }  // [0, 1), exact
    float range(float lo, float hi) { return lo + (hi - lo) * unit(); }
};

// The vertices must be the same floats on every target: no libm calls but
// sqrt (correctly rounded everywhere), only the integer generator and + - * /.
Mesh make_mesh() {
    Mesh m;
    Rng rng{7};
    constexpr int kLat = 24, kLon = 48;
    // A closed bumpy sphere: latitude rings of longitude points (the circle
    // parametrised rationally), each vertex's radius jittered.
    m.positions.push_back({0.0f, 0.0f, 1.0f});  // north pole
    for (int i = 1; i < kLat; ++i) {
        const float z = 1.0f - 2.0f * float(i) / float(kLat);
        const float rho = std::sqrt(1.0f - z * z);
        for (int j = 0; j < kLon; ++j) {
            // A point on the unit circle from a rational parametrisation.
            const float s = -1.0f + 2.0f * float(j) / float(kLon);  // s in [-1, 1)
            const float tq = 2.0f * s;                              // t = tan(angle / 4) scaled
            const float den = 1.0f + tq * tq;
            const float cx = (1.0f - tq * tq) / den, cy = 2.0f * tq / den;
            const float r = 1.0f + 0.08f * (rng.unit() - 0.5f);
            m.positions.push_back({r * rho * cx, r * rho * cy, r * z});
        }
    }
    m.positions.push_back({0.0f, 0.0f, -1.0f});  // south pole
    const auto ring = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * kLon + (j % kLon)); };
    const std::uint32_t south = std::uint32_t(m.positions.size() - 1);
    for (int j = 0; j < kLon; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
    for (int i = 1; i + 1 < kLat; ++i)
        for (int j = 0; j < kLon; ++j) {
            m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
    for (int j = 0; j < kLon; ++j) m.triangles.push_back({ring(kLat - 1, j), south, ring(kLat - 1, j + 1)});
    // A soup of small triangles around and through it; every fifth shares a
    // vertex with the previous one (ties at equal t).
    for (int k = 0; k < 400; ++k) {
        const Vec3 c{rng.range(-1.6f, 1.6f), rng.range(-1.6f, 1.6f), rng.range(-1.6f, 1.6f)};
        const std::uint32_t base = std::uint32_t(m.positions.size());
        for (int v = 0; v < 3; ++v)
            m.positions.push_back(
                {c.x + rng.range(-0.2f, 0.2f), c.y + rng.range(-0.2f, 0.2f), c.z + rng.range(-0.2f, 0.2f)});
        if (k % 5 == 4) m.positions[base] = m.positions[base - 1];
        m.triangles.push_back({base, base + 1, base + 2});
    }
    return m;
}

std::vector<Ray> make_rays(std::size_t n) {
    Rng rng{11};
    std::vector<Ray> rays(n);
    for (std::size_t i = 0; i < n; ++i) {
        Ray& r = rays[i];
        r.org = {rng.range(-2.5f, 2.5f), rng.range(-2.5f, 2.5f), rng.range(-2.5f, 2.5f)};
        const Vec3 to{rng.range(-0.9f, 0.9f), rng.range(-0.9f, 0.9f), rng.range(-0.9f, 0.9f)};
        r.dir = {to.x - r.org.x, to.y - r.org.y, to.z - r.org.z};
        if (i % 10 == 3) r.dir = {0.0f, 0.0f, r.org.z > 0 ? -1.0f : 1.0f};  // axis-aligned
        if (i % 10 == 7) r.dir = {r.dir.x, 0.0f, r.dir.z};                  // a zero component
        if (i % 7 == 5) r.tmax = rng.range(0.2f, 1.0f);                     // short segments
        if (i % 11 == 2) r.tmin = rng.range(0.0f, 0.5f);
    }
    return rays;
}

int failures = 0;

bool same(const Hit& a, const Hit& b) { return a == b; }
bool same(const PointSide& a, const PointSide& b) {
    return a.side == b.side && a.ray == b.ray && a.winding == b.winding && a.crossings == b.crossings;
}

template <class F>
void check(const std::string& what, std::size_t n, F&& equal) {
    for (std::size_t i = 0; i < n; ++i)
        if (!equal(i)) {
            std::fprintf(stderr, "portable_check: FAIL %s: item %zu differs\n", what.c_str(), i);
            ++failures;
            return;
        }
    std::printf("  ok  %s (%zu)\n", what.c_str(), n);
}

template <int N>
void check_wide(const Mesh& mesh, const Mesh& moved, const std::vector<Ray>& rays, const std::vector<Hit>& want,
                const std::vector<Hit>& want_any, const std::vector<Hit>& want_moved) {
    BvhN<N> bvh = BvhN<N>::build(mesh);
    const std::string w = "bvh" + std::to_string(N);
    for (Isa isa : supported_isas()) {
        const std::string tag = w + " " + std::string(name(isa));
        for (Packets p : {Packets::off, Packets::on}) {
            TraceOptions o;
            o.packets = p;
            std::vector<Hit> got(rays.size()), any(rays.size());
            intersect(bvh, rays, got, with_isa(o, isa));
            occluded(bvh, rays, any, with_isa(o, isa));
            const char* ps = p == Packets::on ? " packets" : "";
            check(tag + " closest" + ps, rays.size(), [&](std::size_t i) { return same(got[i], want[i]); });
            check(tag + " any" + ps, rays.size(), [&](std::size_t i) { return any[i].hit() == want_any[i].hit(); });
        }
        for (std::size_t i = 0; i < rays.size(); i += 97)
            if (!same(intersect(bvh, rays[i], with_isa(TraceOptions{}, isa)), want[i])) {
                std::fprintf(stderr, "portable_check: FAIL %s single ray %zu differs\n", tag.c_str(), i);
                ++failures;
                break;
            }
    }
    BvhN<N> refit = BvhN<N>::build(mesh);
    refit.refit(moved);
    for (Isa isa : supported_isas()) {
        std::vector<Hit> got(rays.size());
        intersect(refit, rays, got, with_isa(TraceOptions{}, isa));
        check(w + " " + std::string(name(isa)) + " after refit", rays.size(),
              [&](std::size_t i) { return same(got[i], want_moved[i]); });
    }
}

template <int N>
void check_points(const Mesh& mesh, const std::vector<Vec3>& pts, const std::vector<ClosestPoint>& want_cp,
                  const std::vector<PointSide>& want_side) {
    const BvhN<N> bvh = BvhN<N>::build(mesh);
    const std::string w = "bvh" + std::to_string(N);
    check(w + " closest point", pts.size(), [&](std::size_t i) {
        const ClosestPoint c = closest_point(bvh, pts[i]);
        return c.prim == want_cp[i].prim && c.distance2 == want_cp[i].distance2 &&
               std::memcmp(&c.point, &want_cp[i].point, sizeof(Vec3)) == 0;
    });
    check(w + " inside/outside", pts.size(),
          [&](std::size_t i) { return same(classify_point(bvh, pts[i]), want_side[i]); });
}

}  // namespace

int main(int argc, char** argv) {
    std::string expect, write;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--expect" && i + 1 < argc) expect = argv[++i];
        else if (a == "--write" && i + 1 < argc) write = argv[++i];
        else {
            std::fprintf(stderr, "usage: %s [--expect HITS.bin | --write HITS.bin]\n", argv[0]);
            return 2;
        }
    }
    try {
        std::string isas;
        for (Isa isa : supported_isas()) isas += " " + std::string(name(isa));
        std::printf("portable_check: CPU %s, ISAs:%s (active %s)\n", std::string(cpu_name()).c_str(), isas.c_str(),
                    std::string(name(active_isa())).c_str());
        const Mesh mesh = make_mesh();
        const std::vector<Ray> rays = make_rays(3000);
        std::vector<Hit> want(rays.size()), want_any(rays.size()), want_moved(rays.size());
        brute_force_intersect(mesh, rays, want);
        for (std::size_t i = 0; i < rays.size(); ++i) want_any[i] = brute_force_occluded(mesh, rays[i]);
        Mesh moved = mesh;  // every vertex shifted and scaled: a refit's new positions
        for (Vec3& p : moved.positions) p = {p.x * 0.75f + 0.125f, p.y * 0.75f - 0.0625f, p.z * 1.25f};
        brute_force_intersect(moved, rays, want_moved);
        std::size_t hits = 0;
        for (const Hit& h : want) hits += h.hit();
        std::printf("portable_check: %zu triangles, %zu rays, %zu hit\n", mesh.size(), rays.size(), hits);
        if (hits < rays.size() / 4 || hits == rays.size()) {
            std::fprintf(stderr, "portable_check: FAIL the rays hit %zu of %zu: not a test\n", hits, rays.size());
            return 1;
        }

        const Bvh2 bvh2 = Bvh2::build(mesh);
        std::vector<Hit> got(rays.size()), any(rays.size());
        intersect(bvh2, rays, got);
        occluded(bvh2, rays, any);
        check("bvh2 closest", rays.size(), [&](std::size_t i) { return same(got[i], want[i]); });
        check("bvh2 any", rays.size(), [&](std::size_t i) { return any[i].hit() == want_any[i].hit(); });
        check_wide<4>(mesh, moved, rays, want, want_any, want_moved);
        check_wide<8>(mesh, moved, rays, want, want_any, want_moved);
        check_wide<16>(mesh, moved, rays, want, want_any, want_moved);

        // Points: the closed sphere alone (inside/outside has one answer there).
        Mesh sphere = mesh;
        sphere.triangles.resize(sphere.triangles.size() - 400);
        Rng rng{23};
        std::vector<Vec3> pts(600);
        for (Vec3& p : pts) p = {rng.range(-1.4f, 1.4f), rng.range(-1.4f, 1.4f), rng.range(-1.4f, 1.4f)};
        std::vector<ClosestPoint> want_cp(pts.size());
        std::vector<PointSide> want_side(pts.size());
        std::size_t inside = 0;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            want_cp[i] = brute_force_closest_point(sphere, pts[i]);
            want_side[i] = brute_force_classify_point(sphere, pts[i]);
            inside += want_side[i].side == Side::inside;
        }
        if (inside == 0 || inside == pts.size()) {
            std::fprintf(stderr, "portable_check: FAIL %zu of %zu points inside: not a test\n", inside, pts.size());
            return 1;
        }
        const Bvh2 sphere2 = Bvh2::build(sphere);
        check("bvh2 closest point", pts.size(), [&](std::size_t i) {
            const ClosestPoint c = closest_point(sphere2, pts[i]);
            return c.prim == want_cp[i].prim && c.distance2 == want_cp[i].distance2;
        });
        check("bvh2 inside/outside", pts.size(),
              [&](std::size_t i) { return same(classify_point(sphere2, pts[i]), want_side[i]); });
        check_points<4>(sphere, pts, want_cp, want_side);
        check_points<8>(sphere, pts, want_cp, want_side);
        check_points<16>(sphere, pts, want_cp, want_side);

        const std::size_t bytes = want.size() * sizeof(Hit);
        if (!write.empty()) {
            std::ofstream f(write, std::ios::binary);
            f.write(reinterpret_cast<const char*>(want.data()), std::streamsize(bytes));
            if (!f) {
                std::fprintf(stderr, "portable_check: cannot write %s\n", write.c_str());
                return 2;
            }
            std::printf("portable_check: wrote %zu hits to %s\n", want.size(), write.c_str());
        }
        if (!expect.empty()) {
            std::ifstream f(expect, std::ios::binary);
            const std::vector<char> file((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
            if (file.size() != bytes) {
                std::fprintf(stderr, "portable_check: FAIL %s has %zu bytes, the rays make %zu\n", expect.c_str(),
                             file.size(), bytes);
                return 1;
            }
            check("brute force against " + expect, want.size(), [&](std::size_t i) {
                return std::memcmp(file.data() + i * sizeof(Hit), &want[i], sizeof(Hit)) == 0;
            });
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "portable_check: error: %s\n", e.what());
        return 1;
    }
    if (failures) {
        std::fprintf(stderr, "portable_check: %d check(s) FAILED\n", failures);
        return 1;
    }
    std::printf("portable_check: all agree\n");
    return 0;
}
