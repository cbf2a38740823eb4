#include "usage.h"

#include <iterator>

#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/isa.h"

namespace simdbvh::cli {
namespace {

struct CommandText {
    const char* name;
    const char* text;  // lines after "usage: simdbvh "
};

constexpr CommandText kCommands[] = {
    {"info",
     R"(info     --scene S [--builder B] [--bins N] [--collapse sah|greedy]   triangles, bounds, the BVH2's statistics
           and every width's (bvh4, bvh8, bvh16: nodes, depth, bytes/triangle, fill), all from the same BVH2;
           [--expected-rays N] (default 1000000): what --method auto would choose for N rays, and why
)"},
    {"build", R"(build    --scene S --out FILE.simdbvh [--method bvh2|bvh4|bvh8|bvh16] [--nodes quantized] [--threads N]
           [--builder B] [--bins N] [--collapse C]   builds the tree once (default bvh8) and saves it with the
           mesh (docs/saved_format.md); trace and info take FILE.simdbvh as --scene and load it instead
)"},
    {"gen-rays", R"(gen-rays --scene S --kind K --count N [--seed K] --out RAYS.bin
           K: primary | incoherent | diffuse | diffuse-shuffled | shadow | area-shadow | ao | lidar, or a ray family with its own mesh (--mesh-out MESH.ply
              [--case C] [--quick]; --scene only for random): watertight | offsets | axis-aligned |
              surface-start | grazing | needles | degenerate | random |
              direction-scale
           diffuse rays bounce off primary hits: a scene the camera does not hit is an error
)"},
    {"trace",
     R"(trace    --scene S --rays RAYS.bin --out HITS.bin [--method M] [--query Q] [--any-hit] [--stats] [--threads N]
           [--isa I] [--builder B] [--bins N] [--collapse C] [--test watertight|moller]
           [--box conservative|plain] [--quality medium|high] [--robust] [--drop-invalid] [--packets auto|off|on]
           [--reorder auto|off|on]
           M: auto (default: chosen by the cost model) | brute | brute8 | bvh2 | bvh4 | bvh8 | bvh16 | embree | spheres
           --packets: the wide trees trace coherent rays 32 at a time (streams; auto: where it pays; same closest
                      hits)
           --reorder: the wide trees trace the batch sorted by where the rays start and the octant they go to,
                      the hits in the caller's order (auto: diffuse bounces and other rays scattered from
                      surfaces; same hits)
           Q: closest | any (= --any-hit) | count (int32 winding per ray) | all [--max-hits N] (20-byte
              records: ray, t, u, v, prim); count and all run on bvh2 or brute, every crossing once
)"},
    {"gen-points", R"(gen-points --scene S --count N [--seed K] --out POINTS.bin   uniform in the bounds + 10% per side
)"},
    {"distance", R"(distance --scene S --points POINTS.bin --out DIST.bin [--threads N] [--max-distance R] [--stats]
           [--unsigned] [--rule winding|parity] [--ray shortest|+x|-x|+y|-y|+z|-z] [--tree bvh2|bvh4|bvh8|bvh16]
           closest point per point: 20-byte records (signed distance, triangle, x y z); negative inside;
           --tree: the tree of the closest point and the sign (default bvh4; same records from each)
)"},
    {"inside", R"(inside   --scene S --points POINTS.bin --out SIDES.bin [--threads N] [--rule winding|parity]
           [--ray shortest|+x|-x|+y|-y|+z|-z] [--tree bvh2|bvh4|bvh8|bvh16]
           exact inside/outside per point: one byte (0 outside, 1 inside, 2 on the surface);
           --ray: the axis ray counted from each point (default shortest: toward the nearest face of the
           mesh's bounds); --tree: the tree the rays walk (default bvh8; same bytes from each)
)"},
    {"classify", R"(classify --scene S --rays RAYS.bin --hits HITS.bin [--threads N] [--json FILE]
           any method's closest hits (16-byte hit records, e.g. another library's answers) classified per ray
           against the double-precision reference: agree, tie, leak, false_hit, wrong_triangle, t_error
           (docs/accuracy.md); O(rays x triangles), for ray families and samples
)"},
    {"bench", R"(bench    [--scene S] [--quick|--full] [--threads N] [--json FILE] [--report DIR] [--no-report]
           [--reps N] [--build-reps N] [--rays N] [--sample N] [--stats-rays N]
           [--width-scenes S1,S2|none] [--refit-frames N] [--readme FILE] [--publish DIR]
           every method (bvh4, bvh8, bvh16 at every ISA the CPU has): builds cold and warm, Mrays/s (1 thread,
           all cores; median of --reps after a warm-up), accuracy; wide vs binary (width 2/4/8/16 per ISA:
           Mrays/s, nodes and box tests per ray, bytes/triangle, collapse time) on S and the width scenes
           (default: none; terrain with --full); the refit sequence (S twisted 0.1 rad more per frame, N
           frames, default 5, 20 with --full, 3 with --quick: BVH8 refit vs rebuild vs Embree's);
           --rays default 131,072 (262,144 with --full, 65,536 with --quick; --reps 5, 3 with --quick);
           report with charts and pictures, written only under DIR (default out) and all at once at the end.
           The maintainers' acts: --readme FILE rewrites FILE's results block (pictures in FILE's
           folder/docs/results/), --publish DIR the block of DIR/results.md (pictures in DIR/results/; a missing
           doc is created, one without the block gets it); blocks are checked before the run
bench --sweep [--quick] [--threads N] [--reps N] [--build-reps N] [--budget-ms MS] [--report DIR] [--json FILE]
           [--model-out accel/src/cost_model_fit.cpp] [--readme FILE] [--publish DIR] [--no-report]
           time to answer (build + trace) of brute, brute8, bvh2, bvh4/8/16, embree over soup-N and icosphere-N
           (1..1M triangles) x 1..1M rays; the cost model of --method auto fitted to it (written into
           --model-out for the active ISA) and checked at held-out points (dragon, bunny, teapot)
)"},
    {"render", R"(render   --scene S --out IMG.png [--method M] [--heatmap] [--width W] [--height H]
)"},
    {"panel", R"(panel    [--scene S] [--quick] [--json FILE] [--report DIR]          build quality per builder
           [--threads N] [--reps N] [--rays N] [--stats-rays N] [--no-report]
)"},
    {"accuracy",
     R"(accuracy [--quick] [--family F] [--report DIR] [--json FILE] [--no-embree]   ray families x method variants
           [--seed K] [--threads N] [--scene S (for the random family)] [--inside] [--no-open3d]
           and the inside/outside panel (ours vs Embree hit parity and Open3D's compute_occupancy against CGAL;
           without --family, or --inside)
)"},
};

constexpr const char* kFooter =
    R"(S is a scene name (dragon, dragon-res2..4, bunny, teapot, icosphere[-N], soup[-N], terrain) or a mesh file
(.ply .obj .stl .off, optionally .gz). SIMDBVH_ISA=scalar|avx2|avx512 or --isa forces the ISA.
Outputs (--out, --mesh-out, --json, --report) are checked before any work, must not be an input (nor a file a
scene leads to), and are replaced only when complete, several outputs all at once (symlinks written through,
devices and FIFOs written directly).
)";

}  // namespace

std::string usage() {
    std::string s = "usage: simdbvh <command> [options]     (simdbvh <command> --help, simdbvh --version)\ncommands:\n";
    for (const CommandText& c : kCommands) {
        s += "  ";
        s += c.text;
    }
    return s + kFooter;
}

std::string command_usage(const std::string& command) {
    for (const CommandText& c : kCommands)
        if (command == c.name) {
            std::string s = "usage: simdbvh ";
            s += c.text;
            return s + kFooter;
        }
    return {};
}

std::string version_line() {
    std::string s = "simdbvh " SIMDBVH_VERSION;
    try {
        s += " (isa ";
        s += name(active_isa());
        s += "; supported:";
        for (Isa isa : supported_isas()) {
            s += ' ';
            s += name(isa);
        }
        s += ')';
    } catch (const Error& e) {
        s += " (isa: ";
        s += e.what();
        s += ')';
    }
    return s;
}

}  // namespace simdbvh::cli
