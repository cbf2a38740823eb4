// SPDX-License-Identifier: MIT
// Open3D's compute_occupancy through the Python worker (open3d_inside.h).
#include "lab.h"
#include "open3d_inside.h"

#include <unistd.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "report.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/write_ply.h"
#include "simdbvh/io/output.h"
#include "simdbvh/io/point_files.h"

namespace simdbvh::lab {

namespace {

namespace fs = std::filesystem;

constexpr int kNoOpen3d = 3;  // the worker's exit status when python3 cannot import open3d

// A folder of our own under the system's temporary folder, removed with everything in it.
struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        path = fs::temp_directory_path() /
               ("simdbvh_open3d_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

std::vector<unsigned char> read_bytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The last non-empty line the worker wrote on stderr (a Python traceback ends with the error), shortened.
std::string last_line(const fs::path& p) {
    std::ifstream f(p);
    std::string line, last;
    while (std::getline(f, line))
        if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
    return last.size() > 200 ? last.substr(0, 200) + "..." : last;
}

}  // namespace

Open3dAnswer parse_occupancy(std::span<const unsigned char> bytes, std::size_t points) {
    if (bytes.size() != 8 + points)
        throw Error("Open3D worker output: " + std::to_string(bytes.size()) + " bytes, expected 8 + " +
                    std::to_string(points));
    static_assert(std::endian::native == std::endian::little, "the worker writes little-endian float64");
    Open3dAnswer a;
    std::memcpy(&a.seconds, bytes.data(), 8);
    if (!std::isfinite(a.seconds) || a.seconds < 0) throw Error("Open3D worker output: bad seconds");
    a.sides.resize(points);
    for (std::size_t i = 0; i < points; ++i) {
        const unsigned char b = bytes[8 + i];
        if (b > 1)
            throw Error("Open3D worker output: byte " + std::to_string(int(b)) + " for point " + std::to_string(i));
        a.sides[i] = b ? Side::inside : Side::outside;
    }
    return a;
}

Open3dRun run_open3d_occupancy(std::span<const Open3dJob> jobs, double timeout_seconds) {
    Open3dRun run;
    run.answers.resize(jobs.size());
    const TempDir dir;
    std::map<const Mesh*, std::string> mesh_files;
    std::vector<std::string> point_files(jobs.size()), out_files(jobs.size());
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        auto [it, added] = mesh_files.try_emplace(jobs[i].mesh);
        if (added) {
            it->second = (dir.path / ("mesh" + std::to_string(mesh_files.size()) + ".ply")).string();
            io::write_ply(it->second, *jobs[i].mesh);
        }
        point_files[i] = (dir.path / ("points" + std::to_string(i) + ".bin")).string();
        out_files[i] = (dir.path / ("occupancy" + std::to_string(i) + ".bin")).string();
        io::write_file_atomic(point_files[i], io::encode_points(jobs[i].points));
    }
    PythonOptions opt;
    opt.env = {"OMP_NUM_THREADS=1"};
    opt.stderr_file = (dir.path / "stderr.txt").string();
    opt.timeout_seconds = timeout_seconds;
    // One worker for every job left; when it dies, the job it was on fails and a new worker takes the rest.
    for (std::size_t next = 0; next < jobs.size();) {
        std::vector<std::string> args{"--shim-dir", dir.path.string()};  // the shim is compiled once per run
        for (std::size_t i = next; i < jobs.size(); ++i)
            args.insert(args.end(), {mesh_files[jobs[i].mesh], point_files[i], out_files[i]});
        const PythonRun child = run_python_script("open3d/inside_worker.py", args, opt);
        if (!child.started || child.exit_code() == kNoOpen3d) {
            run.available = false;
            run.message = child.started ? last_line(opt.stderr_file) : child.describe();
            run.answers.clear();
            return run;
        }
        std::size_t done = next;
        for (; done < jobs.size() && fs::exists(out_files[done]); ++done) {
            try {
                run.answers[done] = parse_occupancy(read_bytes(out_files[done]), jobs[done].points.size());
            } catch (const Error& e) {
                run.answers[done].error = e.what();
            }
        }
        if (done == jobs.size()) break;
        std::string why = child.describe();
        if (child.timed_out) why += " after " + std::to_string(int(timeout_seconds)) + " s";
        if (const std::string line = last_line(opt.stderr_file); !line.empty()) why += ": " + line;
        if (child.ok()) why = "the worker wrote no answer";
        run.answers[done].error = why;
        if (child.timed_out) {  // no second wait of that length
            for (std::size_t i = done + 1; i < jobs.size(); ++i) run.answers[i].error = "not run: the worker " + why;
            break;
        }
        next = done + 1;
    }
    return run;
}

}  // namespace simdbvh::lab
