#pragma once
/// \file
/// Private to the CAD front end (compiled with Gmsh only): splitting a solid into blocks
/// whose faces have four corners before its surface is meshed, so that more (or all) of its
/// faces take the transfinite recipe. Works on Gmsh's current model (OpenCASCADE kernel,
/// synchronised); see docs/cad.md, "Splitting into blocks".

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace stcweave::primal::cad_detail {

/// What `split_into_blocks` did.
struct SplitResult {
  /// How the solid was split ("" when it was not), e.g. "a cylinder, split as an O-grid of
  /// 5 blocks".
  std::string how;
  /// Why it was not split, when a split was tried and dropped (for the record's warnings).
  std::string dropped;
};

/// Recognises the model's solid and replaces it by blocks of the same shape whose faces all
/// have four corners (`four_cornered(face tag)` says whether a face has):
/// - one right circular cylinder (a cylindrical face and two planar discs): an O-grid of five
///   blocks (a square core and four ring pieces) along its axis;
/// - one sphere: a cubed sphere of seven blocks (a core cube and six pieces, each with its own
///   copy of the ball turned so that the sphere's poles and seam are outside the piece);
/// - one torus (a toroidal face; radii from its area and volume, axis from its inertia): the
///   20 blocks of `add_torus_blocks`, turned onto its axis;
/// - one solid of planar faces and straight edges with a through-hole (one full cylindrical
///   face bounded by two circles): cut by the half-planes from the hole's axis through each
///   corner of the solid and through the hole's seam, so that every block holds one piece of
///   the hole and one side of the outline;
/// - solids of planar faces and straight edges (`volumes` of them): cut by the planes
///   perpendicular to x, y and z through its corners that cross it (at most 12 planes), kept
///   only when every face of the union of the blocks has four corners.
/// The model is left unchanged when no case applies or a case fails (Gmsh's reason is then
/// in `dropped`). `diagonal` is the solid's bounding box diagonal (tolerances).
[[nodiscard]] SplitResult split_into_blocks(const std::vector<std::pair<int, int> >& volumes,
                                            double diagonal,
                                            const std::function<bool(int)>& four_cornered);

/// Adds the O-grid section of a disc of radius `r` to Gmsh's OpenCASCADE model: a square core
/// of half side r / 2.5 and four ring pieces (a core side, two diagonal cuts, a quarter of the
/// circle). `at(u, v)` places the section's point (u, v) in space (the centre is `at(0, 0)`).
/// Returns the five plane surfaces, the core first; the caller extrudes or revolves them.
[[nodiscard]] std::vector<std::pair<int, int> > add_ogrid_section(
    double r, const std::function<std::array<double, 3>(double, double)>& at);

/// Adds a torus around the z axis through the origin (centre-line radius `major`, tube
/// radius `minor`) as 20 blocks: the tube's section in the plane y = 0 split as an O-grid
/// (`add_ogrid_section`), swept a quarter turn, copied three times around the axis, and made
/// conforming by OpenCASCADE's fragment. Returns the blocks.
std::vector<std::pair<int, int> > add_torus_blocks(double major, double minor);

}  // namespace stcweave::primal::cad_detail
