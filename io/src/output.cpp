// Output files: atomic replacement of regular files, direct writes to devices
// and FIFOs, symlinks written through, and the config-time preflight.
#include "simdbvh/io/output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "temp_files.h"

namespace simdbvh::io {
namespace fs = std::filesystem;
namespace {

mode_t default_mode() {
    static const mode_t mask = [] {
        const mode_t m = ::umask(0);
        ::umask(m);
        return m;
    }();
    return 0666 & ~mask;
}

// 0 or an errno.
int write_all(int fd, std::span<const unsigned char> bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return n < 0 ? errno : EIO;
        done += std::size_t(n);
    }
    return 0;
}

fs::path dir_of(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

// An existing file the user may not write is not replaced, though the folder would let a rename do it (a
// write-protected file, or another user's in a shared folder): as cp and shell redirection refuse it.
void refuse_unwritable(const std::string& name, const fs::path& target) {
    if (::access(target.c_str(), W_OK) != 0 && errno != ENOENT)
        throw Error(name + ": is not writable (" + std::strerror(errno) + "); refusing to replace it");
}

// One output, prepared (temporary file written) and then committed.
class Pending {
public:
    Pending(const fs::path& file, std::span<const unsigned char> bytes) : name_(file.string()), bytes_(bytes) {
        target_ = output_target(file);
        struct stat st {};
        bool existed = false;
        if (::stat(target_.c_str(), &st) == 0) {
            existed = true;
            if (S_ISDIR(st.st_mode)) throw Error(name_ + ": is a directory");
            if (!S_ISREG(st.st_mode)) {
                direct_ = true;  // device, FIFO, socket: written at commit, no temporary file
                return;
            }
            refuse_unwritable(name_, target_);
            in_place_ = st.st_nlink > 1;
        } else if (errno != ENOENT) {
            throw Error(name_ + ": " + std::strerror(errno));
        }
        try {
            tmp_ = std::make_unique<detail::TempFile>(dir_of(target_), target_.filename().string());
        } catch (const Error& e) {
            throw Error(name_ + ": " + e.what());
        }
        const int fd = tmp_->fd();
        int err = 0;
        if (existed) {
            if (::fchmod(fd, st.st_mode & 07777) != 0) err = errno;
            if (!err && ::geteuid() == 0 && (st.st_uid != 0 || st.st_gid != 0))
                (void)!::fchown(fd, st.st_uid, st.st_gid);  // best effort
        } else if (::fchmod(fd, default_mode()) != 0) {
            err = errno;
        }
        if (!err) err = write_all(fd, bytes);
        if (!err && ::fsync(fd) != 0) err = errno;
        if (!err) err = tmp_->close();
        if (err) {
            tmp_->remove();
            throw Error(name_ + ": write failed: " + std::strerror(err));
        }
    }

    void commit() {
        if (direct_) return write_to(O_WRONLY, "");
        if (in_place_) {
            write_to(O_WRONLY | O_TRUNC,
                     " (the file may now be partial; the complete data is in " + tmp_->path().string() + ")");
            tmp_->remove();
            return;
        }
        if (::rename(tmp_->path().c_str(), target_.c_str()) != 0) {
            const int err = errno;
            tmp_->remove();
            throw Error(name_ + ": cannot rename the temporary file into place: " + std::strerror(err));
        }
        tmp_->release();
    }
    bool direct() const { return direct_; }
    bool in_place() const { return in_place_; }

private:
    void write_to(int flags, const std::string& partial_note) {
        const int fd = ::open(target_.c_str(), flags | O_CLOEXEC);
        if (fd < 0) throw Error(name_ + ": cannot open for writing: " + std::strerror(errno));
        int err = write_all(fd, bytes_);
        if (!err && in_place_ && ::fsync(fd) != 0) err = errno;
        if (::close(fd) != 0 && !err) err = errno;
        if (err) {
            if (in_place_) tmp_->release();  // keep the complete copy for the user
            throw Error(name_ + ": write failed: " + std::strerror(err) + partial_note);
        }
    }

    std::string name_;
    fs::path target_;
    std::span<const unsigned char> bytes_;
    std::unique_ptr<detail::TempFile> tmp_;
    bool direct_ = false, in_place_ = false;
};

}  // namespace

fs::path output_target(const fs::path& file) {
    fs::path cur = file;
    for (int i = 0; i < 40; ++i) {
        struct stat st {};
        if (::lstat(cur.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return cur;
        std::error_code ec;
        const fs::path to = fs::read_symlink(cur, ec);
        if (ec) throw Error(file.string() + ": cannot read the symlink " + cur.string() + ": " + ec.message());
        cur = to.is_absolute() ? to : cur.parent_path() / to;
    }
    throw Error(file.string() + ": too many levels of symbolic links");
}

void write_file_atomic(const fs::path& file, std::span<const unsigned char> bytes) {
    const OutputFile one{file, bytes};
    write_files_atomic(std::span(&one, 1));
}

void write_files_atomic(std::span<const OutputFile> files) {
    std::vector<std::unique_ptr<Pending>> pending;
    for (const OutputFile& f : files) pending.push_back(std::make_unique<Pending>(f.path, f.bytes));
    // Direct and in-place writes can fail half-way: before any rename.
    for (auto& p : pending)
        if (p->direct()) p->commit();
    for (auto& p : pending)
        if (p->in_place()) p->commit();
    const detail::BlockSignals block;  // the renames: all of them, or (on an error) those before it
    for (auto& p : pending)
        if (!p->direct() && !p->in_place()) p->commit();
}

void check_writable(const fs::path& file, bool create_parent) {
    const std::string name = file.string();
    const fs::path target = output_target(file);
    struct stat st {};
    if (::stat(target.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) throw Error(name + ": is a directory");
        if (!S_ISREG(st.st_mode)) {
            if (::access(target.c_str(), W_OK) != 0) throw Error(name + ": not writable: " + std::strerror(errno));
            return;
        }
        refuse_unwritable(name, target);
    } else if (errno != ENOENT) {
        throw Error(name + ": " + std::strerror(errno));
    }
    fs::path dir = dir_of(target);
    for (;;) {
        if (::stat(dir.c_str(), &st) == 0) {
            if (!S_ISDIR(st.st_mode)) throw Error(name + ": " + dir.string() + " is not a directory");
            break;
        }
        if (errno != ENOENT) throw Error(name + ": " + dir.string() + ": " + std::strerror(errno));
        if (!create_parent) throw Error(name + ": the directory " + dir.string() + " does not exist");
        const fs::path up = dir.has_parent_path() && dir.parent_path() != dir ? dir.parent_path() : fs::path(".");
        if (up == dir) throw Error(name + ": no existing directory above " + dir.string());
        dir = up;
    }
    try {
        detail::TempFile probe(dir, target.filename().string());
    } catch (const Error& e) {
        throw Error(name + ": " + e.what());
    }
}

}  // namespace simdbvh::io
