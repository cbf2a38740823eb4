#pragma once
// simdbvh: exact, fast ray and point queries against triangle meshes and
// scenes. The one header a user includes; each room's headers may also be
// included alone (docs/architecture.md).
//   kernels/  the ground-floor types (Vec3, Aabb, Ray, Hit, Mesh, Error, Isa, TraceOptions)
//   platform/ threads (parallel_for, executors, pinning), the topology, large allocations
//   bvh2/     the binary BVH: builders, traversal, the sphere hierarchy
//   bvh8/     the wide BVHs (4-, 8- and 16-wide from one collapse)
//   query/    closest point, inside/outside, signed distance, every crossing of a ray
//   accel/    Accel (the method by cost), the cost model, the SIMD brute force
//   scene/    the two-level scene: instances, spheres, boxes, planes
#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/mesh.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/trace_options.h"
#include "simdbvh/kernels/vec.h"

#include "simdbvh/platform/parallel.h"
#include "simdbvh/platform/topology.h"

#include "simdbvh/bvh2/build.h"
#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh2/spheres.h"

#include "simdbvh/bvh8/bvh8.h"

#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/closest_point_wide.h"
#include "simdbvh/query/crossings.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/query/inside_wide.h"
#include "simdbvh/query/signed_distance.h"

#include "simdbvh/accel/accel.h"
#include "simdbvh/accel/brute_force8.h"

#include "simdbvh/scene/scene.h"
#include "simdbvh/scene/scene_hit.h"
#include "simdbvh/scene/shapes.h"
#include "simdbvh/scene/transform.h"
