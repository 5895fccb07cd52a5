#pragma once
/// \file
/// The browser page of a hex mesh: one self-contained HTML file (three.js, the page's script
/// and the mesh data inlined; no network) that draws the mesh with WebGL and replays its weave.
///
/// What the page offers: a slider that replays the hexes in creation order and names, for the
/// step, the rule that made the hex and the loop shrink it belongs to (the (loop, side) chosen,
/// its length and depth, what decided the choice); colouring by sheets (each visible face shows
/// the two sheets crossing it, as a woven pattern), by sheet layer, by scaled Jacobian, depth,
/// layer, creation step or shrink, with a legend; picking a hex (click) and showing only one of
/// its sheets or chords; a clipping plane that removes whole hexes; the scaled Jacobian
/// histogram. The design and the data layout are in docs/viewer.md.
///
/// Data layout: a `<script type="application/json" id="stcweave-data">` element holds a JSON
/// object whose large arrays are base64 strings of little-endian typed arrays: `points`
/// (float32 x 3 per node) and `scaled_jacobian` (float32); the integer arrays `hex_nodes` (8
/// per hex), `neighbours` (6 per hex, -1 on the boundary), `sheet_ids`, `chord_ids` (3 per
/// hex), `layer`, `order` (hex ids in creation order), `shrink`, `depth`, `rule` (codes of
/// `primal::rule_code`), `rule_node` as `{offset, bytes, data}`: value - offset in the
/// narrowest unsigned type (1, 2 or 4 bytes). docs/viewer.md has the rest.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "stcweave/primal/mesh.hpp"
#include "stcweave/primal/mesh_data.hpp"
#include "stcweave/stc/hex_stc.hpp"

namespace stcweave::viewer {

/// True when three.js was found at build time (Debian's libjs-three); without it no page can
/// be made.
[[nodiscard]] bool has_three_js();

/// What the page shows besides the mesh.
struct PageOptions {
  std::string title = "stcweave";  ///< the page's title (e.g. the input file's name)
  /// Per loop shrink, what the trace recorded (`primal::WeaveHistory::shrinks`); empty: the
  /// replay names the shrink index only.
  std::vector<primal::ShrinkRecord> shrinks;
  /// Per hex, the node its rule was applied at (`primal::WeaveHistory::hex_node`); may be
  /// empty.
  std::vector<NodeId> hex_nodes;
};

/// The page of `mesh`. `data` gives the per-hex arrays by name (see mesh_data.hpp):
/// `scaled_jacobian` and `layer` are computed when absent; `creation_step`, `shrink`, `rule`
/// and `depth` make the replay follow the weave (without `creation_step` it follows the hex
/// order of the mesh and says so).
/// \pre `stc` is the STC of `mesh.complex`.
/// \throw Unsupported when three.js was absent at build time (install libjs-three, rebuild).
/// \throw InvalidInput when `stc` or an array of `data` does not match the mesh.
[[nodiscard]] std::string page_html(const primal::HexMesh& mesh, const stc::HexStc& stc,
                                    const primal::MeshData& data, const PageOptions& options = {});

/// Writes `page_html(...)` to `path` (through a temporary file and a rename).
/// \throw as `page_html`; IoError when the file cannot be written.
void write_page(const std::filesystem::path& path, const primal::HexMesh& mesh,
                const stc::HexStc& stc, const primal::MeshData& data,
                const PageOptions& options = {});

/// Base64 (RFC 4648, with padding) of `bytes`; what the page embeds.
[[nodiscard]] std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace stcweave::viewer
