// Shared by the point query commands (see point_queries.h).
#include "point_queries.h"

#include <iostream>

#include "simdbvh/query/inside.h"
#include "simdbvh/accel/cost_model.h"

namespace simdbvh::cli {

bool report_closure(const std::string& scene_name, const Mesh& mesh) {
    const MeshClosure c = mesh_closure(mesh);
    if (c.consistently_oriented()) {
        std::cout << "mesh " << scene_name << ": closed and consistently oriented (" << c.edges << " edges)\n";
        return true;
    }
    std::cout << "warning: mesh " << scene_name << " is not a closed, consistently oriented surface ("
              << c.boundary_edges << " boundary, " << c.nonmanifold_edges << " non-manifold, " << c.misoriented_edges
              << " misoriented of " << c.edges
              << " edges): inside/outside follows the crossing rule and may be wrong near those edges\n";
    return false;
}

InsideOptions::Rule parse_rule(const Options& o) {
    const std::string r = o.get("rule", "winding");
    if (r == "winding") return InsideOptions::Rule::winding;
    if (r == "parity") return InsideOptions::Rule::parity;
    throw UsageError("unknown --rule '" + r + "' (winding, parity)");
}

CountRay parse_ray(const Options& o) {
    try {
        return count_ray_named(o.get("ray", "shortest"));
    } catch (const Error& e) {
        throw UsageError(std::string("--ray: ") + e.what());
    }
}

std::string parse_tree(const Options& o, const std::string& fallback) {
    const std::string tree = o.get("tree", fallback);
    const auto m = parse_accel_method(tree);
    if (!m || !is_tree(*m)) throw UsageError("unknown --tree '" + tree + "' (" + method_names(is_tree) + ")");
    return tree;
}

PointTree PointTree::build(const Mesh& mesh, const std::string& tree) {
    PointTree t{Bvh2::build(mesh), {}};
    if (const int w = tree_width(*parse_accel_method(tree)); w > 2)
        with_width(w, [&](auto n) { t.wide = BvhN<decltype(n)::value>::build(t.bvh2); });
    return t;
}

}  // namespace simdbvh::cli
