#pragma once
/// \file
/// The Spatial Twist Continuum of a hex complex (woven or read from a file): its sheets,
/// chords, STC vertices (one per hex) and boundary points (one per boundary quad), and the
/// two Boost graphs that hold them: the dual graph (vertex = hex or boundary point, edge =
/// face) and the sheet graph (vertex = sheet, edge = chord).
///
/// Directions and axes of a VTK-ordered hex (see quad_surface.hpp):
/// - edge direction 0 = edges 0-1, 3-2, 4-5, 7-6; direction 1 = edges 1-2, 0-3, 5-6, 4-7;
///   direction 2 = edges 0-4, 1-5, 2-6, 3-7. The sheet through a hex "in direction d" is
///   the one dual to its four direction-d edges (it crosses them).
/// - the chord through a hex "along axis a" crosses the two faces perpendicular to the
///   direction-a edges: axis 0 = faces 5 and 3, axis 1 = faces 2 and 4, axis 2 = faces 0
///   and 1. It lies in the two sheets of the other two directions.

#include <array>
#include <boost/graph/adjacency_list.hpp>
#include <cstddef>
#include <vector>

#include "stcweave/stc/hex_complex.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::stc {

/// A sheet: the dual surface of a layer of hexes, i.e. one class of hex edges made
/// parallel through hexes (two edges are in the same class when they are opposite edges
/// of a face of some hex). It meets the boundary in loops, or nowhere (blind sheet).
struct Sheet {
  /// Hexes the sheet passes through, increasing, each once (even when the sheet crosses
  /// itself there).
  std::vector<HexId> hexes;
  /// Chords lying in the sheet, increasing, each once.
  std::vector<ChordId> chords;
  /// True when some hex has two (or three) of its edge directions in this sheet.
  bool self_intersecting = false;
  /// The loops of the boundary surface along which the sheet meets it: for each loop,
  /// the boundary quads it crosses in order (a quad crossed twice, by a self-intersecting
  /// loop, appears twice). Empty for a blind sheet.
  std::vector<std::vector<QuadId>> boundary_loops;
};

/// A chord: the dual curve of a column of hexes linked through opposite faces; the
/// intersection of the two sheets it lies in.
struct Chord {
  /// Hexes along the chord, in order: from `ends[0]` to `ends[1]` for an open chord; from
  /// its lowest hex id for a closed one (a ring). Either way the chord crosses its lowest
  /// hex in the direction of its axis (in through face 5, 2 or 0, out through face 3, 4 or
  /// 1). A hex appears twice when the chord passes through it along two axes.
  std::vector<HexId> hexes;
  /// The boundary quads (= boundary points) where an open chord starts and ends; both
  /// invalid for a closed chord.
  std::array<QuadId, 2> ends{QuadId::invalid(), QuadId::invalid()};
  /// True when the chord is a ring that never meets the boundary (a blind chord).
  bool closed = false;
  /// The two sheets it lies in, increasing; equal when the chord lies where a sheet
  /// crosses itself.
  std::array<SheetId, 2> sheets{SheetId::invalid(), SheetId::invalid()};
};

/// A blind sheet meets no boundary loop.
[[nodiscard]] inline bool is_blind(const Sheet& sheet) {
  return sheet.boundary_loops.empty();
}
/// A blind chord never meets the boundary.
[[nodiscard]] inline bool is_blind(const Chord& chord) {
  return chord.closed;
}

/// An STC vertex: the intersection of three sheets, i.e. one hex.
struct StcVertex {
  std::array<SheetId, 3> sheets;  ///< sheets[d]: the sheet in edge direction d
  std::array<ChordId, 3> chords;  ///< chords[a]: the chord along axis a
};

/// A boundary point: where a chord ends on the boundary; one per boundary quad.
struct BoundaryPoint {
  QuadId quad;    ///< the boundary quad (index into HexStc::boundary)
  HexId hex;      ///< the hex it belongs to
  int face = -1;  ///< its face (0..5, kHexFaces) in that hex
  ChordId chord;  ///< the chord ending there
};

/// What a vertex of the dual graph stands for.
enum class DualVertexKind { HexVertex, BoundaryPoint };

/// Bundled property of a dual-graph vertex: vertex `i < num_hexes` is hex `i`, vertex
/// `num_hexes + q` is the boundary point of boundary quad `q`.
struct DualVertex {
  DualVertexKind kind = DualVertexKind::HexVertex;
  HexId hex;    ///< the hex (kind HexVertex) or the hex owning the boundary quad
  QuadId quad;  ///< the boundary quad (kind BoundaryPoint), invalid otherwise
};

/// Bundled property of a dual-graph edge: one face of the complex.
struct DualEdge {
  HexId hex;      ///< the lower-id hex holding the face
  int face = -1;  ///< the face index (0..5) in that hex
  ChordId chord;  ///< the chord crossing the face
};

/// The dual graph: vertex = hex or boundary point, edge = face (between the two hexes
/// sharing it, or between a hex and the boundary point of its boundary face). Parallel
/// edges appear only when two hexes share two faces (an invalid complex).
using DualGraph =
    boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, DualVertex, DualEdge>;

/// Bundled property of a sheet-graph vertex.
struct SheetVertex {
  SheetId sheet;
};
/// Bundled property of a sheet-graph edge.
struct SheetEdge {
  ChordId chord;
};

/// The sheet graph: vertex `i` = sheet `i`, one edge per chord joining the two sheets it
/// lies in (a self-loop when both are the same sheet), in chord id order. Parallel edges
/// are frequent (two sheets meeting along several chords).
using SheetGraph =
    boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, SheetVertex, SheetEdge>;

/// The STC of a hex complex. Ids are deterministic: sheets and chords are numbered in
/// order of first appearance when scanning hexes by increasing id, then directions
/// (sheets) or axes (chords) 0..2; boundary quads in the order of `boundary_surface`.
struct HexStc {
  std::vector<Sheet> sheets;
  std::vector<Chord> chords;
  std::vector<StcVertex> vertices;             ///< one per hex, indexed by HexId
  std::vector<BoundaryPoint> boundary_points;  ///< one per boundary quad, indexed by QuadId
  /// The boundary surface (faces used by one hex, as `boundary_surface` returns it).
  QuadSurface boundary;
  DualGraph dual_graph;
  SheetGraph sheet_graph;

  [[nodiscard]] std::size_t num_hexes() const { return vertices.size(); }
  [[nodiscard]] const Sheet& sheet(SheetId s) const { return sheets[s.index()]; }
  [[nodiscard]] const Chord& chord(ChordId c) const { return chords[c.index()]; }
  [[nodiscard]] const StcVertex& vertex(HexId h) const { return vertices[h.index()]; }
  [[nodiscard]] const BoundaryPoint& boundary_point(QuadId q) const {
    return boundary_points[q.index()];
  }
};

/// Builds the STC of a hex complex: sheets, chords, STC vertices, boundary points, the
/// loops bounding each sheet, the dual graph and the sheet graph. Linear in the number of
/// hexes up to a sort of its faces and edges.
///
/// The STC is defined for a manifold hex complex (see `validate_hex_complex`). A face in
/// three or more hexes or a boundary edge not shared by exactly two boundary quads make it
/// undefined and are refused; other defects (two hexes sharing two faces, broken vertex
/// links) give an STC whose meaning is undefined: validate first when in doubt.
/// \throw InvalidInput when a hex has a node id out of range or a repeated node, when a
/// face belongs to three or more hexes, or when a boundary edge is not shared by exactly
/// two boundary quads.
[[nodiscard]] HexStc build_hex_stc(const HexComplex& complex);

/// Number of blind chords (closed rings).
[[nodiscard]] std::size_t num_blind_chords(const HexStc& stc);
/// Number of blind sheets (no boundary loop).
[[nodiscard]] std::size_t num_blind_sheets(const HexStc& stc);
/// Number of self-intersecting sheets.
[[nodiscard]] std::size_t num_self_intersecting_sheets(const HexStc& stc);

/// The dual-graph vertex of hex `h`.
[[nodiscard]] inline std::size_t dual_vertex_of_hex(HexId h) {
  return h.index();
}
/// The dual-graph vertex of the boundary point of boundary quad `q`.
[[nodiscard]] inline std::size_t dual_vertex_of_boundary_point(const HexStc& stc, QuadId q) {
  return stc.num_hexes() + q.index();
}

}  // namespace stcweave::stc
