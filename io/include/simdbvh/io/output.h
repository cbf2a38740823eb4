#pragma once
// Output files: written in full before anything is replaced, never through a
// half-written file, and checked before the work that produces them.
#include <filesystem>
#include <span>

namespace simdbvh::io {

// Writes `bytes` to `file`; throws simdbvh::Error naming the file. What is at the path decides how:
// - nothing or a regular file: a uniquely named temporary file (.NAME.tmp.XXXXXX, O_EXCL) next to it is
//   written, fsynced and renamed over it. An existing file keeps its mode (and, as root, its owner); a new
//   one gets 0666 & ~umask. An existing file the user may not write (access W_OK) is refused, as cp refuses
//   it, though the folder would allow the rename. On failure the old file is untouched and no temporary
//   file is left.
// - a symlink: resolved first; its final target is written as above, the link stays a link.
// - a regular file with several hard links: the data is written to a temporary file first (so it is
//   complete and the disk had room for it), then copied over the file in place (O_TRUNC) so every link
//   sees it. Trade-off: a crash or write error during that copy leaves the file partial.
// - a device, FIFO or other non-regular file: opened and written directly, no temporary file.
// - a directory: an error.
void write_file_atomic(const std::filesystem::path& file, std::span<const unsigned char> bytes);

// One of several outputs of one run.
struct OutputFile {
    std::filesystem::path path;
    std::span<const unsigned char> bytes;
};
// All or nothing: every temporary file is written first; only then are they put in place (direct writes to
// non-regular files, in-place copies, then the renames, during which SIGINT, SIGTERM, SIGHUP and SIGPIPE wait:
// a signal cannot leave half of the set renamed). When a temporary file cannot be written, no output is
// touched and every temporary file is removed.
void write_files_atomic(std::span<const OutputFile> files);

// A private folder for files a run makes before it commits them (a chart script's pictures): created with
// mkdtemp as PARENT/simdbvh-staging.XXXXXX (PARENT: the system's temporary folder unless given), removed
// with its files on destruction, and by remove_temp_files() on a signal (its files, one level, then it).
class StagingDir {
public:
    explicit StagingDir(const std::filesystem::path& parent = {});  // throws simdbvh::Error
    ~StagingDir();
    StagingDir(const StagingDir&) = delete;
    StagingDir& operator=(const StagingDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    int slot_ = -1;
};

// The file a write to `file` replaces: symlinks (also dangling ones) resolved, at most 40 levels.
std::filesystem::path output_target(const std::filesystem::path& file);

// Preflight, for config time: throws simdbvh::Error naming `file` unless it can be written: not a
// directory; an existing file must be writable ("is not writable"); its directory exists and a temporary
// file can be created (and is removed) there. create_parent: the directory may be missing when its nearest
// existing ancestor is a writable directory (the caller creates it).
void check_writable(const std::filesystem::path& file, bool create_parent = false);

// Removes every temporary output file and staging folder this process has open. Async-signal-safe (lock-free
// atomics and system calls only): for a SIGINT/SIGTERM handler, which then re-raises the signal.
void remove_temp_files() noexcept;

}  // namespace simdbvh::io
