#include "support/cli.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>

namespace test {

CliRun run_cli(const std::string& args, const std::string& prefix) {
    CliRun r;
    const char* cli = std::getenv("SIMDBVH_CLI");
    if (!cli) {
        r.output = "SIMDBVH_CLI is not set";
        ADD_FAILURE() << r.output;
        return r;
    }
    const std::string cmd = prefix + std::string(cli) + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    const int st = pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    EXPECT_NE(r.status, -1) << "simdbvh did not exit normally: " << r.output;
    return r;
}

}  // namespace test
