#pragma once
// Runs the simdbvh executable named by $SIMDBVH_CLI (set by ctest) and
// captures its exit status and combined stdout + stderr.
#include <string>

namespace test {

struct CliRun {
    int status = -1;     // exit status; -1 when it did not run or was killed
    std::string output;  // stdout and stderr
};

// `prefix` runs in the same shell first (e.g. "ulimit -f 1; ").
CliRun run_cli(const std::string& args, const std::string& prefix = "");

}  // namespace test
