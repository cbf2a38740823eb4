// SPDX-License-Identifier: MIT
#pragma once
// The CLI's one report layer. A command fills a Report (the JSON document the
// chart scripts read, and the Markdown text) and writes it here; tables are
// Table rows written as Markdown or as aligned terminal text. No command
// writes JSON by hand.
//
// JSON (nlohmann-json): strings are escaped; bytes that are not UTF-8 (a path
// or an argument can hold any byte) become U+FFFD; non-finite numbers
// (inf, -inf, nan) are written as null, so every file parses as JSON.
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace simdbvh::cli {

using Json = nlohmann::ordered_json;  // keeps the fields in the order they are set

// The command as typed, for the reports: "simdbvh bench --quick".
std::string command_line(const std::string& command, const std::vector<std::string>& args);

// One number through a printf format ("%.3g").
std::string fmt(const char* format, double v);

// A table: Markdown for the reports, space-aligned text for the terminal.
class Table {
public:
    // align: one character per column, 'l' or 'r' (default: first column left, the rest right).
    explicit Table(std::vector<std::string> header, std::string align = "");
    Table& row(std::vector<std::string> cells);
    std::string markdown() const;
    std::string text() const;
    std::size_t size() const { return rows_.size(); }

private:
    std::vector<std::string> header_;
    std::string align_;
    std::vector<std::vector<std::string>> rows_;
};

// JSON text of `doc` as this layer writes it (indent 2, see above).
std::string json_text(const Json& doc);

// Writes `text` atomically (temporary file, then rename), creating the folder.
void write_text(const std::filesystem::path& file, const std::string& text);

// Replaces what lies between the markers `begin` and `end` in `file` (both kept) with `body`; throws
// simdbvh::Error naming the file when it cannot be read or lacks the markers.
void replace_marked_block(const std::filesystem::path& file, const std::string& begin, const std::string& end,
                          const std::string& body);

struct Report {
    Json json = Json::object();
    std::ostringstream markdown;

    void save_json(const std::filesystem::path& file) const { write_text(file, json_text(json)); }
    void save_markdown(const std::filesystem::path& file) const { write_text(file, markdown.str()); }
};

// A Python script run in a child process (run_python_script).
struct PythonRun {
    bool started = false;    // the child ran (posix_spawn succeeded)
    bool timed_out = false;  // killed (SIGKILL) after the timeout
    int status = 0;          // its waitpid status
    bool ok() const;         // started, not timed out, exit status 0
    int exit_code() const;   // its exit status; -1 when it did not exit by itself
    // "exit status 1", "killed by signal 6 (Aborted)", "timed out", "could not start python3"
    std::string describe() const;
};

struct PythonOptions {
    std::vector<std::string> env;  // "NAME=value" entries set on top of our environment
    std::string stderr_file;       // the child's stderr goes here (empty: ours)
    double timeout_seconds = 0;    // 0: wait as long as it runs
};

// Runs scripts/SCRIPT ARGS... with /usr/bin/python3 (else python3 on the PATH), without a shell (any path
// works); its stdout goes to /dev/null. Waits for it (at most the timeout, then kills it).
PythonRun run_python_script(const std::string& script, const std::vector<std::string>& args,
                            const PythonOptions& options = {});

// Runs scripts/SCRIPT JSON_FILE OUT_DIR (matplotlib) through run_python_script. False, with a warning on
// stderr, when it fails; the report then has tables only.
bool run_chart_script(const std::string& script, const std::string& json_file, const std::string& out_dir);

}  // namespace simdbvh::cli
