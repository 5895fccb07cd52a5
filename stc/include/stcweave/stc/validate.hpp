#pragma once
/// \file
/// Validation of a hex complex against the invariants of DESIGN.md ("Invariants"): the
/// check run on every weave result and by `--check`. Pure topology (no coordinates).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::stc {

/// The invariants checked by `validate_hex_complex`, in the order they are reported.
enum class Invariant {
  NodeOutOfRange,        ///< every hex node id is in 0 .. num_nodes-1
  RepeatedNode,          ///< every hex has 8 distinct nodes
  FaceInThreeHexes,      ///< a face belongs to at most two hexes
  HexesShareTwoFaces,    ///< two hexes share at most one face
  SharedNodesNotAFace,   ///< two hexes sharing four or more nodes share exactly a face of both
  FaceOrientation,       ///< a face shared by two hexes is traversed in opposite directions
  InteriorEdgeCycle,     ///< around an interior edge the hexes form one closed cycle
  BoundaryEdgeFan,       ///< around a boundary edge the hexes form one open fan
  VertexLink,            ///< vertex links are spheres (interior) or disks (boundary)
  MissingBoundaryQuad,   ///< every expected boundary quad is a face used once
  ExtraBoundaryQuad,     ///< every face used once is an expected boundary quad
  ReversedBoundaryQuad,  ///< expected quads appear with the same cyclic order
  EulerCharacteristic,   ///< χ(volume) = V − E + F − C equals χ(boundary) / 2
  /// (only with `check_pinched_faces`) no two distinct faces (n, a, x, b), (n, a, y, b)
  /// share the two edges n-a and n-b: at n both are tangent to the plane of those edges,
  /// so some hex corner at n is flat whatever the node positions (a degenerate hex for any
  /// solver). Combinatorially a hex complex still (every edge cycle and vertex link is
  /// right); geometrically not realisable.
  PinchedFacePair,
};

/// The name of an invariant as reported (`"face_in_three_hexes"`, ...).
[[nodiscard]] std::string_view invariant_name(Invariant invariant);

/// One violated invariant.
struct Violation {
  Invariant invariant;
  std::size_t count = 0;  ///< number of offending elements
  /// Up to `kMaxExamples` offending elements, named with ids: `h12` (a hex), `h3+h8` (a
  /// pair of hexes), `h3+h8:n1,n4,n9` (a pair of hexes and the nodes they share), `n4-n9`
  /// (an edge), `n4` (a node), `q7` (an expected quad), `h3.f2` (face 2 of hex h3), or the
  /// figures (`chi(volume)=1 chi(boundary)=0`).
  std::vector<std::string> examples;

  static constexpr std::size_t kMaxExamples = 10;
  [[nodiscard]] std::string_view name() const { return invariant_name(invariant); }
};

/// The outcome of `validate_hex_complex`: the violated invariants and a few figures.
struct ValidationReport {
  bool valid = true;                  ///< no violation
  std::vector<Violation> violations;  ///< in `Invariant` order, each at most once
  std::size_t hexes = 0;              ///< hexes checked
  std::size_t nodes = 0;              ///< nodes used by the well-formed hexes
  std::size_t edges = 0;              ///< distinct edges
  std::size_t faces = 0;              ///< distinct faces
  std::size_t boundary_faces = 0;     ///< faces used by one hex
  std::int64_t euler_volume = 0;      ///< V − E + F − C
  std::int64_t euler_boundary = 0;    ///< χ of the faces used once
  bool boundary_compared = false;     ///< an expected boundary was given

  /// The violation of `invariant`, or nullptr when it holds.
  [[nodiscard]] const Violation* find(Invariant invariant) const;
  /// One line per violation (`face_in_three_hexes: 1 (h0 h1 h2)`), or a one-line "valid"
  /// with the figures.
  [[nodiscard]] std::string summary() const;
};

/// Checks every invariant of a hex complex: each hex has 8 distinct valid nodes; a face
/// belongs to at most two hexes, which traverse it in opposite directions; two hexes share
/// at most one face; around every interior edge the hexes form one closed cycle, around a
/// boundary edge one open fan; every vertex link is a sphere (interior node) or a disk
/// (boundary node); χ(volume) = χ(boundary)/2; and, when `expected_boundary` is given, the
/// faces used once are exactly its quads (same node ids, same cyclic order up to
/// rotation). Hexes with an invalid or repeated node are reported and left out of the
/// other checks.
///
/// With `check_shared_nodes`: two hexes that share four or more nodes share exactly the four
/// nodes of a face of both (`SharedNodesNotAFace`). Refused: a face and one more node, two
/// opposite edges of both (a diagonal section), a face of one that is a section of the
/// other, two hexes on the same 8 nodes. Both hexes then cover the region near the shared
/// nodes, so with the boundary fixed (the hex volumes sum to the enclosed volume) some hex has
/// a negative Jacobian somewhere, whatever the positions; yet every edge cycle and vertex link
/// can be right (a sheared 3-torus of cubes passes every other check). Each such pair is
/// reported as `h3+h8:n1,n4,n5,n9`. Two or three shared nodes that are not a node, an edge or
/// a face of both (hexes meeting at a diagonal of a face of each, the three nodes of a pinched
/// face pair) are not refused by this check: the faces at a shared diagonal need not be
/// planar, so they do not by themselves make hexes overlap; the weave makes such contacts on
/// small spheres, and the reference checker (`../shared/reference/verify_hex.py`) accepts
/// them too. Pinched pairs have their own check.
///
/// Time: a sort of the faces and edges, then linear (the pairs of hexes sharing a node:
/// linear in the sum over hexes of the hexes at their nodes).
/// \param expected_boundary quads over the complex's node ids; nullptr to skip the
/// comparison.
/// \param check_pinched_faces also require no pinched face pair (`PinchedFacePair`): what
/// a mesh handed to a solver needs; off for the weave's own complex, which may hold pairs
/// at boundary nodes that the pipeline's pillow and unpinch stages remove.
/// \param check_shared_nodes also require `SharedNodesNotAFace`. On by default (the pipeline
/// and `stcweave check` ask it of everything they output or certify); off only to look at a
/// complex made before the weave's rules and the front moves' search checked their contacts
/// (docs/self-intersecting-loops.md "Hexes sharing four nodes off a face").
[[nodiscard]] ValidationReport validate_hex_complex(const HexComplex& complex,
                                                    const QuadSurface* expected_boundary = nullptr,
                                                    bool check_pinched_faces = false,
                                                    bool check_shared_nodes = true);

/// The `SharedNodesNotAFace` check alone (hexes with an invalid or repeated node left out):
/// the pairs of hexes sharing four or more nodes that are not exactly a face of both, counted,
/// with up to `Violation::kMaxExamples` examples (`count` 0 when there is none). The pipeline
/// reports it for the mesh it writes.
[[nodiscard]] Violation shared_nodes_not_a_face(const HexComplex& complex);

/// Two distinct faces (n, a, x, b) and (n, a, y, b) of a complex: they share the edges
/// n-a and n-b. At n both are tangent to the plane of those two edges, so the hexes met
/// going round the edge n-a from one face to the other on one side span a dihedral angle of
/// 0 there: some corner at n is flat (det 0) whatever the positions. Topology, not positions.
struct PinchedFaces {
  NodeId node;
  NodeId a;  ///< the smaller of the two shared neighbours
  NodeId b;
  std::array<std::int32_t, 4> first{};  ///< node cycles of the two faces
  std::array<std::int32_t, 4> second{};
};

/// Every pinched pair of faces of `complex` (the `PinchedFacePair` invariant), sorted by
/// (node, a, b); O(hexes log hexes).
[[nodiscard]] std::vector<PinchedFaces> pinched_faces(const HexComplex& complex);

/// \throw InternalError naming the first violation of `report` (and how many there are)
/// when it is not valid.
void require_valid(const ValidationReport& report);

}  // namespace stcweave::stc
