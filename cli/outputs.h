#pragma once
// The CLI's output files: config-time checks (each output can be created, none
// is also an input or another output), the signal handlers that remove
// temporary files of a killed run, and memory estimates of large requests.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>
#include "simdbvh/io/output.h"

namespace simdbvh::cli {

// (option, path) pairs, e.g. {"--out", "hits.bin"}.
using NamedPaths = std::vector<std::pair<std::string, std::string>>;

// What a command reads.
struct Inputs {
    NamedPaths files = {};   // read as given: {"--rays", "r.bin"}
    NamedPaths scenes = {};  // scene names, each standing for every file it leads to (workloads::scene_input_files):
                             // {"--scene", "scene.json"}: the JSON file and each mesh it references
};

// Throws simdbvh::Error unless every output can be written (io::check_writable; with create_parent for
// files in a folder the command creates) and no output is the same file as an input or another output
// (existing files: same device and inode, so symlinks and hard links are caught; otherwise the paths with
// symlinks resolved). The message names the output and the input (and how the scene reaches it).
void check_outputs(const NamedPaths& outputs, const Inputs& inputs, bool create_parent = false);

// SIGINT, SIGTERM, SIGHUP, SIGPIPE: kill a chart script still running (running_script_pid), remove live
// temporary files and staging folders, then die of the signal (or, where the default action does nothing,
// as PID 1 in a container, exit 128 + signal).
void install_cleanup_handlers();

// Throws simdbvh::Error naming `what` (e.g. "--count 2147483648") when `bytes` exceeds the memory this
// process can use: MemAvailable (/proc/meminfo), or the address-space limit (ulimit -v) when lower.
void check_memory(const std::string& what, std::uint64_t bytes);
// "12.3 GB"
std::string format_bytes(std::uint64_t bytes);

}  // namespace simdbvh::cli
