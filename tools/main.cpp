// simdbvh: build, trace and benchmark BVHs on real meshes. Thin: parses
// options and calls the library; errors become messages and exit status 2.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "common.h"
#include "options.h"
#include "simdbvh/kernels/error.h"

namespace {

constexpr const char* kUsage = R"(usage: simdbvh <command> [options]
commands:
  info     --scene S [--builder B] [--bins N] [--collapse sah|greedy]   triangles, bounds, both trees' statistics
  gen-rays --scene S --kind K --count N [--seed K] --out RAYS.bin
           K: primary | incoherent | diffuse, or a ray family with its own mesh (--mesh-out MESH.ply
              [--case C] [--quick]; --scene only for random): watertight | offsets | axis-aligned |
              surface-start | grazing | needles | degenerate | random
  trace    --scene S --rays RAYS.bin --out HITS.bin [--method M] [--any-hit] [--stats] [--threads N]
           [--isa I] [--builder B] [--bins N] [--collapse C] [--test watertight|moller]
           [--box conservative|plain] [--quality medium|high] [--robust] [--drop-invalid]
           M: brute | bvh2 | bvh8 | embree | spheres
  bench    [--scene S] [--quick] [--threads N] [--json FILE] [--report DIR] [--readme README.md]
           every method: build, Mrays/s (1 thread, all cores), accuracy; report with charts and pictures
  render   --scene S --out IMG.png [--method M] [--heatmap] [--width W] [--height H]
  panel    [--scene S] [--quick] [--json FILE] [--report DIR]          build quality per builder
  accuracy [--quick] [--family F] [--report DIR] [--json FILE] [--no-embree]   ray families x method variants
S is a scene name (dragon, dragon-res2..4, bunny, teapot, icosphere[-N], soup[-N], terrain) or a mesh file
(.ply .obj .stl .off, optionally .gz). SIMDBVH_ISA=scalar|avx2|avx512 or --isa forces the ISA.
)";

}  // namespace

int main(int argc, char** argv) {
    using namespace simdbvh::cli;
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "help") {
        std::fputs(kUsage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    try {
        if (cmd == "info") return cmd_info(args);
        if (cmd == "gen-rays") return cmd_gen_rays(args);
        if (cmd == "trace") return cmd_trace(args);
        if (cmd == "bench") return cmd_bench(args);
        if (cmd == "render") return cmd_render(args);
        if (cmd == "accuracy") return cmd_accuracy(args);
        if (cmd == "panel") return cmd_panel(args);
        std::cerr << "simdbvh: unknown command '" << cmd << "'\n" << kUsage;
        return 2;
    } catch (const UsageError& e) {
        std::cerr << "simdbvh: " << e.what() << "\n";
        return 2;
    } catch (const simdbvh::Error& e) {
        std::cerr << "simdbvh: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "simdbvh: error: " << e.what() << "\n";
        return 2;
    }
}
