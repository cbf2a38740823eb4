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

// Runs scripts/SCRIPT JSON_FILE OUT_DIR with /usr/bin/python3 (matplotlib),
// without a shell (any path works). False, with a warning on stderr, when it
// fails; the report then has tables only.
bool run_chart_script(const std::string& script, const std::string& json_file, const std::string& out_dir);

}  // namespace simdbvh::cli
