#pragma once
// The registry of live temporary output files and staging folders, cleared by
// remove_temp_files() from a signal handler: fixed slots, lock-free atomics,
// no allocation.
#include <signal.h>

#include <filesystem>
#include <string>

namespace simdbvh::io::detail {

// Blocks the usual termination signals (SIGINT, SIGTERM, SIGHUP, SIGPIPE) for its lifetime: a signal that
// arrives meanwhile is delivered when it ends.
struct BlockSignals {
    sigset_t old;
    BlockSignals();
    ~BlockSignals();
    BlockSignals(const BlockSignals&) = delete;
    BlockSignals& operator=(const BlockSignals&) = delete;
};

// Registers a folder for removal on a signal (its files, one level, then the folder): the slot, or -1 when
// every slot is taken. unregister_path(slot) forgets it.
int register_dir(const char* path);
void unregister_path(int slot);

// A temporary file created with mkstemp (O_EXCL, random suffix, retried on EEXIST) in `dir`, named
// .BASE.tmp.XXXXXX, and registered for removal on a signal. Signals are blocked between the creation and
// the registration. The file is removed (and unregistered) on destruction unless release() was called.
class TempFile {
public:
    TempFile(const std::filesystem::path& dir, const std::string& base);  // throws Error
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
    int fd() const { return fd_; }
    const std::filesystem::path& path() const { return path_; }
    int close();     // closes the descriptor: 0 or an errno
    void release();  // the file was renamed away: forget it without removing anything
    void remove();   // removes the file now

private:
    std::filesystem::path path_;
    int fd_ = -1;
    int slot_ = -1;
};

}  // namespace simdbvh::io::detail
