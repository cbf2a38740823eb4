#include "lab.h"
#include "results_doc.h"

#include <fstream>
#include <sstream>
#include <system_error>

#include "simdbvh/kernels/error.h"

namespace simdbvh::lab {

namespace fs = std::filesystem;

namespace {

// "missing", "has the block", or "lacks it" (only --publish may then add it).
enum class DocState { missing, has_block, lacks_block };

DocState state_of(const ResultsDoc& d, const Block& b) {
    std::error_code ec;
    if (d.create && !fs::exists(d.file, ec) && !fs::is_symlink(d.file, ec)) return DocState::missing;
    try {
        check_marked_block(d.file, b.begin, b.end);
        return DocState::has_block;
    } catch (const Error& e) {
        // Only a readable file without the markers may get the block appended.
        if (!d.create || std::string(e.what()).find(": no '") == std::string::npos)
            throw Error(d.option + ": " + e.what());
        return DocState::lacks_block;
    }
}

std::string read_text(const fs::path& file) {
    std::ifstream f(file, std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    if (!f) throw Error(file.string() + ": cannot read");
    return ss.str();
}

}  // namespace

std::vector<ResultsDoc> parse_results_docs(const Options& o, bool no_report) {
    std::vector<ResultsDoc> docs;
    for (const char* opt : {"readme", "publish"})
        if (o.has(opt) && no_report)
            throw UsageError(std::string("--") + opt +
                             " writes the report's pictures too: it needs the report (drop --no-report)");
    if (o.has("readme")) {
        const fs::path f = o.get("readme");
        docs.push_back({"--readme", f, (f.has_parent_path() ? f.parent_path() : fs::path(".")) / "docs" / "results",
                        "docs/results/", false});
    }
    if (o.has("publish")) {
        const fs::path dir = o.get("publish");
        if (dir.empty()) throw UsageError("--publish needs a folder");
        docs.push_back({"--publish", dir / "results.md", dir / "results", "results/", true});
    }
    return docs;
}

void check_results_docs(const std::vector<ResultsDoc>& docs, const Block& block,
                        const std::vector<std::string>& pictures, NamedPaths& outputs) {
    for (const ResultsDoc& d : docs) {
        (void)state_of(d, block);
        outputs.emplace_back(d.option, d.file.string());
        for (const std::string& p : pictures) outputs.emplace_back(d.option, (d.image_dir / p).string());
    }
}

void add_results_docs(ReportFiles& set, const std::vector<ResultsDoc>& docs, const Block& block,
                      const std::function<std::string(const std::string& link)>& body, const fs::path& report_dir,
                      const std::vector<std::pair<std::string, std::string>>& pictures) {
    for (const ResultsDoc& d : docs) {
        const std::string text = body(d.link);
        switch (state_of(d, block)) {
        case DocState::has_block: set.add(d.file, with_marked_block(d.file, block.begin, block.end, text)); break;
        case DocState::missing: set.add(d.file, "# simdbvh results\n\n" + block.begin + text + block.end + "\n"); break;
        case DocState::lacks_block:
            set.add(d.file, read_text(d.file) + "\n" + block.begin + text + block.end + "\n");
            break;
        }
        for (const auto& [from, to] : pictures)
            if (const auto* bytes = set.find(report_dir / from)) set.add(d.image_dir / to, *bytes);
    }
}

}  // namespace simdbvh::lab
