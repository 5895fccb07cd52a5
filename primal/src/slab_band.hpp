#pragma once
/// \file
/// Bands of quads between two cycles of one handle (internal to primal's slab route).
///
/// The slab route cuts a handle along two discs, one on the handle cycle and one on a second
/// cycle of the same class, and weaves the piece of the solid between them (the slab) and the
/// rest apart. The piece between the two cycles is a band of surface quads: the quads beside
/// the cycle (`band_of` in cut.cpp), or the region between the cycle and a partner cycle far
/// from it, which makes both pieces thick (docs/topology.md, "Slabs").

#include <cstddef>
#include <optional>
#include <vector>

#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::primal {

/// The quads of a surface on a cycle's minus side between the cycle and a second cycle of
/// the same class, `outer`, walked the way the band's quads traverse it.
struct SlabBand {
  std::vector<std::size_t> quads;  ///< of the surface, increasing
  std::vector<NodeId> outer;
};

/// The region of `surface` on the minus side of `cycle` (the side of the quads traversing its
/// edges backward) bounded by `cycle` and `partner` alone: none when `partner` touches the
/// cycle, when the region reaches the cycle's other side, or when its boundary is not exactly
/// the two cycles (each edge once).
[[nodiscard]] std::optional<SlabBand> band_between(const stc::QuadSurface& surface,
                                                   const std::vector<NodeId>& cycle,
                                                   const std::vector<NodeId>& partner);

/// Bands between `cycle` and partner cycles far from it: the fundamental cycles of
/// breadth-first trees (the cycle's nodes left out) rooted at the nodes farthest from the
/// cycle, shortest first, kept when `band_between` accepts them. At most `max_bands`, the
/// most even split of the quads first (the smaller side's quad count per partner edge), then
/// the shorter partner.
[[nodiscard]] std::vector<SlabBand> far_bands(const stc::QuadSurface& surface,
                                              const std::vector<NodeId>& cycle,
                                              std::size_t max_bands);

}  // namespace stcweave::primal
