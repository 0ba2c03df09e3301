// Builds the light tree of kernels/lights/light_tree.h over the scene's finite lights.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/common/compat.h"
#include "kernels/types/scene.h"

namespace aw {

// From this many finite (not at infinity) lights on, render.light_selection "auto" uses the
// tree; below it the alias table alone (docs/architecture.md, "Many lights").
constexpr uint32_t kLightTreeMinLights = 16;

// Builds the tree over lights[first, end) with selection powers power[i - first] (>= 0) and
// writes each light's tree_bits / tree_depth. Nodes come depth-first; the root is node 0.
// The tree is at most 32 levels deep (tree_bits holds one bit per level).
std::vector<LightTreeNode> build_light_tree(std::vector<LightGpu>& lights, uint32_t first,
                                            const std::vector<double>& power);

}  // namespace aw
