#pragma once
// Saved structures in the CLI (docs/saved_format.md): `--scene FILE.simdbvh`
// in trace and info, the tree loaded (mapped) instead of built.
#include <memory>
#include <string>

#include "methods.h"

namespace simdbvh::cli {

// True for an existing regular file that starts with the saved format's magic bytes.
bool is_saved_scene(const std::string& name);
// The saved tree as a Tracer (build_ms: the load). --method, when given, must
// name the file's tree; spec.method is set to it.
std::unique_ptr<Tracer> load_saved_tracer(const std::string& file, MethodSpec& spec, bool method_given);
// `simdbvh info --scene FILE.simdbvh`: what the file holds, from its header and a checked load.
int info_saved(const std::string& file);

}  // namespace simdbvh::cli
