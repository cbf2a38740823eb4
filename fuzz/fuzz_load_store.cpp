// libFuzzer target: the saved-structure loader (store/). The first byte picks
// the tree type (bvh2, bvh4, bvh8, bvh16) and whether the payload checksum is
// checked; the rest is the file. Without the checksum a mutated array reaches
// the structural check, so whatever loads is then traced (closest and any
// hit, scalar): a loaded tree must never read outside its arrays. Allowed
// outcome: a tree, or simdbvh::Error. Anything else is a finding.
#include <cstdint>
#include <span>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/store/store.h"

namespace {

std::vector<simdbvh::Ray> probe_rays() {
    std::vector<simdbvh::Ray> rays;
    for (int i = 0; i < 64; ++i) {
        simdbvh::Ray r;
        r.org = {float(i % 4) - 1.5f, float((i / 4) % 4) - 1.5f, -5.0f};
        r.dir = {0.01f * float(i % 7), 0.01f * float(i % 5), 1.0f};
        rays.push_back(r);
    }
    return rays;
}

template <class T>
void load_and_trace(std::span<const unsigned char> bytes, bool verify) {
    static const std::vector<simdbvh::Ray> rays = probe_rays();
    std::vector<simdbvh::Hit> hits(rays.size());
    try {
        const auto saved = simdbvh::load_bytes<T>(bytes, "fuzz.simdbvh", {.verify = verify});
        if constexpr (std::is_same_v<T, simdbvh::Bvh2>) {
            simdbvh::intersect(saved.bvh, std::span(rays), std::span(hits));
            simdbvh::occluded(saved.bvh, std::span(rays), std::span(hits));
        } else {
            simdbvh::intersect(saved.bvh, std::span(rays), std::span(hits), {}, simdbvh::Isa::scalar);
            simdbvh::occluded(saved.bvh, std::span(rays), std::span(hits), {}, simdbvh::Isa::scalar);
        }
    } catch (const simdbvh::Error&) {}
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::span<const unsigned char> bytes(data + 1, size - 1);
    const bool verify = data[0] & 4u;
    switch (data[0] & 3u) {
    case 0: load_and_trace<simdbvh::Bvh2>(bytes, verify); break;
    case 1: load_and_trace<simdbvh::Bvh4>(bytes, verify); break;
    case 2: load_and_trace<simdbvh::Bvh8>(bytes, verify); break;
    default: load_and_trace<simdbvh::Bvh16>(bytes, verify); break;
    }
    return 0;
}
