// simdbvh: build, trace and benchmark BVHs on real meshes. Thin: parses
// options and calls the library; errors become messages and exit status 2.
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "common.h"
#include "lab.h"
#include "options.h"
#include "outputs.h"
#include "printable.h"
#include "simdbvh/kernels/error.h"
#include "usage.h"

int main(int argc, char** argv) {
    using namespace simdbvh::cli;
    escape_terminal_output();
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" ||
        std::string(argv[1]) == "help") {
        std::fputs(usage().c_str(), argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    if (cmd == "--version" || cmd == "version") {
        std::cout << version_line() << "\n";
        return 0;
    }
    const std::vector<std::string> args(argv + 2, argv + argc);
    const std::string cmd_usage = command_usage(cmd);
    if (cmd_usage.empty()) {
        std::cerr << "simdbvh: unknown command '" << cmd << "'\n" << usage();
        return 2;
    }
    for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
            std::cout << cmd_usage;
            return 0;
        }
    install_cleanup_handlers();
    try {
        if (cmd == "build") return cmd_build(args);
        if (cmd == "info") return cmd_info(args);
        if (cmd == "gen-rays") return cmd_gen_rays(args);
        if (cmd == "trace") return cmd_trace(args);
        if (cmd == "bench") return simdbvh::lab::cmd_bench(args);
        if (cmd == "render") return cmd_render(args);
        if (cmd == "accuracy") return simdbvh::lab::cmd_accuracy(args);
        if (cmd == "panel") return simdbvh::lab::cmd_panel(args);
        if (cmd == "gen-points") return cmd_gen_points(args);
        if (cmd == "distance") return cmd_distance(args);
        if (cmd == "inside") return cmd_inside(args);
        if (cmd == "classify") return cmd_classify(args);
        return 2;
    } catch (const UsageError& e) {
        std::cerr << "simdbvh: " << e.what() << "\n";
        return 2;
    } catch (const simdbvh::Error& e) {
        std::cerr << "simdbvh: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "simdbvh: " << cmd << ": out of memory (ask for fewer rays, a smaller image or scene)\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "simdbvh: error: " << e.what() << "\n";
        return 2;
    }
}
