#pragma once
// Shared by the point query commands (distance, inside): the closure line
// and the --rule option.
#include <string>

#include "options.h"
#include "simdbvh/bvh2/inside.h"
#include "simdbvh/mesh.h"

namespace simdbvh::cli {

// One line on stdout saying whether the mesh bounds a volume (inside and the
// sign of distances are exact only for closed, consistently oriented meshes).
// Returns whether it does.
bool report_closure(const std::string& scene_name, const Mesh& mesh);

// --rule winding|parity (default winding).
InsideOptions::Rule parse_rule(const Options& o);

}  // namespace simdbvh::cli
