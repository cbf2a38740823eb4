// Ray and hit files (raw little-endian records).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/output.h"
#include "simdbvh/scene/rays.h"

namespace simdbvh::scene {
namespace {

void put_u32(unsigned char* p, std::uint32_t v) {
    p[0] = static_cast<unsigned char>(v);
    p[1] = static_cast<unsigned char>(v >> 8);
    p[2] = static_cast<unsigned char>(v >> 16);
    p[3] = static_cast<unsigned char>(v >> 24);
}
std::uint32_t get_u32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}
void put_f32(unsigned char* p, float f) { put_u32(p, std::bit_cast<std::uint32_t>(f)); }
float get_f32(const unsigned char* p) { return std::bit_cast<float>(get_u32(p)); }

// Regular files only (symlinks followed): a device such as /dev/zero has no
// size to check and would read forever.
std::vector<unsigned char> read_records(const std::filesystem::path& file, std::size_t record, const char* what) {
    const std::string name = file.string();
    const int fd = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);  // a FIFO would block in open
    if (fd < 0) throw Error(name + ": cannot open: " + std::strerror(errno));
    struct Closer { int fd; ~Closer() { ::close(fd); } } closer{fd};
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

}  // namespace

std::vector<Ray> read_rays(const std::filesystem::path& file) {
    const auto bytes = read_records(file, sizeof(Ray), "32-byte ray");
    std::vector<Ray> rays(bytes.size() / 32);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const unsigned char* p = bytes.data() + 32 * i;
        rays[i].org = Vec3{get_f32(p), get_f32(p + 4), get_f32(p + 8)};
        rays[i].tmin = get_f32(p + 12);
        rays[i].dir = Vec3{get_f32(p + 16), get_f32(p + 20), get_f32(p + 24)};
        rays[i].tmax = get_f32(p + 28);
    }
    return rays;
}

std::vector<unsigned char> encode_rays(std::span<const Ray> rays) {
    std::vector<unsigned char> bytes(rays.size() * 32);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        unsigned char* p = bytes.data() + 32 * i;
        const Ray& r = rays[i];
        const float v[8] = {r.org.x, r.org.y, r.org.z, r.tmin, r.dir.x, r.dir.y, r.dir.z, r.tmax};
        for (int k = 0; k < 8; ++k) put_f32(p + 4 * k, v[k]);
    }
    return bytes;
}

void write_rays(const std::filesystem::path& file, std::span<const Ray> rays) { write_file_atomic(file, encode_rays(rays)); }

std::vector<Hit> read_hits(const std::filesystem::path& file) {
    const auto bytes = read_records(file, sizeof(Hit), "16-byte hit");
    std::vector<Hit> hits(bytes.size() / 16);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const unsigned char* p = bytes.data() + 16 * i;
        hits[i].t = get_f32(p);
        hits[i].u = get_f32(p + 4);
        hits[i].v = get_f32(p + 8);
        hits[i].prim = get_u32(p + 12);
    }
    return hits;
}

std::vector<unsigned char> encode_hits(std::span<const Hit> hits) {
    std::vector<unsigned char> bytes(hits.size() * 16);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        unsigned char* p = bytes.data() + 16 * i;
        put_f32(p, hits[i].t);
        put_f32(p + 4, hits[i].u);
        put_f32(p + 8, hits[i].v);
        put_u32(p + 12, hits[i].prim);
    }
    return bytes;
}

void write_hits(const std::filesystem::path& file, std::span<const Hit> hits) { write_file_atomic(file, encode_hits(hits)); }

}  // namespace simdbvh::scene
