// SPDX-License-Identifier: MIT
#include "report.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <fstream>
#include <span>
#include <string_view>
#include <thread>

#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/output.h"

namespace simdbvh::cli {

namespace fs = std::filesystem;

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

Table::Table(std::vector<std::string> header, std::string align) : header_(std::move(header)), align_(std::move(align)) {
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
    scene::write_file_atomic(file, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

void replace_marked_block(const fs::path& file, const std::string& begin, const std::string& end,
                          const std::string& body) {
    std::ifstream f(file);
    if (!f) throw Error(file.string() + ": cannot read");
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string text = ss.str();
    const auto pb = text.find(begin), pe = text.find(end);
    if (pb == std::string::npos || pe == std::string::npos || pe < pb)
        throw Error(file.string() + ": no '" + begin + "' ... '" + end + "' block");
    write_text(file, text.substr(0, pb + begin.size()) + body + text.substr(pe));
}

bool PythonRun::ok() const { return started && !timed_out && WIFEXITED(status) && WEXITSTATUS(status) == 0; }

int PythonRun::exit_code() const { return started && !timed_out && WIFEXITED(status) ? WEXITSTATUS(status) : -1; }

std::string PythonRun::describe() const {
    if (!started) return "could not start python3";
    if (timed_out) return "timed out";
    if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status))
        return "killed by signal " + std::to_string(WTERMSIG(status)) + " (" + ::strsignal(WTERMSIG(status)) + ")";
    return "wait status " + std::to_string(status);
}

PythonRun run_python_script(const std::string& script, const std::vector<std::string>& args,
                            const PythonOptions& options) {
    const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string path = std::string(SIMDBVH_SOURCE_DIR) + "/scripts/" + script;
    std::vector<const char*> argv{py.c_str(), path.c_str()};
    for (const std::string& a : args) argv.push_back(a.c_str());
    argv.push_back(nullptr);
    // Our environment, with the options' entries replacing any of the same name.
    std::vector<const char*> envp;
    for (char** e = environ; *e; ++e) {
        const std::string_view entry(*e);
        const bool replaced = std::any_of(options.env.begin(), options.env.end(), [&](const std::string& o) {
            const auto eq = o.find('=');
            return entry.substr(0, entry.find('=')) == std::string_view(o).substr(0, eq);
        });
        if (!replaced) envp.push_back(*e);
    }
    for (const std::string& o : options.env) envp.push_back(o.c_str());
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
    PythonRun run;
    pid_t pid = 0;
    const int err = ::posix_spawnp(&pid, argv[0], &fa, nullptr, const_cast<char* const*>(argv.data()),
                                   const_cast<char* const*>(envp.data()));
    posix_spawn_file_actions_destroy(&fa);
    if (err != 0) return run;
    run.started = true;
    if (options.timeout_seconds <= 0) {
        while (::waitpid(pid, &run.status, 0) < 0 && errno == EINTR) {
        }
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

bool run_chart_script(const std::string& script, const std::string& json_file, const std::string& out_dir) {
    const PythonRun run = run_python_script(script, {json_file, out_dir});
    if (!run.ok())
        std::cerr << "[simdbvh] warning: chart script failed (scripts/" << script << " " << json_file << " " << out_dir
                  << ": " << run.describe() << "; needs /usr/bin/python3 with matplotlib); the report has tables only\n";
    return run.ok();
}

}  // namespace simdbvh::cli
