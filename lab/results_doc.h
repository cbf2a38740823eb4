#pragma once
// The results blocks of bench, bench --scene and bench --sweep in Markdown
// files (the maintainers' act, never the default): --readme FILE rewrites the
// marked block of FILE, its pictures in FILE's folder/docs/results/;
// --publish DIR the block of DIR/results.md, its pictures in DIR/results/.
// Checked before the work, written with the report as one set (ReportFiles).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "lab.h"
#include "options.h"
#include "outputs.h"
#include "report.h"

namespace simdbvh::lab {

struct ResultsDoc {
    std::string option;               // "--readme" or "--publish"
    std::filesystem::path file;       // FILE, or DIR/results.md
    std::filesystem::path image_dir;  // FILE's folder/docs/results, or DIR/results
    std::string link;                 // the pictures' path in the block: "docs/results/" or "results/"
    bool create = false;              // --publish: a missing file is created, one without the block gets it appended
};

// --readme FILE and --publish DIR (either, both or neither). Both need the report's pictures: a UsageError
// with --no-report.
std::vector<ResultsDoc> parse_results_docs(const Options& o, bool no_report);

// The markers of one block, e.g. "<!-- bench:begin -->", "<!-- bench:end -->".
struct Block {
    std::string begin, end;
};

// Config time: every --readme file has the block (--publish: has it, or lacks it and gets it, or is
// missing and is created). Appends each doc and its pictures (file names in the image folder) to
// `outputs`, for check_outputs.
void check_results_docs(const std::vector<ResultsDoc>& docs, const Block& block,
                        const std::vector<std::string>& pictures, NamedPaths& outputs);

// At the end of the run: adds to `set` each doc with its block replaced by body(link) and each picture
// present in the set under `report_dir` (report name, name in the image folder) copied to the image folder.
void add_results_docs(ReportFiles& set, const std::vector<ResultsDoc>& docs, const Block& block,
                      const std::function<std::string(const std::string& link)>& body,
                      const std::filesystem::path& report_dir,
                      const std::vector<std::pair<std::string, std::string>>& pictures);

}  // namespace simdbvh::lab
