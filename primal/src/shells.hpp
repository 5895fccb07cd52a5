#pragma once
/// \file
/// The shells (connected components) of a quad surface, node by node: shared by the pillow
/// (one pillow per shell) and the tet interior (one Gmsh surface per shell).

#include <cstddef>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::primal {

/// Per node of `surface`, the index of its connected component (-1 for a node no quad uses);
/// components are numbered in order of their first quad. `*shells` receives their number.
std::vector<int> shell_of_nodes(const stc::QuadSurface& surface, std::size_t* shells);

}  // namespace stcweave::primal
