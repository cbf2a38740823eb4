// Raw little-endian record files (see records.h).
#include "records.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "simdbvh/kernels/error.h"

namespace simdbvh::io::detail {

std::vector<unsigned char> read_records(const std::filesystem::path& file, std::size_t record, const char* what) {
    const std::string name = file.string();
    const int fd = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);  // a FIFO would block in open
    if (fd < 0) throw Error(name + ": cannot open: " + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw Error(name + ": cannot determine the size: " + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw Error(name + ": is a directory");
    if (!S_ISREG(st.st_mode)) throw Error(name + ": is not a regular file (a device, FIFO or socket)");
    const auto size = std::uint64_t(st.st_size);
    if (size % record != 0)
        throw Error(name + ": size " + std::to_string(size) + " is not a multiple of " + std::to_string(record) +
                    " bytes (" + what + " records)");
    std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
    for (std::size_t got = 0; got < bytes.size();) {
        const ssize_t r = ::pread(fd, bytes.data() + got, bytes.size() - got, off_t(got));
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) throw Error(name + ": read error: " + std::strerror(errno));
        if (r == 0) throw Error(name + ": read error: the file shrank while reading");
        got += std::size_t(r);
    }
    return bytes;
}

}  // namespace simdbvh::io::detail
