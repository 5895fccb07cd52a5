#pragma once
/// \file
/// Per-hex and per-node data of a hex mesh, as the writers store them (VTK `CELL_DATA` /
/// `POINT_DATA`, VTU `<CellData>` / `<PointData>`, Gmsh `$ElementData` / `$NodeData`) and
/// as the browser page (`stcweave::viewer`) draws them.
///
/// Cell arrays written by `hex_mesh_data` (names chosen for ParaView users):
/// | name | type | meaning |
/// |---|---|---|
/// | `scaled_jacobian` | double | Verdict scaled Jacobian of the hex (`hex_scaled_jacobian`) |
/// | `sheet_0`, `sheet_1`, `sheet_2` | int | the sheet through the hex in edge direction 0, 1, 2
/// (`stc::StcVertex::sheets`) | | `chord_0`, `chord_1`, `chord_2` | int | the chord through the hex
/// along axis 0, 1, 2 (`stc::StcVertex::chords`) | | `layer` | int | dual distance to the boundary:
/// 0 for a hex with a boundary face, i+1 for a hex sharing a face with a layer-i hex (derived here,
/// always available) | | `creation_step` | int | rank of the hex in the weave's creation order (0 =
/// first hex made) | | `shrink` | int | index of the loop shrink that made the hex (the trace's
/// `shrink`; undone shrinks leave gaps) | | `rule` | int | the rule that made it: 0 cross, 1
/// cross-relaxed, 2 blind-chord, 3 parallel-merge, 9 another rule | | `depth` | int | the depth
/// (seed sect. 6) of the (loop, side) that shrink chose, from the trace; 0 with the `reliable`
/// rules, -1 when the trace did not record that shrink |
///
/// The four weave arrays are present only when the mesh comes from a weave (`WeaveHistory`).
/// Point arrays: `boundary` (1 for a node on a boundary face, else 0) and `valence` (number of
/// hexes sharing the node: 8 at a regular interior node, 4 on a flat boundary).

#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "stcweave/primal/io.hpp"
#include "stcweave/primal/mesh.hpp"
#include "stcweave/stc/hex_stc.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::primal {

/// How the values of a data array are written.
enum class DataType {
  Int32,    ///< integers (VTK `int`, VTU `Int32`)
  Float64,  ///< reals with `%.17g` (VTK `double`, VTU `Float64`)
};

/// A named array with one value per cell (hex) or per point (node), in id order.
struct DataArray {
  std::string name;  ///< letters, digits and `_` only (checked by the writers)
  DataType type = DataType::Float64;
  std::vector<double> values;
};

/// The cell and point arrays written beside a hex mesh.
struct MeshData {
  std::vector<DataArray> cells;   ///< one value per hex
  std::vector<DataArray> points;  ///< one value per node
  /// The cell array named `name`, or nullptr.
  [[nodiscard]] const DataArray* cell(std::string_view name) const;
  /// The point array named `name`, or nullptr.
  [[nodiscard]] const DataArray* point(std::string_view name) const;
  [[nodiscard]] bool empty() const { return cells.empty() && points.empty(); }
};

/// Codes of the `rule` cell array.
inline constexpr int kRuleCross = 0;
inline constexpr int kRuleCrossRelaxed = 1;
inline constexpr int kRuleBlindChord = 2;
inline constexpr int kRuleParallelMerge = 3;
/// A hex the pillow stage added after the weave (pillow.hpp).
inline constexpr int kRulePillow = 4;
/// A hex of the tet interior (tet_interior.hpp): a quarter of a split tetrahedron.
inline constexpr int kRuleTetSplit = 5;
inline constexpr int kRuleOther = 9;
/// The code of a weave rule name (`"cross"` -> 0, ...; an unknown name -> `kRuleOther`).
[[nodiscard]] int rule_code(std::string_view rule);
/// The name of a rule code (`"other"` for `kRuleOther` and any unknown code).
[[nodiscard]] std::string_view rule_name(int code);

/// One loop shrink: the (loop, side) its selection chose (`weave::WeaveResult::shrinks`).
using ShrinkRecord = weave::ShrinkRecord;

/// What a weave tells about each hex it made and each loop shrink.
struct WeaveHistory {
  std::vector<std::int32_t> hex_shrink;  ///< per hex, `weave::WeaveResult::hex_shrink`
  std::vector<std::string> hex_rule;     ///< per hex, `weave::WeaveResult::hex_rule`
  /// Per hex, the node the rule was applied at (invalid where no rule made it at a node).
  std::vector<NodeId> hex_node;
  /// The shrinks, by increasing index.
  std::vector<ShrinkRecord> shrinks;
  /// The record of shrink `index`, or nullptr when the trace did not record it.
  [[nodiscard]] const ShrinkRecord* shrink(std::int32_t index) const;
};

/// Gathers from trace events what `WeaveResult::shrinks` and `WeaveResult::hex_node` hold, for
/// a caller that has the trace alone (`stcweave view` of a trace file): hand `add` every event
/// in order. Keeps one record per selection and the node of each rule that made a hex.
class TraceDigest {
 public:
  /// Takes one trace event into account. A rule event for a hex id seen before (a shrink
  /// undone by backtracking, its hex ids made again) replaces the earlier one.
  void add(const weave::TraceEvent& event);
  [[nodiscard]] const std::vector<ShrinkRecord>& shrinks() const { return shrinks_; }
  [[nodiscard]] const std::vector<NodeId>& hex_nodes() const { return hex_nodes_; }

 private:
  std::vector<ShrinkRecord> shrinks_;
  std::vector<NodeId> hex_nodes_;
};

/// The history of a weave: `woven`'s per-hex shrink, rule and node, and its shrink records.
/// \throw InvalidInput when `woven.hex_shrink` or `woven.hex_rule` does not have one entry
///        per hex, or `woven.hex_node` is neither empty nor one entry per hex.
[[nodiscard]] WeaveHistory weave_history(const weave::WeaveResult& woven);

/// Extends `history` to `hexes` hexes with the hexes a later stage appended after the woven
/// ones (the pillow stage appends its hexes, `MeshResult::mesh`): shrink -1, rule `rule`, no
/// node. \throw InvalidInput when `history` already covers more than `hexes` hexes.
void append_hexes(WeaveHistory& history, std::size_t hexes, const std::string& rule);

/// For each hex and face (`stc::kHexFaces` order), the hex across that face, -1 on the
/// boundary, -2 when three or more hexes share the face. Deterministic (a sort of faces).
[[nodiscard]] std::vector<std::array<std::int32_t, 6>> hex_face_neighbours(
    const stc::HexComplex& complex);

/// Dual distance of every hex to the boundary from the face neighbours (0: a hex with a
/// boundary face); hexes no path reaches get -1.
[[nodiscard]] std::vector<std::int32_t> hex_layers(
    const std::vector<std::array<std::int32_t, 6>>& neighbours);

/// The cell and point data of a hex mesh (see the table of this file): quality, sheets,
/// chords and layer always, the four weave arrays when `history` is given.
/// \pre `stc` is the STC of `mesh.complex` (`stc::build_hex_stc`).
/// \throw InvalidInput when `stc` or `history` does not have one entry per hex.
[[nodiscard]] MeshData hex_mesh_data(const HexMesh& mesh, const stc::HexStc& stc,
                                     const WeaveHistory* history = nullptr);

/// Writes a hex mesh with cell and point data: legacy VTK, VTU and Gmsh MSH (4.1 and 2.2)
/// store `data`; MEDIT and Abaqus have no place for it and get the mesh alone. Empty
/// `data`: the same bytes as `write_hex_mesh(mesh, path, format)`.
/// \throw InvalidInput when an array has the wrong length or an invalid name, and as
///        `write_hex_mesh`.
/// \throw IoError as `write_hex_mesh`.
void write_hex_mesh(const HexMesh& mesh, const MeshData& data, const std::filesystem::path& path,
                    Format format = Format::Auto);

/// Reads the cell and point data of a hex mesh file: legacy VTK (`SCALARS` and `FIELD`
/// arrays of `CELL_DATA` / `POINT_DATA`, first component of each), VTU (`<CellData>`,
/// `<PointData>`, ASCII) and Gmsh MSH (`$ElementData`, `$NodeData`, first time step).
/// Other formats have none: empty data. Values are in the file's cell / node order.
/// \throw IoError when the file cannot be read.
/// \throw InvalidInput when a data section is malformed (file, line, what to do).
[[nodiscard]] MeshData read_mesh_data(const std::filesystem::path& path,
                                      Format format = Format::Auto);
/// Same, from text held in memory; `name` stands for the file in messages.
[[nodiscard]] MeshData read_mesh_data(std::string_view text, Format format,
                                      const std::string& name);

}  // namespace stcweave::primal
