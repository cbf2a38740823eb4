// libFuzzer target: the ray and hit file readers (raw little-endian records).
// Allowed outcome: records, or simdbvh::Error (a size that is not a multiple
// of the record size). Anything else is a finding.
#include <cstdlib>

#include "fuzz_util.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/ray_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = simdbvh::fuzz::write_input("in.bin", data, size);
    try {
        const auto rays = simdbvh::io::read_rays(path);
        if (rays.size() * 32 != size) std::abort();
    } catch (const simdbvh::Error&) {}
    try {
        const auto hits = simdbvh::io::read_hits(path);
        if (hits.size() * 16 != size) std::abort();
    } catch (const simdbvh::Error&) {}
    return 0;
}
