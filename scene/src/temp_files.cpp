// Temporary output files and their removal on SIGINT/SIGTERM.
#include "temp_files.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/output.h"

namespace simdbvh::scene {
namespace {

constexpr int kSlots = 64;
struct Slot {
    std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live (remove on a signal)
    char path[PATH_MAX];
};
static_assert(std::atomic<int>::is_always_lock_free);
Slot g_slots[kSlots];

int register_path(const char* p) {
    if (std::strlen(p) >= PATH_MAX) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expect = 0;
        if (!g_slots[i].state.compare_exchange_strong(expect, 1)) continue;
        std::strcpy(g_slots[i].path, p);
        g_slots[i].state.store(2);
        return i;
    }
    return -1;  // more than kSlots live temporary files: this one is not removed on a signal
}

void unregister(int slot) {
    if (slot >= 0) g_slots[slot].state.store(0);
}

// Blocks the usual termination signals while a temporary file is created and registered.
struct BlockSignals {
    sigset_t old;
    BlockSignals() {
        sigset_t s;
        sigemptyset(&s);
        for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&s, sig);
        pthread_sigmask(SIG_BLOCK, &s, &old);
    }
    ~BlockSignals() { pthread_sigmask(SIG_SETMASK, &old, nullptr); }
};

}  // namespace

void remove_temp_files() noexcept {
    for (Slot& s : g_slots)
        if (s.state.load() == 2) ::unlink(s.path);
}

namespace detail {

TempFile::TempFile(const std::filesystem::path& dir, const std::string& base) {
    // NAME_MAX is 255: keep room for ".", ".tmp." and the six random characters.
    std::string name = ".";  // (built with += : GCC 12 warns falsely on "literal" + string)
    name += base.substr(0, 200);
    name += ".tmp.XXXXXX";
    const std::string tmpl = (dir / name).string();
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    {
        BlockSignals block;
        fd_ = ::mkostemp(buf.data(), O_CLOEXEC);
        if (fd_ >= 0) slot_ = register_path(buf.data());
    }
    if (fd_ < 0) throw Error("cannot create a temporary file in " + dir.string() + ": " + std::strerror(errno));
    path_ = buf.data();
}

TempFile::~TempFile() { remove(); }

int TempFile::close() {
    if (fd_ < 0) return 0;
    const int rc = ::close(fd_);
    fd_ = -1;
    return rc == 0 ? 0 : errno;
}

void TempFile::release() {
    close();
    unregister(slot_);
    slot_ = -1;
    path_.clear();
}

void TempFile::remove() {
    close();
    if (!path_.empty()) ::unlink(path_.c_str());
    unregister(slot_);
    slot_ = -1;
    path_.clear();
}

}  // namespace detail
}  // namespace simdbvh::scene
