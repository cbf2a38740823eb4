#pragma once
// Usage text: the whole tool's and each command's (simdbvh <command> --help), and the version line.
#include <string>

namespace simdbvh::cli {

std::string usage();
// One command's usage; empty for an unknown command.
std::string command_usage(const std::string& command);
// "simdbvh 0.1.0 (isa avx2; supported: scalar avx2)": the CMake project version and the active ISA.
std::string version_line();

}  // namespace simdbvh::cli
