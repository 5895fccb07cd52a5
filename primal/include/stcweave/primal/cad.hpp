#pragma once
/// \file
/// CAD in: a solid read from a STEP, BREP or IGES file (or a primitive made with the
/// OpenCASCADE kernel) becomes a loop-clean closed quad surface, through Gmsh's C++ API.
///
/// This is the only part of stcweave that sees Gmsh. Gmsh is initialised on the first call
/// and finalised once when the program ends; calls are serialised (Gmsh holds one global
/// model), each starts from an empty model and sets every option it relies on, so the
/// result does not depend on earlier calls or on the user's Gmsh configuration files.
///
/// Two recipes give surfaces whose loops never cross themselves (the weave's precondition):
/// - `Transfinite`: every face of the solid has exactly four corners, so each gets a
///   block-structured grid. Opposite curves of a face get the same number of segments; the
///   number is chosen per chain of opposite curves (the longest curve of the chain divided
///   by the target size, rounded, at least 1).
/// - `TriangleSplit`: Gmsh's triangles (`Mesh.Algorithm` `CadOptions::triangle_algorithm`,
///   Delaunay by default) at twice the target size, each split into three quads
///   (`Mesh.SubdivisionAlgorithm` 1 with no recombination; checked in Gmsh 4.8.4: the quads are
///   exactly three times the triangles), so the quads' edges are about the target size.
/// - `Mixed`: the four-cornered faces block-structured, the others split from triangles, at
///   twice the target size, then every element split (a quad into four, a triangle into
///   three). Such a surface is not loop-clean by construction, so it is checked
///   (`diagnose`); one with a self-intersecting loop is dropped for `TriangleSplit`.
/// `Auto` takes `Transfinite` when every face qualifies (falling back to `TriangleSplit`, with
/// a warning, should Gmsh's transfinite meshing still fail), `Mixed` when some do and the
/// result is loop-clean, `TriangleSplit` otherwise, and says why in the record.
///
/// Side effect a library user should know: while Gmsh reads a file, the process's standard
/// output (file descriptor 1) is redirected into a temporary file, because OpenCASCADE's
/// readers print there past Gmsh's own settings; with `CadOptions::verbose` it is sent to
/// standard error for the whole call instead. Other threads printing on stdout meanwhile
/// are redirected too.
///
/// Without Gmsh at build time (CMake option `STCWEAVE_WITH_GMSH=OFF`) every function here
/// that needs Gmsh throws `Unsupported` with `cad_unavailable_message`.

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// How the surface of a CAD solid is meshed into quads.
enum class CadRecipe {
  Auto,         ///< `Transfinite` when every face has four corners, else `Mixed` or `TriangleSplit`
  Transfinite,  ///< block-structured faces (refused when a face does not have 4 corners)
  /// triangles (Gmsh's `CadOptions::triangle_algorithm`), each split into three quads
  TriangleSplit,
  /// four-cornered faces structured, the others split from triangles; checked loop-clean
  /// (else `TriangleSplit`, with a warning)
  Mixed,
};

/// `"auto"`, `"transfinite"`, `"triangle-split"`, `"mixed"`.
[[nodiscard]] std::string_view cad_recipe_name(CadRecipe recipe);

/// The recipe named `name` (one of the names of `cad_recipe_name`).
/// \throw InvalidInput for any other name; the message lists the valid ones.
[[nodiscard]] CadRecipe cad_recipe_from_name(std::string_view name);

/// Settings of the CAD front end.
struct CadOptions {
  /// Target edge length of the quads. `<= 0` (the default): a tenth of the diagonal of the
  /// solid's bounding box.
  double size = 0.0;
  /// Which recipe; `Auto` by default.
  CadRecipe recipe = CadRecipe::Auto;
  /// Gmsh's 2D algorithm (`Mesh.Algorithm`) for the triangles of `TriangleSplit` and of the
  /// split faces of `Mixed`: 1 MeshAdapt, 5 Delaunay (the default: it beats Gmsh's all-hex
  /// mesh on more rows of the CAD table than 6, docs/cad.md), 6 Frontal-Delaunay. Others are
  /// refused (`InvalidInput`).
  int triangle_algorithm = 5;
  /// Let Gmsh (and OpenCASCADE's readers) print their messages, on standard error (the
  /// process's stdout is sent there while Gmsh works); false by default: Gmsh is silenced
  /// (`General.Terminal` 0, its messages go to its logger) and what OpenCASCADE prints is
  /// captured, the errors among them ending up in the exceptions' messages.
  bool verbose = false;
  /// Before meshing, split a recognised solid into blocks whose faces all have four corners,
  /// so that it takes the transfinite recipe (docs/cad.md, "Splitting into blocks"): a right
  /// circular cylinder into an O-grid of 5 blocks, a sphere into a cubed sphere of 7, a solid
  /// of planar faces and straight edges by the axis planes through its corners (kept only
  /// when every face of the blocks then has four corners). The surface keeps the solid's
  /// geometry. Not applied with `CadRecipe::TriangleSplit`; on by default.
  bool split = true;
};

/// What the CAD front end did: enough to re-run it and to judge the surface.
struct CadRecord {
  std::string path;                    ///< the CAD file, or "generated <shape>" for a primitive
  std::string format;                  ///< "step", "brep", "iges" or "occ" (a primitive)
  std::string gmsh_version;            ///< of the Gmsh library linked in
  CadRecipe recipe = CadRecipe::Auto;  ///< the recipe used (never `Auto`)
  std::string reason;                  ///< why this recipe (e.g. "face 3 has 6 corners")
  /// How the solid was split into blocks before meshing (`CadOptions::split`), "" when not.
  std::string split;
  double size = 0.0;                 ///< the target edge length used
  std::size_t volumes = 0;           ///< solids in the file
  std::size_t faces = 0;             ///< CAD faces of the solids' boundary
  std::size_t curves = 0;            ///< CAD curves of those faces
  std::size_t triangles = 0;         ///< triangles before the split (`TriangleSplit`: quads / 3)
  std::size_t structured_faces = 0;  ///< CAD faces meshed block-structured
  std::size_t quads = 0;             ///< quads of the surface made
  std::size_t nodes = 0;             ///< nodes of the surface made
  /// Largest distance from a surface node to the CAD entity (face, curve or point) Gmsh
  /// placed it on, measured with Gmsh's closest-point projection.
  double max_cad_distance = 0.0;
  std::vector<std::string> warnings;  ///< Gmsh's warnings, in order
  double seconds = 0.0;               ///< wall-clock time of the whole front end
};

/// A quad surface made from a CAD solid, with the record of how.
struct CadSurface {
  /// The surface as a reader would have returned it (`format` is the CAD format, quads
  /// with `quad_lines` all 0); feed it to `mesh_file`. Nodes are numbered by increasing
  /// Gmsh node tag, quads by CAD face then Gmsh element tag.
  MeshFile file;
  CadRecord record;
};

/// A solid made with the OpenCASCADE kernel, for tests and benchmarks without files.
struct CadPrimitive {
  enum class Kind {
    Box,       ///< `a` x `b` x `c`, corner at the origin
    Cylinder,  ///< radius `a`, height `b`, axis z from the origin
    Sphere,    ///< radius `a`, centred at the origin
    LBlock,    ///< an `a` x `b` x `c` box with the quarter x > a/2, y > b/2 removed
    /// The same L-block as three boxes glued face to face (OpenCASCADE's fragment), as a
    /// block-structured CAD model is built: every face of the three has four corners.
    LBlockBlocks,
    /// An `a` x `b` x `c` plate, corner at the origin, with a through-hole along z of radius
    /// min(a, b) / 4 at its centre (genus 1; one solid).
    PlateWithHole,
    /// The same plate as four blocks glued face to face (cut along its diagonals), so that
    /// every face of the four has four corners.
    PlateWithHoleBlocks,
    /// A torus around the z axis, centre-line radius `a`, tube radius `b` (one solid, one face).
    Torus,
    /// The same torus as 20 blocks glued face to face: the tube's section split as an O-grid
    /// (a square core and four ring pieces), swept in four quarter turns, so that every face of
    /// the 20 has four corners.
    TorusBlocks,
  };
  Kind kind = Kind::Box;
  double a = 1.0;
  double b = 1.0;
  double c = 1.0;
};

/// True when stcweave was built with Gmsh (CMake option `STCWEAVE_WITH_GMSH`).
[[nodiscard]] bool has_cad_support();

/// True when `path` has a CAD extension: `.step`, `.stp`, `.brep`, `.iges`, `.igs`
/// (case-insensitive). Does not look at the file.
[[nodiscard]] bool is_cad_path(const std::filesystem::path& path);

/// The message a build without Gmsh gives for the CAD file `path`: what (no CAD support),
/// why (built without Gmsh) and what to do (install libgmsh-dev and reconfigure, or give a
/// quad surface).
[[nodiscard]] std::string cad_unavailable_message(const std::filesystem::path& path);

/// Reads the solid(s) of a CAD file and meshes their boundary into a closed quad surface
/// with the recipe of `options` (see the file comment). The boundary nodes lie on the CAD
/// surface (`CadRecord::max_cad_distance` says how closely).
/// \throw IoError when the file does not exist or cannot be read.
/// \throw InvalidInput when Gmsh cannot read it (Gmsh's and OpenCASCADE's reason in the
///        message), when it holds no solid (an open shell, loose faces), for a bad size,
///        and when Gmsh fails to mesh its surface (with Gmsh's reason).
/// \throw Unsupported without Gmsh at build time, and for `CadRecipe::Transfinite` on a
///        solid with a face that has not four corners.
[[nodiscard]] CadSurface mesh_cad_surface(const std::filesystem::path& path,
                                          const CadOptions& options = {});

/// The same for a primitive built in memory with Gmsh's OpenCASCADE kernel.
/// \throw InvalidInput for non-positive dimensions, and as `mesh_cad_surface(path)`.
[[nodiscard]] CadSurface mesh_cad_surface(const CadPrimitive& primitive,
                                          const CadOptions& options = {});

}  // namespace stcweave::primal
