// SPDX-License-Identifier: MIT
// The procedural pieces of the ray families: small geometric helpers, the
// torus, the Wachter-Binder offset origin.
#include <bit>
#include <cmath>

#include "family_parts.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::workloads {

namespace detail {

std::string decade(double v) {
    int e = 0;
    while (v >= 10.0) {
        v /= 10.0;
        ++e;
    }
    return "1e" + std::to_string(e);
}

Vec3 translate(Vec3 p, double off) {
    return {float(double(p.x) + off), float(double(p.y) + off), float(double(p.z) + off)};
}

Vec3 in_ball(Rng& rng, float r) {
    for (;;) {
        const Vec3 p{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        if (dot(p, p) < 1.0f) return p * r;
    }
}

Vec3 unit_vector(Rng& rng) {
    const float z = 1.0f - 2.0f * rng.uniform();
    const float phi = kTwoPi * rng.uniform();
    const float s = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

}  // namespace detail

using detail::kTwoPi;

Mesh torus(int n, int m, float major_r, float minor_r, Vec3 center) {
    if (n < 3 || m < 3) throw Error("torus needs at least 3 x 3 segments");
    Mesh t;
    for (int i = 0; i < n; ++i) {
        const float phi = kTwoPi * float(i) / float(n);
        for (int j = 0; j < m; ++j) {
            const float th = kTwoPi * float(j) / float(m);
            const float rr = major_r + minor_r * std::cos(th);
            t.positions.push_back(center + Vec3{rr * std::cos(phi), rr * std::sin(phi), minor_r * std::sin(th)});
        }
    }
    auto id = [&](int i, int j) { return std::uint32_t((i % n) * m + (j % m)); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {  // outward counter-clockwise
            t.triangles.push_back(Triangle{id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            t.triangles.push_back(Triangle{id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return t;
}

// Wachter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection"
// (Ray Tracing Gems, ch. 6): move p by 256 ulps along n per component; within
// 1/32 (times scale) of the origin, by n / 65536 (times scale).
Vec3 offset_ray_origin(Vec3 p, Vec3 n, float scale) {
    constexpr float kOrigin = 1.0f / 32.0f, kFloatScale = 1.0f / 65536.0f, kIntScale = 256.0f;
    Vec3 out;
    for (int k = 0; k < 3; ++k) {
        const auto of = std::int32_t(kIntScale * n[k]);
        const auto bits = std::bit_cast<std::int32_t>(p[k]);
        const float pi = std::bit_cast<float>(bits + (p[k] < 0.0f ? -of : of));
        out[k] = std::fabs(p[k]) < kOrigin * scale ? p[k] + kFloatScale * scale * n[k] : pi;
    }
    return out;
}

}  // namespace simdbvh::workloads
