#pragma once
/// \file
/// Meshes with coordinates: a quad surface or a hex complex plus a "#V by 3" point matrix.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <vector>

#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::primal {

/// Node coordinates, one row per node ("#V by 3").
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3>;

/// A quad surface with coordinates. `points.rows() == surface.num_nodes`.
struct SurfaceMesh {
  Points points;
  stc::QuadSurface surface;
};

/// A hex mesh with coordinates. `points.rows() == complex.num_nodes`.
struct HexMesh {
  Points points;
  stc::HexComplex complex;
};

/// Everything a reader found in a file, before any interpretation. Node ids are 0-based
/// rows of `points` (readers translate 1-based or tagged ids).
struct MeshFile {
  std::string path;    ///< as given to the reader
  std::string format;  ///< "obj", "off", "vtk", "msh2", "msh4", "medit", "mfem"
  Points points;
  std::vector<stc::Quad> quads;  ///< surface quads found in the file
  std::vector<stc::Hex> hexes;   ///< hexahedra, VTK order
  std::size_t triangles = 0;     ///< triangles found (a quad surface must have none)
  std::size_t tetrahedra = 0;
  std::size_t other_cells = 0;  ///< prisms, pyramids, polygons with > 4 sides, ...
  /// The first of `other_cells`: where it is and what it is ("line 12: VTK cell type 13
  /// with 6 nodes"), for the diagnosis's message; empty when there is none.
  std::string first_other_cell;
  std::vector<std::string> notes;  ///< quirks met while reading (e.g. mislabelled cells)
  /// For each quad, the 1-based line of the file where it is defined (0 when unknown).
  std::vector<std::size_t> quad_lines;
};

}  // namespace stcweave::primal
