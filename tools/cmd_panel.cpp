// simdbvh panel: build quality per builder. For each builder (binned SAH at
// 8/16/32/64 bins, sweep SAH, midpoint, median, variance) and seed 002's
// sphere hierarchy: build time with 1 thread and all cores, SAH cost, depth,
// leaf-size histogram, bytes/triangle, BVH2 and BVH8 Mrays/s (one thread,
// closest hit, primary/incoherent/diffuse), nodes visited per ray (counted on
// a sample), the time to trace one 640x480 primary frame with the BVH2 on one
// thread, and agreement of that frame with the binned-SAH reference. A table,
// a JSON file and DIR/panel.md with charts (scripts/plot_panel.py).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "common.h"
#include "methods.h"
#include "outputs.h"
#include "options.h"
#include "simdbvh/bvh2/spheres.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/topology.h"
#include "simdbvh/scene/rays.h"

namespace simdbvh::cli {

namespace {

namespace fs = std::filesystem;
using scene::RayKind;

constexpr RayKind kKinds[] = {RayKind::primary, RayKind::incoherent, RayKind::diffuse};
constexpr int kFrameW = 640, kFrameH = 480;
// Sweep SAH is not skipped on large scenes: it builds the full dragon (871k
// triangles) in about 7 s on one thread, far under the 60 s that would have
// justified skipping it there.
// Leaf-size histogram buckets: 1, 2, 3, 4, 5-8, 9-16, 17+.
constexpr std::array<const char*, 7> kLeafBuckets = {"1", "2", "3", "4", "5-8", "9-16", "17+"};
int leaf_bucket(std::uint32_t n) {
    if (n <= 4) return int(n) - 1;
    if (n <= 8) return 4;
    if (n <= 16) return 5;
    return 6;
}

struct Row {
    std::string name;     // e.g. "sah-binned/16", "spheres"
    std::string builder;  // the BVH2 builder ("variance" for spheres)
    int bins = 0;
    bool skipped = false;
    std::string note;
    double build_ms_1 = 0, build_ms_all = 0, bvh8_ms = 0;
    double sah = 0, sah_bvh8 = 0, bytes_per_tri = 0, bytes_per_tri_bvh8 = 0;
    int depth = 0;
    std::size_t nodes = 0, leaves = 0;
    std::array<std::size_t, 7> leaf_hist{};
    std::array<double, 3> mrays2{}, mrays8{};         // per kind, closest hit, 1 thread
    std::array<double, 3> nodes_per_ray2{}, nodes_per_ray8{}, tris_per_ray2{};
    double frame_ms = 0;        // 640x480 primary, BVH2 (or spheres), 1 thread, closest hit
    double frame_ms_bvh8 = 0;
    std::size_t frame_mismatch = 0;  // frame hits that differ (bitwise) from the reference row
};

// Best (smallest) seconds of `reps` runs of f: on a shared machine the
// minimum is the least disturbed estimate.
template <class F>
double time_best(int reps, F&& f) {
    std::vector<double> s;
    for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        s.push_back(seconds_since(t0));
    }
    return *std::min_element(s.begin(), s.end());
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

void write_text(const fs::path& file, const std::string& text) {
    if (file.has_parent_path()) fs::create_directories(file.parent_path());
    scene::write_file_atomic(file, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

std::string to_json(const std::vector<Row>& rows, const std::string& scene, std::size_t tris, const std::string& machine,
                    const std::string& isa, int threads_all, std::size_t nrays, std::size_t nstats,
                    const std::string& command) {
    std::ostringstream j;
    j.precision(7);
    j << "{\n  \"scene\": \"" << scene << "\",\n  \"triangles\": " << tris << ",\n  \"machine\": \"" << machine
      << "\",\n  \"bvh8_isa\": \"" << isa << "\",\n  \"threads_all\": " << threads_all << ",\n  \"rays_per_kind\": " << nrays
      << ",\n  \"stats_sample\": " << nstats << ",\n  \"frame\": \"" << kFrameW << "x" << kFrameH
      << " primary, closest hit, 1 thread\",\n  \"command\": \"" << command << "\",\n  \"rows\": [\n";
    auto arr = [&](const auto& a) {
        std::ostringstream s;
        s.precision(7);
        s << "[";
        for (std::size_t i = 0; i < a.size(); ++i) s << (i ? ", " : "") << a[i];
        s << "]";
        return s.str();
    };
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        j << "    {\"name\": \"" << r.name << "\", \"builder\": \"" << r.builder << "\", \"bins\": " << r.bins
          << ", \"skipped\": " << (r.skipped ? "true" : "false") << ", \"note\": \"" << r.note << "\"";
        if (!r.skipped) {
            j << ", \"build_ms_1\": " << r.build_ms_1 << ", \"build_ms_all\": " << r.build_ms_all
              << ", \"bvh8_collapse_ms\": " << r.bvh8_ms << ", \"sah_cost\": " << r.sah
              << ", \"sah_cost_bvh8\": " << r.sah_bvh8 << ", \"depth\": " << r.depth << ", \"nodes\": " << r.nodes
              << ", \"leaves\": " << r.leaves << ", \"leaf_hist\": " << arr(r.leaf_hist)
              << ", \"bytes_per_triangle\": " << r.bytes_per_tri << ", \"bytes_per_triangle_bvh8\": " << r.bytes_per_tri_bvh8
              << ", \"mrays_bvh2\": " << arr(r.mrays2) << ", \"mrays_bvh8\": " << arr(r.mrays8)
              << ", \"nodes_per_ray_bvh2\": " << arr(r.nodes_per_ray2) << ", \"nodes_per_ray_bvh8\": " << arr(r.nodes_per_ray8)
              << ", \"triangles_per_ray_bvh2\": " << arr(r.tris_per_ray2) << ", \"frame_ms\": " << r.frame_ms
              << ", \"frame_ms_bvh8\": " << r.frame_ms_bvh8 << ", \"frame_mismatches\": " << r.frame_mismatch;
        }
        j << "}" << (i + 1 < rows.size() ? ",\n" : "\n");
    }
    j << "  ],\n  \"ray_kinds\": [\"primary\", \"incoherent\", \"diffuse\"],\n  \"leaf_buckets\": [";
    for (std::size_t i = 0; i < kLeafBuckets.size(); ++i) j << (i ? ", " : "") << "\"" << kLeafBuckets[i] << "\"";
    j << "]\n}\n";
    return j.str();
}

std::string md_table(const std::vector<Row>& rows, int threads_all) {
    std::ostringstream s;
    s << "| builder | build ms 1 thr | build ms " << threads_all
      << " thr | SAH | depth | B/tri | BVH2 Mrays/s prim / incoh / diff | BVH8 Mrays/s prim / incoh / diff | "
         "BVH2 nodes/ray prim / incoh / diff | frame ms BVH2 | frame ms BVH8 |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Row& r : rows) {
        if (r.skipped) {
            s << "| " << r.name << " | skipped: " << r.note << " |||||||||| \n";
            continue;
        }
        auto three = [](const std::array<double, 3>& a, const char* f) {
            return fmt(f, a[0]) + " / " + fmt(f, a[1]) + " / " + fmt(f, a[2]);
        };
        const bool sph = r.name == "spheres";
        s << "| " << r.name << " | " << fmt("%.0f", r.build_ms_1) << " | " << fmt("%.0f", r.build_ms_all) << " | "
          << fmt("%.2f", r.sah) << " | " << r.depth << " | " << fmt("%.1f", r.bytes_per_tri) << " | "
          << three(r.mrays2, "%.3g") << " | " << (sph ? std::string("n/a") : three(r.mrays8, "%.3g")) << " | "
          << three(r.nodes_per_ray2, "%.0f") << " | " << fmt("%.0f", r.frame_ms) << " | "
          << (sph ? std::string("n/a") : fmt("%.0f", r.frame_ms_bvh8)) << " |\n";
    }
    return s.str();
}

std::string leaf_table(const std::vector<Row>& rows) {
    std::ostringstream s;
    s << "| builder | nodes | leaves |";
    for (const char* b : kLeafBuckets) s << " " << b << " |";
    s << "\n|---|---:|---:|";
    for (std::size_t i = 0; i < kLeafBuckets.size(); ++i) s << "---:|";
    s << "\n";
    for (const Row& r : rows) {
        if (r.skipped) continue;
        s << "| " << r.name << " | " << r.nodes << " | " << r.leaves << " |";
        for (std::size_t c : r.leaf_hist) s << " " << c << " |";
        s << "\n";
    }
    return s.str();
}

template <class NodeVec>
void leaf_stats(const NodeVec& nodes, Row& row) {
    for (const auto& n : nodes)
        if (n.is_leaf()) {
            ++row.leaves;
            ++row.leaf_hist[std::size_t(leaf_bucket(n.count))];
        }
}

}  // namespace

int cmd_panel(const std::vector<std::string>& args) {
    const Options o("panel", args, {"scene", "threads", "json", "report", "reps", "rays", "stats-rays"},
                    {"quick", "no-report"});
    std::string why;
    const std::string scene_name = o.has("scene") ? o.get("scene") : default_scene(&why);
    const bool quick = o.has("quick");
    const Topology& topo = topology();
    const int all = int(o.get_int("threads", std::max(1, topo.physical_cores), 1, 1024));
    const int reps = int(o.get_int("reps", quick ? 3 : 5, 1, 100));
    const int build_reps = std::min(reps, 3);
    const auto nrays = std::size_t(o.get_int("rays", quick ? 65536 : 262144, 1024, 1 << 26));
    const auto nstats = std::size_t(o.get_int("stats-rays", quick ? 8192 : 32768, 256, 1 << 24));
    const std::string report_dir = o.get("report", "out");
    const std::string json_file = o.get("json", report_dir + "/panel.json");
    NamedPaths outputs{{"--json", json_file}};
    if (!o.has("no-report")) outputs.emplace_back("--report", report_dir + "/panel.md");
    check_outputs(outputs, {{"--scene", scene_name}}, /*create_parent=*/true);
    const std::string machine = machine_line();
    const Isa isa = active_isa();
    std::string command = "simdbvh panel";
    for (const std::string& a : args) command += " " + a;

    progress("scene: " + scene_name + (why.empty() ? "" : " (" + why + ")"), true);
    progress("machine: " + machine, true);
    const Mesh mesh = load_scene_with_progress(scene_name);

    std::vector<std::vector<Ray>> rays;
    for (RayKind k : kKinds) {
        progress("generating " + std::to_string(nrays) + " " + std::string(scene::name(k)) + " rays", true);
        rays.push_back(scene::generate_rays(mesh, k, nrays, 42));
    }
    // The stats sample: every k-th ray (a primary set's first rows may all miss).
    std::vector<std::vector<Ray>> sample(3);
    for (int k = 0; k < 3; ++k) {
        const std::size_t stride = std::max<std::size_t>(1, rays[k].size() / nstats);
        for (std::size_t i = 0; i < rays[k].size() && sample[k].size() < nstats; i += stride) sample[k].push_back(rays[k][i]);
    }
    const std::vector<Ray> frame = scene::primary_rays(scene::default_camera(mesh.bounds(), kFrameW, kFrameH));
    std::vector<Hit> ref_frame, hits(std::max(nrays, frame.size()));

    std::vector<Row> rows;
    auto add = [&](std::string nm, std::string builder, int bins) {
        Row r;
        r.name = std::move(nm);
        r.builder = std::move(builder);
        r.bins = bins;
        rows.push_back(std::move(r));
    };
    for (int bins : {8, 16, 32, 64}) add("sah-binned/" + std::to_string(bins), "sah-binned", bins);
    for (const char* b : {"sah-sweep", "midpoint", "median", "variance"}) add(b, b, 0);
    add("spheres", "variance", 0);
    std::vector<std::string> notes;

    for (Row& row : rows) {
        BuildOptions bo;
        bo.builder = *parse_builder(row.builder);
        if (row.bins) bo.bins = row.bins;
        auto run_stats = [&](auto&& trace_one, std::array<double, 3>& nodes_pr, std::array<double, 3>* tris_pr) {
            for (int k = 0; k < 3; ++k) {
                TraceStats st;
                const std::size_t n = sample[k].size();
                trace_one(std::span<const Ray>(sample[k]), std::span<Hit>(hits).first(n), &st);
                nodes_pr[k] = st.rays ? double(st.nodes_visited) / double(st.rays) : 0;
                if (tris_pr) (*tris_pr)[k] = st.rays ? double(st.triangle_tests) / double(st.rays) : 0;
            }
        };
        auto run_speed = [&](auto&& trace_one, std::array<double, 3>& mr) {
            for (int k = 0; k < 3; ++k) {
                const double s = time_best(reps, [&] { trace_one(rays[k], std::span<Hit>(hits).first(rays[k].size()), nullptr); });
                mr[k] = double(rays[k].size()) / s / 1e6;
            }
        };
        auto run_frame = [&](auto&& trace_one, double& ms, bool check) {
            ms = 1e3 * time_best(reps, [&] { trace_one(frame, std::span<Hit>(hits).first(frame.size()), nullptr); });
            if (!check) return;
            if (ref_frame.empty()) ref_frame.assign(hits.begin(), hits.begin() + std::ptrdiff_t(frame.size()));
            for (std::size_t i = 0; i < frame.size(); ++i) row.frame_mismatch += !(hits[i] == ref_frame[i]);
        };

        if (row.name == "spheres") {
            progress("building spheres (1 thread)", true);
            SphereBvh sb = SphereBvh::build(mesh, bo);
            row.build_ms_1 = sb.stats().build_ms;
            for (int r = 1; r < build_reps; ++r) row.build_ms_1 = std::min(row.build_ms_1, SphereBvh::build(mesh, bo).stats().build_ms);
            {
                BuildOptions many = bo;
                many.threads = all;
                progress("building spheres (" + std::to_string(all) + " threads)", true);
                row.build_ms_all = 1e300;
                for (int r = 0; r < build_reps; ++r)
                    row.build_ms_all = std::min(row.build_ms_all, SphereBvh::build(mesh, many).stats().build_ms);
            }
            const SphereBuildStats& st = sb.stats();
            row.sah = st.sah_cost;
            row.depth = st.depth;
            row.nodes = st.nodes;
            row.bytes_per_tri = st.bytes_per_triangle;
            row.note = "AABB SAH of the variance topology; sphere-area SAH " + fmt("%.2f", st.sphere_sah_cost);
            leaf_stats(sb.nodes(), row);
            auto tr = [&](std::span<const Ray> r, std::span<Hit> h, TraceStats* s) {
                TraceOptions to;
                to.stats = s;
                intersect(sb, r, h, to);
            };
            progress("tracing spheres", true);
            run_stats(tr, row.nodes_per_ray2, &row.tris_per_ray2);
            run_speed(tr, row.mrays2);
            run_frame(tr, row.frame_ms, true);
            continue;
        }

        progress("building " + row.name + " (1 thread)", true);
        const Bvh2 b2 = Bvh2::build(mesh, bo);
        row.build_ms_1 = b2.stats().build_ms;
        for (int r = 1; r < build_reps; ++r) row.build_ms_1 = std::min(row.build_ms_1, Bvh2::build(mesh, bo).stats().build_ms);
        {
            BuildOptions many = bo;
            many.threads = all;
            progress("building " + row.name + " (" + std::to_string(all) + " threads)", true);
            row.build_ms_all = 1e300;
            for (int r = 0; r < build_reps; ++r)
                row.build_ms_all = std::min(row.build_ms_all, Bvh2::build(mesh, many).stats().build_ms);
        }
        const BuildStats& st = b2.stats();
        row.sah = st.sah_cost;
        row.depth = st.depth;
        row.nodes = st.nodes;
        row.bytes_per_tri = st.bytes_per_triangle;
        leaf_stats(b2.nodes(), row);
        const Bvh8 b8 = Bvh8::build(b2);
        row.bvh8_ms = b8.stats().build_ms;
        row.sah_bvh8 = b8.stats().sah_cost;
        row.bytes_per_tri_bvh8 = b8.stats().bytes_per_triangle;

        auto tr2 = [&](std::span<const Ray> r, std::span<Hit> h, TraceStats* s) {
            TraceOptions to;
            to.stats = s;
            intersect(b2, r, h, to);
        };
        auto tr8 = [&](std::span<const Ray> r, std::span<Hit> h, TraceStats* s) {
            TraceOptions to;
            to.stats = s;
            intersect(b8, r, h, to, isa);
        };
        progress("tracing " + row.name + " (bvh2, bvh8/" + std::string(name(isa)) + ")", true);
        run_stats(tr2, row.nodes_per_ray2, &row.tris_per_ray2);
        run_stats(tr8, row.nodes_per_ray8, nullptr);
        run_speed(tr2, row.mrays2);
        run_speed(tr8, row.mrays8);
        run_frame(tr2, row.frame_ms, true);
        run_frame(tr8, row.frame_ms_bvh8, true);
    }

    // Terminal table.
    std::printf("\nscene %s, %zu triangles; %s; BVH8 on %s; build 1 and %d threads; trace 1 thread, closest hit,\n"
                "%zu rays per kind (best of %d; builds best of %d); nodes/ray on %zu evenly spaced rays; frame = %dx%d primary rays\n",
                scene_name.c_str(), mesh.size(), machine.c_str(), std::string(name(isa)).c_str(), all, nrays, reps,
                build_reps, nstats, kFrameW, kFrameH);
    std::printf("%-14s %8s %8s %7s %5s %6s | %-20s | %-20s | %-17s | %8s %8s %5s\n", "builder", "build1", "buildN",
                "SAH", "depth", "B/tri", "BVH2 Mr/s p/i/d", "BVH8 Mr/s p/i/d", "nodes/ray p/i/d", "frame2ms",
                "frame8ms", "diff");
    for (const Row& r : rows) {
        if (r.skipped) {
            std::printf("%-14s skipped: %s\n", r.name.c_str(), r.note.c_str());
            continue;
        }
        char b8[64], f8[16];
        if (r.name == "spheres") {
            std::snprintf(b8, sizeof b8, "%s", "n/a");
            std::snprintf(f8, sizeof f8, "%s", "n/a");
        } else {
            std::snprintf(b8, sizeof b8, "%6.3g %6.3g %6.3g", r.mrays8[0], r.mrays8[1], r.mrays8[2]);
            std::snprintf(f8, sizeof f8, "%.1f", r.frame_ms_bvh8);
        }
        std::printf("%-14s %8.1f %8.1f %7.2f %5d %6.1f | %6.3g %6.3g %6.3g | %-20s | %5.0f %5.0f %5.0f | %8.1f %8s %5zu\n",
                    r.name.c_str(), r.build_ms_1, r.build_ms_all, r.sah, r.depth, r.bytes_per_tri, r.mrays2[0],
                    r.mrays2[1], r.mrays2[2], b8, r.nodes_per_ray2[0], r.nodes_per_ray2[1], r.nodes_per_ray2[2],
                    r.frame_ms, f8, r.frame_mismatch);
    }
    for (const std::string& n : notes) std::printf("note: %s\n", n.c_str());
    std::printf("diff = frame hits (BVH2 + BVH8) not bit-identical to the %s row (0 expected)\n", rows[0].name.c_str());

    write_text(json_file, to_json(rows, scene_name, mesh.size(), machine, std::string(name(isa)), all, nrays, nstats, command));
    std::cout << "\nwrote " << json_file << "\n";
    if (o.has("no-report")) return 0;

    const fs::path dir = report_dir;
    fs::create_directories(dir);
    const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string cmd = py + " '" SIMDBVH_SOURCE_DIR "/scripts/plot_panel.py' '" + json_file + "' '" +
                            dir.string() + "'";
    const bool charts = std::system(cmd.c_str()) == 0;
    if (!charts) progress("charts failed (needs /usr/bin/python3 with matplotlib): " + cmd, true);
    std::ostringstream md;
    md << "# Build-quality panel: " << scene_name << "\n\n"
       << mesh.size() << " triangles" << (why.empty() ? "" : " (" + why + ")") << ". Machine: " << machine
       << ".\n\nCommand: `" << command << "`\n\n"
       << "Build times (BVH2 only; BVH8 collapse time is in the JSON) with 1 and " << all << " threads (BuildOptions::threads). Trace: one thread, closest hit, "
       << nrays << " rays per kind, best of " << reps << " runs (builds: best of " << build_reps
       << "; the machine is shared, the minimum is the least disturbed figure); BVH8 on " << name(isa)
       << ". Nodes visited per ray counted (TraceOptions::stats) on " << nstats
       << " rays of each kind (every k-th ray). Frame: one " << kFrameW << "x" << kFrameH
       << " primary image from the default camera, closest hit, one thread. SAH: C = sum of Ct*A(n)/A(root) over inner "
          "nodes + Ci*N*A(n)/A(root) over leaves, Ct = Ci = 1 (BVH2).\n\n"
       << md_table(rows, all) << "\n";
    for (const std::string& n : notes) md << "- " << n << "\n";
    for (const Row& r : rows)
        if (!r.skipped && r.name == "spheres") md << "- spheres: " << r.note << "; no BVH8 for spheres.\n";
    md << "- Every row's frame hits are compared bit for bit with the " << rows[0].name << " row: mismatches ";
    std::size_t mism = 0;
    for (const Row& r : rows) mism += r.frame_mismatch;
    md << mism << ".\n\n## Leaf sizes (BVH2 leaves by triangle count)\n\n" << leaf_table(rows) << "\n";
    if (charts)
        md << "## Charts\n\n![build time against trace speed](build_vs_trace.png)\n\n"
              "![SAH cost against measured speed](sah_vs_mrays.png)\n\n![leaf sizes](leaf_hist.png)\n";
    write_text(dir / "panel.md", md.str());
    std::cout << "wrote " << (dir / "panel.md").string() << "\n";
    return 0;
}

}  // namespace simdbvh::cli
