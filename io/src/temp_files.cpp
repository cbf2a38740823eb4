// Temporary output files and their removal on SIGINT/SIGTERM.
#include "temp_files.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <system_error>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/output.h"

namespace simdbvh::io {
namespace {

constexpr int kSlots = 64;
enum Kind : int { kFile = 0, kDir = 1 };
struct Slot {
    std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live (remove on a signal)
    int kind = kFile;
    char path[PATH_MAX];
};
static_assert(std::atomic<int>::is_always_lock_free);
Slot g_slots[kSlots];

int register_path(const char* p, int kind) {
    if (std::strlen(p) >= PATH_MAX) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expect = 0;
        if (!g_slots[i].state.compare_exchange_strong(expect, 1)) continue;
        std::strcpy(g_slots[i].path, p);
        g_slots[i].kind = kind;
        g_slots[i].state.store(2);
        return i;
    }
    return -1;  // more than kSlots live temporary files: this one is not removed on a signal
}

// The folder's entries (one level), then the folder, with system calls only (async-signal-safe). Entries
// removed while the listing runs can hide others from it: the listing is repeated while it finds any.
void remove_flat_dir(const char* path) noexcept {
    const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        alignas(8) char buf[4096];
        for (int pass = 0; pass < 8; ++pass) {
            bool removed = false;
            ::lseek(fd, 0, SEEK_SET);
            for (;;) {
                const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
                if (n <= 0) break;
                for (long off = 0; off < n;) {
                    // struct linux_dirent64: u64 ino, s64 off, u16 reclen, u8 type, then the name
                    unsigned short reclen = 0;
                    std::memcpy(&reclen, buf + off + 16, sizeof reclen);
                    const char* name = buf + off + 19;
                    off += reclen;
                    if (reclen == 0) break;
                    if (std::strcmp(name, ".") == 0 || std::strcmp(name, "..") == 0) continue;
                    if (::unlinkat(fd, name, 0) == 0) removed = true;
                }
            }
            if (!removed) break;
        }
        ::close(fd);
    }
    ::rmdir(path);
}

}  // namespace

void remove_temp_files() noexcept {
    for (Slot& s : g_slots) {
        if (s.state.load() != 2) continue;
        if (s.kind == kDir) remove_flat_dir(s.path);
        else ::unlink(s.path);
    }
}

StagingDir::StagingDir(const std::filesystem::path& parent) {
    std::error_code ec;
    const std::filesystem::path where = parent.empty() ? std::filesystem::temp_directory_path(ec) : parent;
    if (ec) throw Error("no temporary folder for a staging folder ($TMPDIR, /tmp): " + ec.message());
    const std::string tmpl = (where / "simdbvh-staging.XXXXXX").string();
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    bool made = false;
    {
        detail::BlockSignals block;
        made = ::mkdtemp(buf.data()) != nullptr;
        if (made) slot_ = detail::register_dir(buf.data());
    }
    if (!made) throw Error("cannot create a staging folder in " + where.string() + ": " + std::strerror(errno));
    path_ = buf.data();
}

StagingDir::~StagingDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
    detail::unregister_path(slot_);
}

namespace detail {

BlockSignals::BlockSignals() {
    sigset_t s;
    sigemptyset(&s);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&s, sig);
    pthread_sigmask(SIG_BLOCK, &s, &old);
}
BlockSignals::~BlockSignals() { pthread_sigmask(SIG_SETMASK, &old, nullptr); }

int register_dir(const char* path) { return register_path(path, kDir); }

void unregister_path(int slot) {
    if (slot >= 0) g_slots[slot].state.store(0);
}

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
        if (fd_ >= 0) slot_ = register_path(buf.data(), kFile);
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
    unregister_path(slot_);
    slot_ = -1;
    path_.clear();
}

void TempFile::remove() {
    close();
    if (!path_.empty()) ::unlink(path_.c_str());
    unregister_path(slot_);
    slot_ = -1;
    path_.clear();
}

}  // namespace detail
}  // namespace simdbvh::io
