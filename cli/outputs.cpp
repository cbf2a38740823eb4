#include "outputs.h"

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "report.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/output.h"
#include "simdbvh/workloads/scene_inputs.h"

namespace simdbvh::cli {
namespace fs = std::filesystem;
namespace {

bool same_file(const std::string& a, const std::string& b) {
    std::error_code ec;
    const fs::path ta = io::output_target(a), tb = io::output_target(b);
    if (fs::exists(ta, ec) && fs::exists(tb, ec)) return fs::equivalent(ta, tb, ec);
    return fs::weakly_canonical(ta, ec) == fs::weakly_canonical(tb, ec);
}

void on_signal(int sig) {
    // A chart script still writing into a staging folder would refill it: stopped first.
    if (const pid_t child = running_script_pid(); child > 0) {
        ::kill(child, SIGKILL);
        ::waitpid(child, nullptr, 0);
    }
    io::remove_temp_files();
    ::signal(sig, SIG_DFL);
    ::raise(sig);
    ::_exit(128 + sig);  // PID 1: the default action of SIGTERM and SIGINT is to do nothing
}

}  // namespace

void check_outputs(const NamedPaths& outputs, const Inputs& inputs, bool create_parent) {
    // (what the message calls it, the file)
    std::vector<std::pair<std::string, std::string>> read;
    for (const auto& [opt, path] : inputs.files) read.emplace_back(opt + " " + path, path);
    for (const auto& [opt, name] : inputs.scenes)
        for (const workloads::SceneInput& in : workloads::scene_input_files(name))
            read.emplace_back(in.via.empty()
                                  ? opt + " " + name
                                  : in.path.string() + ", which " + opt + " " + name + " reads (" + in.via + ")",
                              in.path.string());
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const auto& [opt, path] = outputs[i];
        for (const auto& [what, in_path] : read) {
            std::error_code ec;
            if (fs::is_regular_file(in_path, ec) && same_file(path, in_path))
                throw Error(path + ": " + opt + " is the same file as " + what + " (refusing to replace an input)");
        }
        for (std::size_t j = 0; j < i; ++j)
            if (same_file(path, outputs[j].second))
                throw Error(path + ": " + opt + " is the same file as " + outputs[j].first + " " + outputs[j].second +
                            " (two outputs cannot share a file)");
        io::check_writable(path, create_parent);
    }
}

void install_cleanup_handlers() {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sa.sa_flags = SA_RESETHAND | SA_NODEFER;  // the re-raised signal is delivered at once, with the default action
    sigemptyset(&sa.sa_mask);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;  // nohup: stay ignored
        ::sigaction(sig, &sa, nullptr);
    }
}

std::string format_bytes(std::uint64_t bytes) {
    char buf[32];
    if (bytes >= (1ULL << 30)) std::snprintf(buf, sizeof buf, "%.1f GB", double(bytes) / double(1ULL << 30));
    else std::snprintf(buf, sizeof buf, "%.1f MB", double(bytes) / double(1ULL << 20));
    return buf;
}

void check_memory(const std::string& what, std::uint64_t bytes) {
    std::uint64_t avail = 0;
    std::ifstream mi("/proc/meminfo");
    for (std::string line; std::getline(mi, line);)
        if (line.rfind("MemAvailable:", 0) == 0) {
            std::istringstream(line.substr(13)) >> avail;
            avail *= 1024;
        }
    if (avail == 0) avail = std::uint64_t(::sysconf(_SC_PHYS_PAGES)) * std::uint64_t(::sysconf(_SC_PAGESIZE));
    std::string limit = "available memory";
    struct rlimit rl {};
    if (::getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY && rl.rlim_cur < avail) {
        avail = rl.rlim_cur;
        limit = "the address-space limit (ulimit -v)";
    }
    if (bytes > avail)
        throw Error(what + " needs about " + format_bytes(bytes) + " of memory, more than " + limit + " (" +
                    format_bytes(avail) + "); ask for less");
}

}  // namespace simdbvh::cli
