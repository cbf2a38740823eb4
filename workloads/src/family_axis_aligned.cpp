// SPDX-License-Identifier: MIT
// The axis-aligned family: a lattice of boxes, rays along the axes and face
// diagonals with +-0.0 components, from origins on the slab planes.
#include "family_parts.h"

namespace simdbvh::workloads::detail {

namespace {

void append_quad(Mesh& m, Vec3 a, Vec3 b, Vec3 c, Vec3 d) {  // a b c d counter-clockwise
    const auto i = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c, d});
    m.triangles.push_back(Triangle{i, i + 1, i + 2});
    m.triangles.push_back(Triangle{i, i + 2, i + 3});
}

void append_box(Mesh& m, Vec3 lo, Vec3 hi) {
    auto p = [&](int i) { return Vec3{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z}; };
    append_quad(m, p(0), p(2), p(3), p(1));  // z = lo
    append_quad(m, p(4), p(5), p(7), p(6));  // z = hi
    append_quad(m, p(0), p(1), p(5), p(4));  // y = lo
    append_quad(m, p(2), p(6), p(7), p(3));  // y = hi
    append_quad(m, p(0), p(4), p(6), p(2));  // x = lo
    append_quad(m, p(1), p(3), p(7), p(5));  // x = hi
}

}  // namespace

// A 3 x 3 x 3 lattice of boxes [i, i + 0.5]^3 (their faces are the BVH's slab
// planes), rays along the axes and along face diagonals with +-0.0 in the
// other components, from lattice origins on those planes.
std::vector<FamilyCase> family_axis_aligned(const FamilyOptions& o) {
    FamilyCase c;
    c.family = Family::axis_aligned;
    c.name = "axis-aligned/boxes";
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                const Vec3 lo{float(i), float(j), float(k)};
                append_box(c.mesh, lo, lo + Vec3{0.5f, 0.5f, 0.5f});
            }
    std::vector<Vec3> dirs;
    for (int axis = 0; axis < 3; ++axis)
        for (float s : {1.0f, -1.0f})
            for (float z1 : {0.0f, -0.0f})
                for (float z2 : {0.0f, -0.0f}) {
                    Vec3 d{z1, z1, z1};
                    d[axis] = s;
                    d[(axis + 1) % 3] = z1;
                    d[(axis + 2) % 3] = z2;
                    dirs.push_back(d);
                }
    for (int axis = 0; axis < 3; ++axis)  // face diagonals: one zero component
        for (float s1 : {1.0f, -1.0f})
            for (float s2 : {1.0f, -1.0f})
                for (float z : {0.0f, -0.0f}) {
                    Vec3 d;
                    d[axis] = z;
                    d[(axis + 1) % 3] = s1;
                    d[(axis + 2) % 3] = s2;
                    dirs.push_back(d);
                }
    const std::vector<float> coords = o.quick ? std::vector<float>{-1.0f, 0.0f, 0.5f, 1.0f, 2.5f}
                                              : std::vector<float>{-1.0f, 0.0f, 0.25f, 0.5f, 1.0f, 1.5f, 2.5f, 3.0f};
    for (float x : coords)
        for (float y : coords)
            for (float z : coords)
                for (const Vec3& d : dirs) {
                    Ray r;
                    r.org = {x, y, z};
                    r.dir = d;
                    c.rays.push_back(r);
                    c.expect.push_back(RayExpect{Expect::reference});
                }
    return {std::move(c)};
}

}  // namespace simdbvh::workloads::detail
