#pragma once
/// \file
/// Export of the STC graphs of a hex complex (the dual graph and the sheet graph) to
/// GraphViz DOT and GraphML. Output is deterministic (vertices and edges in id order) and
/// names elements with their ids: `h3` (hex), `q5` (boundary point of boundary quad 5),
/// `s2` (sheet), `c7` (chord).
///
/// Attributes written:
/// - dual graph: vertex `label` (`h3` / `q5`), `kind` (`hex` / `boundary_point`); edge
///   `label` = `chord` (the chord crossing the face), `face` (`h3.f2`, the face in its
///   lower-id hex).
/// - sheet graph: vertex `label` (`s2`), `hexes`, `loops`, `chords`, `self_intersecting`,
///   `blind`; edge `label` (`c7`), `hexes` (its length), `blind`.

#include <filesystem>
#include <iosfwd>
#include <vector>

#include "stcweave/stc/hex_stc.hpp"

namespace stcweave::stc {

/// Which graph of the STC to export.
enum class StcGraph { Dual, Sheet };

/// Output format of a graph.
enum class GraphFormat { Dot, GraphMl };

/// Writes one graph of `stc` to `out`.
void write_graph(std::ostream& out, const HexStc& stc, StcGraph graph, GraphFormat format);

/// Writes several graphs of `stc` to one stream: GraphML holds them as sibling `<graph>`
/// elements (ids `dual`, `sheets`) of one document; DOT as consecutive graphs.
void write_graphs(std::ostream& out, const HexStc& stc, const std::vector<StcGraph>& graphs,
                  GraphFormat format);

/// Writes `graphs` to `path` through a temporary file renamed at the end, so a failure
/// never leaves a half-written file in place of a good one.
/// \throw IoError when the file cannot be written.
void write_graph_file(const std::filesystem::path& path, const HexStc& stc,
                      const std::vector<StcGraph>& graphs, GraphFormat format);

}  // namespace stcweave::stc
