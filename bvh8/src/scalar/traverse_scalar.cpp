// Wide BVH traversal (N = 4, 8, 16), baseline x86-64 (no AVX, no xsimd):
// traverse-inl.h over the scalar reference kernels (box.h, triangle.h), one
// lane at a time.
#include "simdbvh/bvh8/internal/scalar/kernels_scalar.h"
#include "simdbvh/bvh8/internal/traverse-inl.h"

namespace simdbvh::bvh8 {

template struct Traversal<scalar::Kernels, 4>;
template struct Traversal<scalar::Kernels, 8>;
template struct Traversal<scalar::Kernels, 16>;

}  // namespace simdbvh::bvh8
