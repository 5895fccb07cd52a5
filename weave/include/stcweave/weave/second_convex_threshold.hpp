#pragma once
/// \file
/// A thresholded second convex rule (seed sect. 4.3, our variant; docs/extended-rules.md).
///
/// The seed's rule keeps the candidates of highest side elimination weight (sharp convex
/// side edges / loop length). On a surface made of split triangles every loop circles one
/// vertex, and a loop near a sharp rim has one or two of its side edges on the rim, always
/// on the side away from the vertex: the whole rest of the front. The plain rule then
/// prefers that side to the small cap, and the weave collapses almost the whole front at
/// every step (`cylinder_a6_trisubdiv_coarse`: 1,300 hexes against 56 with `reliable`).
/// The variant counts a weight only from `min_weight` on: a side whose sharp edges are a
/// few stray ones does not run "along a sharp region" and weighs zero. When no candidate
/// reaches the threshold the filter keeps them all.

#include "stcweave/weave/select.hpp"

namespace stcweave::weave {

/// The second convex filter counting a side elimination weight only when it is at least
/// `min_weight` (in ]0, 1]); below, the weight is 0. Traced under the same name,
/// "second_convex" (the threshold is in the report's options).
[[nodiscard]] Filter second_convex_threshold_filter(double min_weight);

}  // namespace stcweave::weave
