#pragma once
// The lab: the rigs behind `simdbvh bench`, `bench --sweep`, `panel` and
// `accuracy`, their reports and charts, in namespace simdbvh::lab. It is built
// on the CLI's common layer (options, outputs, method specs, the report
// layer), whose names the lab uses as its own; the CLI reaches the lab only
// through the commands declared here.
#include <string>
#include <vector>

namespace simdbvh::cli {}

namespace simdbvh::lab {

using namespace simdbvh::cli;

int cmd_bench(const std::vector<std::string>& args);
int cmd_bench_sweep(const std::vector<std::string>& args);  // bench --sweep
int cmd_accuracy(const std::vector<std::string>& args);
int cmd_panel(const std::vector<std::string>& args);

}  // namespace simdbvh::lab
