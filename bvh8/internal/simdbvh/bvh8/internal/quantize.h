#pragma once
// Internal: step 3 of a wide build with WideOptions::quantized_nodes, the
// quantized copy of the packed nodes (qnode.h) that traversal reads.
#include <vector>

#include "simdbvh/bvh8/node.h"
#include "simdbvh/bvh8/qnode.h"

namespace simdbvh::bvh8 {

// One quantized node per node, same children, each dequantized child box
// containing the node's own (checked here for every plane). Empty when a node
// cannot be quantized (an axis wider than 255 * 2^119, beyond any finite
// mesh's); traversal then reads the full nodes. `threads` as the pack's.
template <int N>
std::vector<QNodeN<N>> quantize(const NodesN<N>& nodes, int threads);

// One box: false when it cannot be quantized. Exposed for the tests.
template <int N>
bool quantize_box(const BoxN<N>& box, const ChildN<N>* children, QBoxN<N>& out);

}  // namespace simdbvh::bvh8
