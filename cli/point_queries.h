#pragma once
// Shared by the point query commands (distance, inside): the closure line,
// the --rule and --ray options and the --tree a query walks.
#include <string>
#include <type_traits>
#include <variant>

#include "options.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::cli {

// One line on stdout saying whether the mesh bounds a volume (inside and the
// sign of distances are exact only for closed, consistently oriented meshes).
// Returns whether it does.
bool report_closure(const std::string& scene_name, const Mesh& mesh);

// --rule winding|parity (default winding).
InsideOptions::Rule parse_rule(const Options& o);

// --ray shortest|+x|-x|+y|-y|+z|-z (default shortest): the ray each point's
// crossings are counted along.
CountRay parse_ray(const Options& o);

// --tree bvh2|bvh4|bvh8|bvh16 (every tree gives the same answers; the
// default is the fastest for the command's query in the bench).
std::string parse_tree(const Options& o, const std::string& fallback);

// The tree a point query walks: the BVH2, or a wide tree collapsed from it.
struct PointTree {
    Bvh2 bvh2;
    std::variant<std::monostate, Bvh4, Bvh8, Bvh16> wide;

    static PointTree build(const Mesh& mesh, const std::string& tree);
    // f(the tree): the BVH2 or the wide tree.
    template <class F>
    void visit(F&& f) const {
        std::visit(
            [&](const auto& t) {
                if constexpr (std::is_same_v<std::decay_t<decltype(t)>, std::monostate>) f(bvh2);
                else f(t);
            },
            wide);
    }
};

}  // namespace simdbvh::cli
