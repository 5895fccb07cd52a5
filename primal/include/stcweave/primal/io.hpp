#pragma once
/// \file
/// Mesh readers and writers (ASCII formats only).
///
/// Readers return a `MeshFile`: what the file holds, before any interpretation (node ids
/// are 0-based rows of `points`, hexes in VTK order, quads as written). They never crash
/// on bad content: every count and every node index is checked, and a problem is reported
/// as `InvalidInput` with the file, the 1-based line, the element and what to do.
/// Non-finite coordinates (`nan`, `inf`) are kept as read: the diagnosis reports them.
///
/// Writers format numbers with `%.17g` (so output is byte-for-byte deterministic and
/// doubles round-trip exactly), write to a temporary file in the target folder and rename
/// it over the target, so a failure never leaves a truncated file behind.
///
/// Hex node order: VTK, Gmsh, MEDIT, MFEM and Abaqus C3D8 share the same order for linear
/// hexahedra (bottom face 0-1-2-3, top face 4-7 with node i+4 above node i); VTK_VOXEL
/// (lexicographic order) is reordered on reading. Second-order cells are reduced to their
/// corners (listed first in every supported format).

#include <filesystem>
#include <iosfwd>
#include <string>
#include <string_view>

#include "stcweave/primal/mesh.hpp"

namespace stcweave::primal {

/// A mesh file format.
enum class Format {
  Auto,   ///< from the file's extension (and, on reading, its first bytes)
  Obj,    ///< Wavefront OBJ (surfaces)
  Off,    ///< Object File Format (surfaces)
  Vtk,    ///< legacy VTK, ASCII (UNSTRUCTURED_GRID or POLYDATA)
  Vtu,    ///< VTK XML unstructured grid, ASCII data arrays
  Msh,    ///< Gmsh MSH: 4.1 on writing; 2.2 or 4.1 (from `$MeshFormat`) on reading
  Msh2,   ///< Gmsh MSH 2.2 (on reading, same as `Msh`)
  Medit,  ///< MEDIT / INRIA `.mesh`, ASCII
  Mfem,   ///< MFEM mesh v1.0 (ASCII)
  Inp,    ///< Abaqus input file (`*NODE`, `*ELEMENT`)
};

/// The lowercase name of a format (`"obj"`, `"msh2"`, `"medit"`, ...; `"auto"`).
[[nodiscard]] std::string_view format_name(Format format);

/// The format named `name` (case-insensitive): `obj`, `off`, `vtk`, `vtu`, `msh`, `msh2`,
/// `mesh` or `medit`, `mfem`, `inp`.
/// \throw InvalidInput for any other name; the message lists the valid names.
[[nodiscard]] Format format_from_name(std::string_view name);

/// The format of a file from its extension (case-insensitive): `.obj`, `.off`, `.vtk`,
/// `.vtu`, `.msh` (`Format::Msh`), `.mesh` (`Format::Medit`), `.inp`.
/// \throw InvalidInput for any other extension; the message lists the valid ones.
[[nodiscard]] Format format_from_path(const std::filesystem::path& path);

/// Reads a mesh file. With `Format::Auto` the format comes from the extension, except that
/// a file starting with `MFEM` is read as MFEM whatever its extension; a file with an
/// unknown extension is recognised by its first bytes when possible.
/// Reads: OBJ, OFF, legacy VTK (classic `CELLS` and VTK 5.1 `OFFSETS`/`CONNECTIVITY`
/// layouts), VTU (ASCII), Gmsh MSH 2.2 and 4.1 (ASCII), MEDIT, MFEM v1.0, Abaqus `.inp`.
/// \throw IoError when the file cannot be opened or read.
/// \throw InvalidInput when its content cannot be used (message: `file:line: what; what to
///        do`).
[[nodiscard]] MeshFile read_mesh(const std::filesystem::path& path, Format format = Format::Auto);

/// Reads a mesh from a stream (for tests and in-memory data); `name` stands for the file in
/// messages and in `MeshFile::path`. Content starting with `MFEM` is always read as MFEM;
/// with `Format::Auto` the format is recognised from the first bytes when possible (VTK,
/// VTU, MSH, MEDIT, OFF; not OBJ or INP).
/// \throw InvalidInput as `read_mesh(path)`, and for `Format::Auto` on unrecognised content.
[[nodiscard]] MeshFile read_mesh(std::istream& in, Format format, const std::string& name);

/// Writes a hex mesh: legacy VTK (`.vtk`, cell type 12), VTU (`.vtu`, ASCII), Gmsh MSH 4.1
/// (`.msh`) or 2.2 (`Format::Msh2`), MEDIT (`.mesh`, `Hexahedra`) or Abaqus (`.inp`, C3D8,
/// 1-based). With `Format::Auto`, the format comes from the extension.
/// \pre every hex node is a row of `mesh.points` (checked).
/// \throw InvalidInput for a format that cannot hold hexes, or a node outside the points.
/// \throw IoError when the file cannot be written (the target is then left untouched).
void write_hex_mesh(const HexMesh& mesh, const std::filesystem::path& path,
                    Format format = Format::Auto);

/// Writes a quad surface as OBJ, OFF or legacy VTK POLYDATA. With `Format::Auto`, the
/// format comes from the extension.
/// \pre every quad node is a row of `mesh.points` (checked).
/// \throw InvalidInput for another format, or a node outside the points.
/// \throw IoError when the file cannot be written (the target is then left untouched).
void write_surface(const SurfaceMesh& mesh, const std::filesystem::path& path,
                   Format format = Format::Auto);

/// Writes `text` to `path` the way the mesh writers do: through a temporary file in the same
/// folder, then a rename, so a failure never leaves a half-written file in place.
/// \throw IoError when the file cannot be written (the target is then left untouched).
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace stcweave::primal
