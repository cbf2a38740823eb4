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
#include "simdbvh/io/output.h"

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

// The text of `file` with what lies between the markers `begin` and `end` (both kept) replaced by `body`;
// throws simdbvh::Error naming the file when it cannot be read or lacks the markers (or has them twice).
std::string with_marked_block(const std::filesystem::path& file, const std::string& begin, const std::string& end,
                              const std::string& body);
// The same check alone, for config time: before the work whose result goes between the markers.
void check_marked_block(const std::filesystem::path& file, const std::string& begin, const std::string& end);

// The files of one report, committed together: nothing is written before commit(), which writes every file to
// a temporary file beside it and renames them all into place only when each is complete
// (io::write_files_atomic). A failed or interrupted run leaves every file as it was.
class ReportFiles {
public:
    void add(const std::filesystem::path& file, const std::string& text);
    void add(const std::filesystem::path& file, std::vector<unsigned char> bytes);  // replaces an earlier one
    // The bytes added for `file`, or nullptr.
    const std::vector<unsigned char>* find(const std::filesystem::path& file) const;
    // Runs scripts/SCRIPT (run_chart_script) on `json` (written as JSON_NAME) in a staging folder of its own
    // (io::StagingDir) and adds every PNG it draws there under `dir`. False, with a warning on stderr, when
    // the script fails: the report then has tables only.
    bool add_charts(const std::string& script, const std::string& json, const std::string& json_name,
                    const std::filesystem::path& dir);
    // Creates the missing folders, then writes every file, all or nothing; removes the folders it created
    // when that fails. Throws simdbvh::Error naming the file.
    void commit() const;
    std::vector<std::filesystem::path> paths() const;

private:
    std::vector<std::pair<std::filesystem::path, std::vector<unsigned char>>> files_;
};

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
    std::string missing;     // why it was not started when the scripts are not found (scripts_dir)
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

// The folder of the Python scripts the reports run: SIMDBVH_SCRIPTS, else share/simdbvh/scripts in the
// executable's folder or up to two above it (the build tree and an install both have one); empty when none.
std::filesystem::path scripts_dir();

// Runs scripts_dir()/SCRIPT ARGS... with /usr/bin/python3 (else python3 on the PATH), without a shell (any path
// works), with PYTHONDONTWRITEBYTECODE=1 (no __pycache__ in the source tree); its stdout goes to /dev/null.
// Waits for it (at most the timeout, then kills it).
PythonRun run_python_script(const std::string& script, const std::vector<std::string>& args,
                            const PythonOptions& options = {});

// Runs scripts/SCRIPT JSON_FILE OUT_DIR (matplotlib) through run_python_script. False, with a warning on
// stderr, when it fails; the report then has tables only.
bool run_chart_script(const std::string& script, const std::string& json_file, const std::string& out_dir);

// The script run_python_script is waiting for (0: none): a signal handler kills it before it removes the
// staging folder the script writes into.
int running_script_pid() noexcept;

}  // namespace simdbvh::cli
