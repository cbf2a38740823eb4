// SPDX-License-Identifier: MIT
#include "report.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <fstream>
#include <span>

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

bool run_chart_script(const std::string& script, const std::string& json_file, const std::string& out_dir) {
    const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string path = std::string(SIMDBVH_SOURCE_DIR) + "/scripts/" + script;
    std::cout.flush();
    // posix_spawn, no shell: the paths reach the script as they are. Its stdout (noise here) goes to /dev/null.
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    const char* argv[] = {py.c_str(), path.c_str(), json_file.c_str(), out_dir.c_str(), nullptr};
    pid_t pid = 0;
    const int err = ::posix_spawnp(&pid, argv[0], &fa, nullptr, const_cast<char* const*>(argv), environ);
    posix_spawn_file_actions_destroy(&fa);
    int status = 0;
    const bool ok = err == 0 && ::waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (!ok)
        std::cerr << "[simdbvh] warning: chart script failed (" << py << " " << path << " " << json_file << " "
                  << out_dir << "; needs matplotlib); the report has tables only\n";
    return ok;
}

}  // namespace simdbvh::cli
