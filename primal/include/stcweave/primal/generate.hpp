#pragma once
/// \file
/// Shapes generated on the fly (for benchmarks and examples; the tests have their own,
/// independent generator): structured boxes and the seed's Fig. 5 bars, each as its
/// natural hex mesh and as that mesh's boundary.

#include <string>
#include <string_view>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// The largest side `box_hexes` accepts (a 1000^3 box already has 10^9 hexes).
inline constexpr int kMaxBoxSide = 1000;

/// The a x b x c structured hex mesh of [0,a] x [0,b] x [0,c] (unit cubes), hexes
/// positively oriented in VTK order, node (i,j,k) at (i,j,k) with id i + (a+1)(j + (b+1)k).
/// \throw InvalidInput unless 1 <= a, b, c <= kMaxBoxSide.
[[nodiscard]] HexMesh box_hexes(int a, int b, int c);

/// The boundary of `box_hexes(a, b, c)`: 2(ab + bc + ca) quads oriented outward, nodes
/// renumbered compactly in increasing order of their hex-mesh ids.
/// \throw InvalidInput as `box_hexes`.
[[nodiscard]] SurfaceMesh box_surface(int a, int b, int c);

/// The solids of the seed's Fig. 5: one topological quad mesh (14 quads, 28 edges, 16
/// nodes: the boundary of a 1 x 1 x 3 bar) on differently shaped solids, each the union of
/// three convex hexes. \cite seed sect. 3, Fig. 5.
enum class BarShape {
  Straight,  ///< the 1 x 1 x 3 bar: three hexes are the obvious answer
  L,         ///< bent once at a mitred corner
  U,         ///< bent twice
  Plate,     ///< a 6 x 6 x 1 plate cut into three slabs across its large faces
};

/// Names of the bar shapes, in enum order: "straight", "l", "u", "plate".
[[nodiscard]] std::vector<std::string> bar_shape_names();

/// The bar shape named `name` (case-sensitive).
/// \throw InvalidInput for another name; the message lists the valid ones.
[[nodiscard]] BarShape bar_shape_from_name(std::string_view name);

/// The three positively oriented hexes of a Fig. 5 solid.
[[nodiscard]] HexMesh bar_hexes(BarShape shape);

/// The boundary of `bar_hexes(shape)`: 14 quads oriented outward, 16 nodes.
[[nodiscard]] SurfaceMesh bar_surface(BarShape shape);

/// A generated shape named in a benchmark manifest: `box:AxBxC` (the A x B x C box) or
/// `bar:SHAPE` (a Fig. 5 bar, SHAPE one of `bar_shape_names()`).
struct ShapeSpec {
  enum class Kind { Box, Bar };
  Kind kind = Kind::Box;
  int a = 1, b = 1, c = 1;            ///< box sides (Box only)
  BarShape bar = BarShape::Straight;  ///< (Bar only)
};

/// Parses `box:AxBxC` or `bar:SHAPE` (`box:8x8x8`, `bar:l`).
/// \throw InvalidInput for anything else, or box sides outside 1..kMaxBoxSide; the message
///        shows the accepted forms.
[[nodiscard]] ShapeSpec parse_shape_spec(std::string_view spec);

/// The canonical text of a spec, as `parse_shape_spec` accepts it (`box:8x8x8`, `bar:l`).
[[nodiscard]] std::string to_string(const ShapeSpec& spec);

/// The natural hex mesh of a spec: `box_hexes` or `bar_hexes`.
[[nodiscard]] HexMesh shape_hexes(const ShapeSpec& spec);

/// The boundary of a hex mesh (faces used by one hex, oriented outward for positively
/// oriented hexes), nodes compacted in increasing order of their hex-mesh ids.
[[nodiscard]] SurfaceMesh boundary_mesh(const HexMesh& mesh);

}  // namespace stcweave::primal
