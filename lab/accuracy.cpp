#include "lab.h"
#include "accuracy.h"

namespace simdbvh::lab {

Tally classify_sample(const Mesh& mesh, std::span<const Ray> rays, std::span<const Hit> reference,
                      std::span<const Hit> hits, bool any_hit) {
    if (any_hit)
        return reference::compare_occluded(mesh, rays, reference::occluded_flags(reference),
                                           reference::occluded_flags(hits))
            .b;
    return reference::compare_methods(mesh, rays, reference, hits).b;
}

}  // namespace simdbvh::lab
