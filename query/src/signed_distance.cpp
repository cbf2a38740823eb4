// Signed distance: closest point plus the exact inside test (see signed_distance.h).
#include "simdbvh/query/signed_distance.h"
#include "simdbvh/kernels/error.h"

#include <vector>

namespace simdbvh {

void signed_distance(const Bvh2& bvh, std::span<const Vec3> points, std::span<SignedDistance> out,
                     const PointQueryOptions& opts, const InsideOptions& inside) {
    simdbvh::detail::check_size(out.size(), points.size(), "out");
    std::vector<ClosestPoint> nearest(points.size());
    closest_point(bvh, points, nearest, opts);
    std::vector<PointSide> sides(points.size());
    InsideOptions io = inside;
    io.threads = opts.threads;
    classify_points(bvh, points, sides, io);
    for (std::size_t i = 0; i < points.size(); ++i) out[i] = SignedDistance{nearest[i], sides[i]};
}

}  // namespace simdbvh
