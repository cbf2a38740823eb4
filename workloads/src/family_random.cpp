// SPDX-License-Identifier: MIT
// The random family: incoherent rays on a real mesh (or a procedural stand-in).
#include "family_parts.h"

#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::workloads::detail {

std::vector<FamilyCase> family_random(const FamilyOptions& o) {
    FamilyCase c;
    c.family = Family::random;
    std::string scene = o.random_scene;
    if (scene.empty() && is_cached("dragon-res4")) scene = "dragon-res4";
    if (!scene.empty()) {
        c.mesh = load_scene(scene);
        c.name = "random/" + scene;
    } else {
        c.mesh = icosphere(4, 0.5f, {0.5f, 0.5f, 0.5f});
        const Mesh soup = random_soup(4000, o.seed * 3 + 1);
        const auto base = std::uint32_t(c.mesh.positions.size());
        c.mesh.positions.insert(c.mesh.positions.end(), soup.positions.begin(), soup.positions.end());
        for (const Triangle& t : soup.triangles)
            c.mesh.triangles.push_back(Triangle{t[0] + base, t[1] + base, t[2] + base});
        c.name = "random/icosphere+soup";
    }
    c.rays = incoherent_rays(c.mesh.bounds(), o.quick ? 2000 : 20000, o.seed * 3 + 2);
    c.expect.assign(c.rays.size(), RayExpect{Expect::reference});
    return {std::move(c)};
}

}  // namespace simdbvh::workloads::detail
