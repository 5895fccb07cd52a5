#pragma once
/// \file
/// Pillowing: a closed sheet of hexes parallel to a boundary shell, inserted between the
/// recovered weave and the positioning (docs/pillowing.md).
///
/// What it guarantees. For every shell (connected component of the boundary surface) that is
/// pillowed, each of its boundary nodes n gets one interior copy n'; every hex of the complex
/// that used n uses n' instead, and each boundary quad (a, b, c, d) of the shell gets one new
/// hex between the quad and its copy (a', b', c', d'). Boundary nodes keep their ids and
/// coordinates and the boundary quads stay exactly the faces used once, so the result is a
/// hex complex with the same boundary whenever the input was one (`stc::validate_hex_complex`
/// with the input surface as expected boundary passes). Afterwards every hex has at most one
/// face, and no corner with all four nodes, on that shell: each corner's Jacobian depends on
/// at least one free node, which the untangler can move.
///
/// Copies start inside, offset from their boundary node against the (area-weighted) vertex
/// normal by `PillowOptions::offset` times the mean length of the node's boundary edges. The
/// positioning stage then untangles and improves them like every other interior node.
///
/// Time and memory: linear in the number of hexes and quads. Deterministic: new nodes and
/// hexes are numbered in the order of the boundary nodes and quads.

#include <cstddef>
#include <string>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// When the pipeline pillows.
enum class PillowMode {
  /// Pillow the shells that need it: those holding a node of a hex corner whose four nodes
  /// all lie on the boundary (so no placement of the interior nodes can change its Jacobian)
  /// with a scaled Jacobian below `PillowOptions::min_fixed_corner` (docs/pillowing.md says
  /// why; a corner whose nodes lie on two shells selects both).
  Auto,
  Always,  ///< pillow every shell
  Never,   ///< never pillow
};

/// Name of a mode as used on the command line ("auto", "always", "never").
[[nodiscard]] std::string to_string(PillowMode mode);
/// \throw InvalidInput for an unknown name; the message lists the valid ones.
[[nodiscard]] PillowMode pillow_mode_from_name(const std::string& name);

/// Options of `pillow` (plain values; defaults measured in docs/pillowing.md).
struct PillowOptions {
  PillowMode mode = PillowMode::Auto;
  /// Auto: a shell is pillowed when a fixed corner (a hex corner whose four nodes are
  /// boundary nodes) holding one of its nodes has a scaled Jacobian below this. A corner on an edge
  /// where two boundary faces of one hex meet at dihedral angle a has a scaled Jacobian of at
  /// most sin a, so 0.2 catches every such edge flatter than about 168 degrees (and every
  /// non-convex one), and leaves the 90-degree edges of boxes alone.
  double min_fixed_corner = 0.2;
  /// Initial inward offset of a copy, as a fraction of the mean length of its node's
  /// boundary edges (0 < offset < 1; a quarter was measured to work).
  double offset = 0.25;
  /// Auto: when every bad fixed corner is positive (the woven complex may be valid as it is),
  /// position both the pillowed and the unpillowed complex and keep the better one
  /// (`choose_pillowed`). Off: pillow whenever a fixed corner is bad.
  bool compare = true;
};

/// What `pillow` decided and did.
struct PillowReport {
  PillowMode mode = PillowMode::Auto;
  bool applied = false;               ///< at least one shell was pillowed
  std::size_t shells = 0;             ///< connected components of the boundary surface
  std::size_t shells_pillowed = 0;    ///< of those, pillowed
  std::size_t fixed_corners = 0;      ///< hex corners whose four nodes are boundary nodes
  std::size_t bad_fixed_corners = 0;  ///< of those, below `min_fixed_corner`
  /// Smallest scaled Jacobian of a fixed corner (1 when there is none), and where.
  double worst_fixed_corner = 1.0;
  HexId worst_hex;
  int worst_corner = -1;
  std::size_t nodes_added = 0;  ///< interior copies of boundary nodes
  std::size_t hexes_added = 0;  ///< one per boundary quad of a pillowed shell
  /// One line: which mode, whether pillowed, and why (names the worst fixed corner).
  std::string reason;
  /// Per shell that no mode can pillow, selected or not, two of its quads that share two
  /// nodes that are not an edge ("q3 and q9", joined by ", "); empty when every shell can be
  /// pillowed. The pipeline names them when pinched face pairs at boundary nodes are left.
  std::string unpillowable;
  /// Auto with `compare`: both complexes were positioned and compared (`choose_pillowed`).
  bool compared = false;
  /// After the pillow (pipeline, `unpinch` in primal/src/position_pinch.hpp): pinched face
  /// pairs found, 2-hex blocks pillowed to remove them (10 hexes and 12 nodes each, counted
  /// here, not in `hexes_added`), and pairs left. All 0 when there was no pinched pair.
  std::size_t pinched_pairs = 0;
  std::size_t unpinch_blocks = 0;
  std::size_t unpinch_hexes = 0;
  std::size_t pinched_left = 0;
};

/// The fixed corners of `mesh` (hex corners whose four nodes are among the boundary nodes
/// `0 .. num_boundary_nodes-1`) and their scaled Jacobians, as `pillow`'s Auto mode sees them;
/// `bad_fixed_corners` counts those below `options.min_fixed_corner`. Nothing is changed.
/// \throw InvalidInput when a hex names a node outside the point matrix.
[[nodiscard]] PillowReport assess_pillow(const HexMesh& mesh, std::size_t num_boundary_nodes,
                                         const PillowOptions& options = {});

/// Pillows the shells of `boundary` that `options.mode` selects (see the file comment), except
/// a shell two of whose quads share two nodes that are not an edge (their pillow hexes would
/// share four nodes off a face: `stc::Invariant::SharedNodesNotAFace`); `reason` names them.
/// New nodes are appended after the existing ones, new hexes after the existing hexes.
/// \pre `boundary` is the complex's boundary: its quads are the faces used once, oriented
///      outward, over the nodes `0 .. boundary.num_nodes-1` of `mesh`.
/// \throw InvalidInput when the point matrix and the complex disagree, a quad names a node
///        outside the boundary's node range, or `options.offset` is not in ]0, 1[.
PillowReport pillow(HexMesh& mesh, const stc::QuadSurface& boundary,
                    const PillowOptions& options = {});

/// Auto mode's second question: is the pillow worth comparing? True when `report` pillowed
/// in `Auto` mode with `compare` on and every bad fixed corner is positive (worst fixed
/// corner > 0): then the woven complex can be valid without the pillow, and the pillow may
/// make the worst hex worse (a few hexes whose nodes are all on the boundary, as
/// `svd2016_Dolphin_1`, get a thin pillow layer instead). A flat or inverted fixed corner
/// needs the pillow: no comparison.
[[nodiscard]] bool pillow_worth_comparing(const PillowReport& report, const PillowOptions& options);

/// Quality of one positioned candidate, as `choose_pillowed` compares them.
struct PillowCandidate {
  std::size_t inverted = 0;          ///< hexes with scaled Jacobian <= 0
  double min_scaled_jacobian = 0.0;  ///< Verdict's, centre included
  double mean_scaled_jacobian = 0.0;
  std::size_t hexes = 0;
};

/// Whether the pillowed candidate is kept: fewer inverted hexes wins; at equal counts the
/// larger minimum scaled Jacobian wins; at equal minima (within 1e-9) the pillowed one is
/// kept (it has no corner fixed by the boundary). Pure function of the figures.
[[nodiscard]] bool choose_pillowed(const PillowCandidate& pillowed,
                                   const PillowCandidate& unpillowed);

/// The report of a compared Auto decision: `pillowed` with `compared` set and its reason
/// extended by both candidates' figures; when `keep_pillow` is false, `applied`,
/// `shells_pillowed`, `nodes_added` and `hexes_added` are reset (the woven complex is kept).
[[nodiscard]] PillowReport compared_pillow_report(PillowReport pillowed, bool keep_pillow,
                                                  const PillowCandidate& with,
                                                  const PillowCandidate& without);

}  // namespace stcweave::primal
