// read_file: a regular file (symlinks resolved), raw or gzip (by magic bytes),
// read in chunks. The format's SizeLimit sees the first bytes and decides how
// large the data may honestly grow; reading stops with an error past that, so
// a gzip bomb costs at most what its header declares.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>

#include "simdbvh/io/internal/size_limit.h"

namespace simdbvh::io::detail {
namespace {

constexpr std::size_t kFirstChunk = std::size_t(1) << 16;  // enough for any header check
constexpr std::size_t kChunk = std::size_t(1) << 20;

// Opens without blocking (a FIFO would block in open) and refuses anything but a regular file.
int open_regular(const std::string& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) fail(file, 0, std::string("cannot open: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const bool dir = S_ISDIR(st.st_mode);
        ::close(fd);
        fail(file, 0, dir ? "is a directory" : "is not a regular file (a device, FIFO or socket)");
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

// Raw bytes from the file, through a small buffer.
struct RawInput {
    const std::string& file;
    int fd;
    std::vector<unsigned char> buf = std::vector<unsigned char>(std::size_t(1) << 18);
    std::size_t pos = 0, len = 0;
    bool eof = false;

    // Makes at least `n` unread bytes available (fewer only at the end of the file).
    void want(std::size_t n) {
        if (len - pos >= n || eof) return;
        std::memmove(buf.data(), buf.data() + pos, len - pos);
        len -= pos;
        pos = 0;
        while (len < n && !eof) {
            const ssize_t r = ::read(fd, buf.data() + len, buf.size() - len);
            if (r < 0 && errno == EINTR) continue;
            if (r < 0) fail(file, 0, std::string("read error: ") + std::strerror(errno));
            if (r == 0) eof = true;
            len += std::size_t(r);
        }
    }
    std::size_t avail() const { return len - pos; }
};

// Inflates gzip members one after another (concatenated members are legal gzip);
// anything else after a member is an error.
struct Gunzip {
    RawInput& in;
    z_stream zs{};
    bool done = false;

    explicit Gunzip(RawInput& i) : in(i) {
        if (inflateInit2(&zs, 15 + 16) != Z_OK) throw std::bad_alloc();
    }
    ~Gunzip() { inflateEnd(&zs); }
    Gunzip(const Gunzip&) = delete;
    Gunzip& operator=(const Gunzip&) = delete;

    // Fills out[0, n) as far as the data goes; returns the number of bytes written.
    std::size_t read(char* out, std::size_t n) {
        zs.next_out = reinterpret_cast<Bytef*>(out);
        zs.avail_out = unsigned(n);
        while (zs.avail_out && !done) {
            in.want(1);
            zs.next_in = in.buf.data() + in.pos;
            zs.avail_in = unsigned(in.avail());
            const int rc = inflate(&zs, Z_NO_FLUSH);
            in.pos = std::size_t(zs.next_in - in.buf.data());
            if (rc == Z_STREAM_END) next_member();
            else if (rc == Z_MEM_ERROR) throw std::bad_alloc();
            else if (rc == Z_BUF_ERROR && in.avail() == 0 && in.eof)
                fail(in.file, 0, "truncated or corrupt gzip data: unexpected end of file");
            else if (rc != Z_OK && rc != Z_BUF_ERROR)
                fail(in.file, 0, std::string("truncated or corrupt gzip data: ") + (zs.msg ? zs.msg : "error"));
        }
        return n - zs.avail_out;
    }
    void next_member() {
        in.want(2);
        if (in.avail() == 0) {
            done = true;
            return;
        }
        if (in.avail() < 2 || in.buf[in.pos] != 0x1f || in.buf[in.pos + 1] != 0x8b)
            fail(in.file, 0, "trailing data after the gzip stream");
        inflateReset(&zs);
    }
};

std::size_t nul_offset(const std::vector<char>& data, std::size_t from) {
    const void* p = std::memchr(data.data() + from, 0, data.size() - from);
    return p ? std::size_t(static_cast<const char*>(p) - data.data()) : data.size();
}

}  // namespace

std::vector<char> read_file(const std::filesystem::path& path, const SizeLimit& limit) {
    const std::string file = path.string();
    RawInput in{file, open_regular(file)};
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{in.fd};
    in.want(2);
    const bool gz = in.avail() >= 2 && in.buf[0] == 0x1f && in.buf[1] == 0x8b;
    Gunzip gunzip(in);
    auto chunk = [&](char* out, std::size_t n) -> std::size_t {
        if (gz) return gunzip.read(out, n);
        std::size_t got = 0;
        while (got < n) {
            in.want(1);
            const std::size_t k = std::min(n - got, in.avail());
            if (!k) break;
            std::memcpy(out + got, in.buf.data() + in.pos, k);
            in.pos += k;
            got += k;
        }
        return got;
    };
    std::vector<char> data;
    std::optional<Allowance> allow;
    std::size_t used = 0, scanned = 0;
    for (;;) {
        const std::size_t want = used ? kChunk : kFirstChunk;
        data.resize(used + want);
        const std::size_t n = chunk(data.data() + used, want);
        used += n;
        data.resize(used);
        const bool complete = n < want;
        if (!allow) {
            allow = limit(file, std::string_view(data.data(), used), complete);
            // A raw file's size is known: room for all of it (and the last chunk's
            // read) at once, so the data is held once, not twice while the
            // vector grows by copying.
            if (allow && !gz && !complete) {
                struct stat st {};
                if (::fstat(in.fd, &st) == 0 && st.st_size > 0)
                    data.reserve(std::size_t(std::min<std::uint64_t>(std::uint64_t(st.st_size), allow->max_bytes)) +
                                 kChunk);
            }
        }
        if (allow && allow->text) {
            const std::size_t at = nul_offset(data, scanned);
            scanned = used;
            if (at < used) {
                const std::size_t line = 1 + std::size_t(std::count(data.data(), data.data() + at, '\n'));
                fail(file, line, "NUL byte in a text file (binary data or UTF-16 text)");
            }
        }
        if (allow && used > allow->max_bytes)
            fail(file, 0,
                 "more than " + std::to_string(allow->max_bytes) + " bytes of data (after decompression), more than " +
                     allow->why);
        if (complete) break;
    }
    return data;
}

}  // namespace simdbvh::io::detail
