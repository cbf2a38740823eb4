// SPDX-License-Identifier: MIT
#include "report.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <fstream>
#include <optional>
#include <span>
#include <string_view>
#include <thread>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/output.h"

namespace simdbvh::cli {

namespace fs = std::filesystem;

namespace {
std::atomic<pid_t> g_running_script{0};
static_assert(std::atomic<pid_t>::is_always_lock_free);
}  // namespace

std::string command_line(const std::string& command, const std::vector<std::string>& args) {
    std::string s = "simdbvh " + command;
    for (const std::string& a : args) s += " " + a;
    return s;
}

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

Table::Table(std::vector<std::string> header, std::string align)
    : header_(std::move(header)), align_(std::move(align)) {
    if (align_.empty()) align_.push_back('l');
    align_.resize(header_.size(), 'r');
}

Table& Table::row(std::vector<std::string> cells) {
    cells.resize(header_.size());
    rows_.push_back(std::move(cells));
    return *this;
}

std::string Table::markdown() const {
    std::string s = "|";
    for (const std::string& h : header_) s += " " + h + " |";
    s += "\n|";
    for (char a : align_) s += a == 'l' ? "---|" : "---:|";
    s += "\n";
    for (const auto& r : rows_) {
        s += "|";
        for (const std::string& c : r) s += " " + c + " |";
        s += "\n";
    }
    return s;
}

std::string Table::text() const {
    std::vector<std::size_t> w(header_.size());
    for (std::size_t i = 0; i < header_.size(); ++i) w[i] = header_[i].size();
    for (const auto& r : rows_)
        for (std::size_t i = 0; i < r.size(); ++i) w[i] = std::max(w[i], r[i].size());
    auto line = [&](const std::vector<std::string>& cells) {
        std::string s;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const std::string pad(w[i] - cells[i].size(), ' ');
            s += (i ? "  " : "") + (align_[i] == 'l' ? cells[i] + pad : pad + cells[i]);
        }
        while (!s.empty() && s.back() == ' ') s.pop_back();
        return s + "\n";
    };
    std::string s = line(header_);
    for (const auto& r : rows_) s += line(r);
    return s;
}

std::string json_text(const Json& doc) {
    return doc.dump(2, ' ', /*ensure_ascii=*/false, nlohmann::json::error_handler_t::replace) + "\n";
}

void write_text(const fs::path& file, const std::string& text) {
    if (file.has_parent_path()) fs::create_directories(file.parent_path());
    io::write_file_atomic(file, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

std::string with_marked_block(const fs::path& file, const std::string& begin, const std::string& end,
                              const std::string& body) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) throw Error(file.string() + ": cannot read (not a regular file)");
    std::ifstream f(file, std::ios::binary);
    if (!f) throw Error(file.string() + ": cannot read");
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string text = ss.str();
    const auto pb = text.find(begin), pe = text.find(end);
    if (pb == std::string::npos || pe == std::string::npos || pe < pb)
        throw Error(file.string() + ": no '" + begin + "' ... '" + end + "' block");
    if (text.find(begin, pb + 1) != std::string::npos || text.find(end, pe + 1) != std::string::npos)
        throw Error(file.string() + ": the '" + begin + "' ... '" + end + "' block is there twice");
    return text.substr(0, pb + begin.size()) + body + text.substr(pe);
}

void check_marked_block(const fs::path& file, const std::string& begin, const std::string& end) {
    (void)with_marked_block(file, begin, end, "");
}

void ReportFiles::add(const fs::path& file, const std::string& text) {
    add(file, std::vector<unsigned char>(text.begin(), text.end()));
}

void ReportFiles::add(const fs::path& file, std::vector<unsigned char> bytes) {
    const fs::path key = file.lexically_normal();
    for (auto& [p, b] : files_)
        if (p == key) {
            b = std::move(bytes);
            return;
        }
    files_.emplace_back(key, std::move(bytes));
}

const std::vector<unsigned char>* ReportFiles::find(const fs::path& file) const {
    const fs::path key = file.lexically_normal();
    for (const auto& [p, b] : files_)
        if (p == key) return &b;
    return nullptr;
}

std::vector<fs::path> ReportFiles::paths() const {
    std::vector<fs::path> v;
    for (const auto& f : files_) v.push_back(f.first);
    return v;
}

bool ReportFiles::add_charts(const std::string& script, const std::string& json, const std::string& json_name,
                             const fs::path& dir) {
    std::optional<io::StagingDir> staging;
    try {
        staging.emplace();
        io::write_file_atomic(staging->path() / json_name,
                              std::span(reinterpret_cast<const unsigned char*>(json.data()), json.size()));
    } catch (const Error& e) {
        std::cerr << "[simdbvh] warning: no charts (" << e.what() << "); the report has tables only\n";
        return false;
    }
    const bool ok = run_chart_script(script, (staging->path() / json_name).string(), staging->path().string());
    if (!ok) return false;
    std::vector<fs::path> pictures;
    for (const auto& e : fs::directory_iterator(staging->path()))
        if (e.is_regular_file() && e.path().extension() == ".png") pictures.push_back(e.path());
    std::sort(pictures.begin(), pictures.end());
    for (const fs::path& p : pictures) {
        std::ifstream f(p, std::ios::binary);
        std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        if (!f && !f.eof()) throw Error(p.string() + ": cannot read the chart");
        add(dir / p.filename(), std::move(bytes));
    }
    return true;
}

void ReportFiles::commit() const {
    // The folders to create, outermost first, so that exactly those are removed on failure.
    std::vector<fs::path> created;
    for (const auto& [p, b] : files_) {
        std::vector<fs::path> missing;
        std::error_code ec;
        for (fs::path d = p.parent_path(); !d.empty() && !fs::exists(d, ec); d = d.parent_path()) missing.push_back(d);
        for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
            if (!fs::create_directory(*it, ec) && ec) {
                for (auto c = created.rbegin(); c != created.rend(); ++c) fs::remove_all(*c, ec);
                throw Error(it->string() + ": cannot create the folder: " + ec.message());
            }
            created.push_back(*it);
        }
    }
    std::vector<io::OutputFile> out;
    for (const auto& [p, b] : files_) out.push_back({p, b});
    try {
        io::write_files_atomic(out);
    } catch (...) {
        std::error_code ec;
        for (auto c = created.rbegin(); c != created.rend(); ++c) fs::remove_all(*c, ec);
        throw;
    }
}

bool PythonRun::ok() const { return started && !timed_out && WIFEXITED(status) && WEXITSTATUS(status) == 0; }

int PythonRun::exit_code() const { return started && !timed_out && WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

std::string PythonRun::describe() const {
    if (!missing.empty()) return missing;
    if (!started) return "could not start python3";
    if (timed_out) return "timed out";
    if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status))
        return "killed by signal " + std::to_string(WTERMSIG(status)) + " (" + ::strsignal(WTERMSIG(status)) + ")";
    return "wait status " + std::to_string(status);
}

std::filesystem::path scripts_dir() {
    // No path is baked in at build time: the environment, else the executable's own tree (the build tree puts
    // share/simdbvh beside the simdbvh binary, one or two levels above the test binaries; an install puts it
    // in <prefix>/share/simdbvh beside <prefix>/bin). Empty when none is found.
    if (const char* env = std::getenv("SIMDBVH_SCRIPTS"); env && *env) return fs::path(env);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    fs::path root = exe.parent_path();
    for (int up = 0; up < 3 && !root.empty(); ++up, root = root.parent_path()) {
        const fs::path d = root / "share" / "simdbvh" / "scripts";
        if (fs::is_directory(d, ec)) return d;
    }
    return {};
}

PythonRun run_python_script(const std::string& script, const std::vector<std::string>& args,
                            const PythonOptions& options) {
    const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const fs::path dir = scripts_dir();
    PythonRun run;
    if (dir.empty()) {
        run.missing = "no share/simdbvh/scripts beside this executable and SIMDBVH_SCRIPTS is not set";
        return run;
    }
    const std::string path = (dir / script).string();
    std::vector<const char*> argv{py.c_str(), path.c_str()};
    for (const std::string& a : args) argv.push_back(a.c_str());
    argv.push_back(nullptr);
    // Our environment, with the options' entries replacing any of the same name.
    std::vector<const char*> envp;
    for (char** e = environ; *e; ++e) {
        const std::string_view entry(*e);
        const std::string_view key = entry.substr(0, entry.find('='));
        const bool replaced = key == "PYTHONDONTWRITEBYTECODE" ||
                              std::any_of(options.env.begin(), options.env.end(), [&](const std::string& o) {
                                  return key == std::string_view(o).substr(0, o.find('='));
                              });
        if (!replaced) envp.push_back(*e);
    }
    for (const std::string& o : options.env) envp.push_back(o.c_str());
    const bool bytecode_set = std::any_of(options.env.begin(), options.env.end(), [](const std::string& o) {
        return o.rfind("PYTHONDONTWRITEBYTECODE=", 0) == 0;
    });
    if (!bytecode_set) envp.push_back("PYTHONDONTWRITEBYTECODE=1");
    envp.push_back(nullptr);
    std::cout.flush();
    std::cerr.flush();
    // posix_spawn, no shell: the paths reach the script as they are. Its stdout (noise here) goes to /dev/null.
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    if (!options.stderr_file.empty())
        posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, options.stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                         0644);
    // The cleanup signals stay blocked from the spawn until the child's id is stored, so the handler always
    // sees the child it must stop (else the script could recreate a staging folder the handler removed);
    // the child starts with the mask we had.
    sigset_t cleanup_signals, old_mask;
    sigemptyset(&cleanup_signals);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&cleanup_signals, sig);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    pthread_sigmask(SIG_BLOCK, &cleanup_signals, &old_mask);
    posix_spawnattr_setsigmask(&attr, &old_mask);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
    pid_t pid = 0;
    const int err = ::posix_spawnp(&pid, argv[0], &fa, &attr, const_cast<char* const*>(argv.data()),
                                   const_cast<char* const*>(envp.data()));
    if (err == 0) g_running_script.store(pid);
    pthread_sigmask(SIG_SETMASK, &old_mask, nullptr);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&fa);
    if (err != 0) return run;
    run.started = true;
    struct Forget {
        ~Forget() { g_running_script.store(0); }
    } forget;
    if (options.timeout_seconds <= 0) {
        while (::waitpid(pid, &run.status, 0) < 0 && errno == EINTR) {}
        return run;
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout_seconds);
    for (;;) {
        const pid_t r = ::waitpid(pid, &run.status, WNOHANG);
        if (r == pid || (r < 0 && errno != EINTR)) return run;
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(pid, SIGKILL);  // the child we started, by its id
            ::waitpid(pid, &run.status, 0);
            run.timed_out = true;
            return run;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

int running_script_pid() noexcept { return g_running_script.load(); }

bool run_chart_script(const std::string& script, const std::string& json_file, const std::string& out_dir) {
    const PythonRun run = run_python_script(script, {json_file, out_dir});
    if (!run.ok())
        std::cerr << "[simdbvh] warning: chart script failed (" << script << " " << json_file << " " << out_dir << ": "
                  << run.describe() << "; needs /usr/bin/python3 with matplotlib); the report has tables only\n";
    return run.ok();
}

}  // namespace simdbvh::cli
