#include "stcweave/stc/hex_stc.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>

#include "stcweave/stc/bucket_sort.hpp"
#include "stcweave/stc/errors.hpp"
#include "union_find.hpp"

/// How the STC is found, and why it is right.
///
/// Sheets: a union-find over the distinct edges of the complex joins, in every hex, the
/// four edges of each direction; a class is a sheet (two edges opposite in a face of a hex
/// are dual to the same sheet). Chords: faces are matched by their node sets, so that each
/// hex face knows the hex face on its other side; a chord enters a hex through one face
/// and leaves through the opposite one, so following face matches from a hex along one
/// axis either reaches a boundary face in both directions (open chord) or comes back
/// (ring). Since the face match is an involution and "leave by the opposite face" a
/// bijection, every (hex, axis) lies on exactly one chord, visited once. Loops: on the
/// boundary quads, a loop enters a quad through one side and leaves through the opposite
/// one; it is traced through the boundary-edge adjacency, and the sheet it bounds is the
/// sheet of the (hex) edges it crosses. Everything is numbered by scans in increasing
/// order, so the result is deterministic.

namespace stcweave::stc {
namespace {

constexpr std::array<int, 12> kEdgeDirection = {0, 1, 0, 1, 0, 1, 0, 1, 2, 2, 2, 2};
constexpr std::array<int, 6> kFaceAxis = {2, 2, 1, 0, 1, 0};
constexpr std::array<int, 6> kOppositeFace = {1, 0, 4, 5, 2, 3};
constexpr std::array<std::array<int, 2>, 3> kAxisFaces = {{{5, 3}, {2, 4}, {0, 1}}};

std::string face_str(const Quad& q) {
  return q[0].str() + " " + q[1].str() + " " + q[2].str() + " " + q[3].str();
}

void check_nodes(const HexComplex& complex) {
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    const Hex& hex = complex.hexes[h];
    for (std::size_t i = 0; i < 8; ++i) {
      if (!hex[i].is_valid() || hex[i].index() >= complex.num_nodes) {
        throw InvalidInput(HexId(h).str() + " has node " + hex[i].str() +
                           " out of range (the complex has " + std::to_string(complex.num_nodes) +
                           " nodes)");
      }
      for (std::size_t j = 0; j < i; ++j) {
        if (hex[i] == hex[j])
          throw InvalidInput(HexId(h).str() + " has node " + hex[i].str() +
                             " twice (a hex needs 8 distinct nodes)");
      }
    }
  }
}

using detail::UnionFind;

/// Faces matched by node set: for every hex face slot (6h+f) its face id; per face, its
/// use count and its first two slots.
struct FaceTable {
  std::vector<std::uint32_t> face_of_slot;
  std::vector<int> count;
  std::vector<std::array<std::int64_t, 2>> slots;

  [[nodiscard]] std::int64_t neighbour(std::size_t slot) const {
    const std::uint32_t f = face_of_slot[slot];
    if (count[f] != 2) return -1;
    return slots[f][0] == static_cast<std::int64_t>(slot) ? slots[f][1] : slots[f][0];
  }
};

FaceTable match_faces(const HexComplex& complex) {
  struct Entry {
    std::array<std::int32_t, 4> key;
    std::uint32_t slot;
  };
  std::vector<Entry> entries;
  entries.reserve(complex.hexes.size() * 6);
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (int f = 0; f < 6; ++f) {
      const Quad q = hex_face(complex.hexes[h], f);
      Entry e{{q[0].value(), q[1].value(), q[2].value(), q[3].value()},
              static_cast<std::uint32_t>(6 * h + static_cast<std::size_t>(f))};
      std::sort(e.key.begin(), e.key.end());
      entries.push_back(e);
    }
  }
  sort_by_smallest_node(
      entries, [](const Entry& e) { return e.key[0]; },
      [](const Entry& a, const Entry& b) {
        return a.key != b.key ? a.key < b.key : a.slot < b.slot;
      });
  FaceTable t;
  t.face_of_slot.assign(entries.size(), 0);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i == 0 || entries[i].key != entries[i - 1].key) {
      t.count.push_back(0);
      t.slots.push_back({-1, -1});
    }
    const auto f = static_cast<std::uint32_t>(t.count.size() - 1);
    if (t.count[f] < 2) t.slots[f][static_cast<std::size_t>(t.count[f])] = entries[i].slot;
    ++t.count[f];
    t.face_of_slot[entries[i].slot] = f;
  }
  return t;
}

/// Distinct edges: for every hex edge slot (12h+k) its edge id.
std::vector<std::uint32_t> match_edges(const HexComplex& complex, std::size_t* num_edges) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  entries.reserve(complex.hexes.size() * 12);
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (std::size_t k = 0; k < 12; ++k) {
      const auto [a, b] = kHexEdges[k];
      auto u = static_cast<std::uint64_t>(complex.hexes[h][static_cast<std::size_t>(a)].value());
      auto v = static_cast<std::uint64_t>(complex.hexes[h][static_cast<std::size_t>(b)].value());
      if (u > v) std::swap(u, v);
      entries.emplace_back((u << 32) | v, static_cast<std::uint32_t>(12 * h + k));
    }
  }
  sort_by_smallest_node(entries, [](const auto& e) { return e.first >> 32; });
  std::vector<std::uint32_t> edge_of_slot(entries.size(), 0);
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i > 0 && entries[i].first != entries[i - 1].first) ++next;
    edge_of_slot[entries[i].second] = next;
  }
  *num_edges = entries.empty() ? 0 : next + 1;
  return edge_of_slot;
}

}  // namespace

HexStc build_hex_stc(const HexComplex& complex) {
  check_nodes(complex);
  const std::size_t num_hexes = complex.hexes.size();
  HexStc stc;
  stc.vertices.resize(num_hexes);

  // Faces: refuse non-manifold faces, number boundary quads as boundary_surface does.
  const FaceTable faces = match_faces(complex);
  for (std::size_t f = 0; f < faces.count.size(); ++f) {
    if (faces.count[f] > 2) {
      const auto slot = static_cast<std::size_t>(faces.slots[f][0]);
      const auto other = static_cast<std::size_t>(faces.slots[f][1]);
      throw InvalidInput("the STC of a non-manifold hex complex is undefined: face (" +
                         face_str(hex_face(complex.hexes[slot / 6], static_cast<int>(slot % 6))) +
                         ") belongs to " + std::to_string(faces.count[f]) + " hexes (" +
                         HexId(slot / 6).str() + ", " + HexId(other / 6).str() +
                         ", ...); run validate to list every defect");
    }
  }
  // Two hexes sharing two faces (duplicated hexes): a chord through them has no order.
  for (std::size_t h = 0; h < num_hexes; ++h) {
    for (std::size_t i = 1; i < 6; ++i) {
      const std::int64_t a = faces.neighbour(6 * h + i);
      if (a < 0) continue;
      for (std::size_t j = 0; j < i; ++j) {
        const std::int64_t b = faces.neighbour(6 * h + j);
        if (b < 0 || b / 6 != a / 6) continue;
        throw InvalidInput("the STC of this hex complex is undefined: hexes " + HexId(h).str() +
                           "+" + HexId(static_cast<std::size_t>(a / 6)).str() +
                           " share two faces (two hexes share at most one: duplicated hexes?); "
                           "run validate to list every defect");
      }
    }
  }
  std::vector<QuadId> boundary_of_slot(6 * num_hexes, QuadId::invalid());
  stc.boundary.num_nodes = complex.num_nodes;
  for (std::size_t slot = 0; slot < 6 * num_hexes; ++slot) {
    if (faces.count[faces.face_of_slot[slot]] != 1) continue;
    boundary_of_slot[slot] = QuadId(stc.boundary.quads.size());
    stc.boundary.quads.push_back(hex_face(complex.hexes[slot / 6], static_cast<int>(slot % 6)));
  }

  // Sheets: classes of edges made parallel through hexes.
  std::size_t num_edges = 0;
  const std::vector<std::uint32_t> edge_of_slot = match_edges(complex, &num_edges);
  UnionFind edge_classes(num_edges);
  for (std::size_t h = 0; h < num_hexes; ++h) {
    std::array<std::uint32_t, 3> first{};
    std::array<bool, 3> seen{};
    for (std::size_t k = 0; k < 12; ++k) {
      const auto d = static_cast<std::size_t>(kEdgeDirection[k]);
      const std::uint32_t e = edge_of_slot[12 * h + k];
      if (!seen[d]) {
        first[d] = e;
        seen[d] = true;
      } else {
        edge_classes.unite(first[d], e);
      }
    }
  }
  std::vector<SheetId> sheet_of_root(num_edges, SheetId::invalid());
  const auto sheet_of_edge = [&](std::uint32_t e) -> SheetId& {
    return sheet_of_root[edge_classes.find(e)];
  };
  for (std::size_t h = 0; h < num_hexes; ++h) {
    StcVertex& vertex = stc.vertices[h];
    for (std::size_t d = 0; d < 3; ++d) {
      // The first edge of direction d: local edges 0, 1 and 8.
      static constexpr std::array<std::size_t, 3> kFirstEdge = {0, 1, 8};
      SheetId& sheet = sheet_of_edge(edge_of_slot[12 * h + kFirstEdge[d]]);
      if (!sheet.is_valid()) {
        sheet = SheetId(stc.sheets.size());
        stc.sheets.emplace_back();
      }
      vertex.sheets[d] = sheet;
    }
    for (std::size_t d = 0; d < 3; ++d) {
      Sheet& sheet = stc.sheets[vertex.sheets[d].index()];
      bool repeated = false;
      for (std::size_t e = 0; e < 3; ++e)
        if (e != d && vertex.sheets[e] == vertex.sheets[d]) repeated = true;
      if (repeated) sheet.self_intersecting = true;
      if (sheet.hexes.empty() || sheet.hexes.back() != HexId(h)) sheet.hexes.push_back(HexId(h));
    }
  }

  // Chords: follow face matches through opposite faces.
  std::vector<std::array<bool, 3>> assigned(num_hexes, {false, false, false});
  const std::size_t step_limit = 3 * num_hexes + 1;
  for (std::size_t h0 = 0; h0 < num_hexes; ++h0) {
    for (std::size_t a0 = 0; a0 < 3; ++a0) {
      if (assigned[h0][a0]) continue;
      // Walk from h0 out of face kAxisFaces[a0][0] until a boundary face or back at h0.
      std::size_t h = h0;
      int in_face = kAxisFaces[a0][1];
      bool closed = false;
      for (std::size_t steps = 0;; ++steps) {
        if (steps > step_limit)
          throw InternalError("chord through " + HexId(h0).str() + " does not end");
        const int out_face = kOppositeFace[static_cast<std::size_t>(in_face)];
        const std::int64_t next = faces.neighbour(6 * h + static_cast<std::size_t>(out_face));
        if (next < 0) break;
        h = static_cast<std::size_t>(next) / 6;
        in_face = static_cast<int>(next % 6);
        if (h == h0 &&
            static_cast<std::size_t>(kFaceAxis[static_cast<std::size_t>(in_face)]) == a0) {
          closed = true;
          break;
        }
      }
      Chord chord;
      chord.closed = closed;
      const auto id = ChordId(stc.chords.size());
      if (closed) {
        h = h0;
        in_face = kAxisFaces[a0][0];
      } else {
        // h was left through a boundary face: start there and walk back.
        const int out_face = kOppositeFace[static_cast<std::size_t>(in_face)];
        chord.ends[0] = boundary_of_slot[6 * h + static_cast<std::size_t>(out_face)];
        in_face = out_face;
      }
      for (std::size_t steps = 0;; ++steps) {
        if (steps > step_limit)
          throw InternalError("chord through " + HexId(h0).str() + " does not end");
        const auto axis = static_cast<std::size_t>(kFaceAxis[static_cast<std::size_t>(in_face)]);
        if (assigned[h][axis])
          throw InternalError("chord " + id.str() + " passes twice through " + HexId(h).str());
        assigned[h][axis] = true;
        stc.vertices[h].chords[axis] = id;
        chord.hexes.push_back(HexId(h));
        const int out_face = kOppositeFace[static_cast<std::size_t>(in_face)];
        const std::size_t out_slot = 6 * h + static_cast<std::size_t>(out_face);
        const std::int64_t next = faces.neighbour(out_slot);
        if (next < 0) {
          chord.ends[1] = boundary_of_slot[out_slot];
          break;
        }
        h = static_cast<std::size_t>(next) / 6;
        in_face = static_cast<int>(next % 6);
        if (closed && h == h0 &&
            kFaceAxis[static_cast<std::size_t>(in_face)] == static_cast<int>(a0))
          break;
      }
      const StcVertex& v0 = stc.vertices[h0];
      chord.sheets = {v0.sheets[(a0 + 1) % 3], v0.sheets[(a0 + 2) % 3]};
      if (chord.sheets[1] < chord.sheets[0]) std::swap(chord.sheets[0], chord.sheets[1]);
      stc.sheets[chord.sheets[0].index()].chords.push_back(id);
      if (chord.sheets[1] != chord.sheets[0])
        stc.sheets[chord.sheets[1].index()].chords.push_back(id);
      stc.chords.push_back(std::move(chord));
    }
  }

  // Boundary points.
  stc.boundary_points.resize(stc.boundary.quads.size());
  for (std::size_t slot = 0; slot < 6 * num_hexes; ++slot) {
    const QuadId q = boundary_of_slot[slot];
    if (!q.is_valid()) continue;
    const auto face = static_cast<int>(slot % 6);
    const std::size_t h = slot / 6;
    stc.boundary_points[q.index()] = BoundaryPoint{
        q, HexId(h), face, stc.vertices[h].chords[static_cast<std::size_t>(kFaceAxis[face])]};
  }

  // Loops on the boundary: per boundary quad side, its edge and the other quad side on it.
  const std::size_t num_quads = stc.boundary.quads.size();
  std::vector<std::uint32_t> side_edge(4 * num_quads);
  std::vector<std::int64_t> edge_side_a(num_edges, -1);
  std::vector<std::int64_t> edge_side_b(num_edges, -1);
  std::vector<int> edge_side_count(num_edges, 0);
  for (std::size_t q = 0; q < num_quads; ++q) {
    const BoundaryPoint& bp = stc.boundary_points[q];
    const auto& local = kHexFaces[static_cast<std::size_t>(bp.face)];
    for (std::size_t s = 0; s < 4; ++s) {
      const int k = kHexLocalEdge[static_cast<std::size_t>(local[s])]
                                 [static_cast<std::size_t>(local[(s + 1) % 4])];
      const std::uint32_t e = edge_of_slot[12 * bp.hex.index() + static_cast<std::size_t>(k)];
      side_edge[4 * q + s] = e;
      const auto side = static_cast<std::int64_t>(4 * q + s);
      if (edge_side_count[e] == 0) edge_side_a[e] = side;
      if (edge_side_count[e] == 1) edge_side_b[e] = side;
      ++edge_side_count[e];
    }
  }
  for (std::size_t e = 0; e < num_edges; ++e) {
    if (edge_side_count[e] == 0 || edge_side_count[e] == 2) continue;
    const auto side = static_cast<std::size_t>(edge_side_a[e]);
    const Quad& q = stc.boundary.quads[side / 4];
    throw InvalidInput("the STC of a non-manifold hex complex is undefined: boundary edge " +
                       q[side % 4].str() + "-" + q[(side + 1) % 4].str() + " is shared by " +
                       std::to_string(edge_side_count[e]) +
                       " boundary quads, not 2; run validate to list every defect");
  }
  std::vector<std::array<bool, 2>> crossed(num_quads, {false, false});
  for (std::size_t q0 = 0; q0 < num_quads; ++q0) {
    for (std::size_t r0 = 0; r0 < 2; ++r0) {
      if (crossed[q0][r0]) continue;
      std::vector<QuadId> loop;
      std::size_t q = q0;
      std::size_t in_side = r0;
      for (std::size_t steps = 0;; ++steps) {
        if (steps > 2 * num_quads) throw InternalError("a boundary loop does not close");
        crossed[q][in_side % 2] = true;
        loop.push_back(QuadId(q));
        const std::size_t out = 4 * q + (in_side + 2) % 4;
        const std::uint32_t e = side_edge[out];
        const auto next = static_cast<std::size_t>(
            edge_side_a[e] == static_cast<std::int64_t>(out) ? edge_side_b[e] : edge_side_a[e]);
        q = next / 4;
        in_side = next % 4;
        if (q == q0 && in_side % 2 == r0) break;
      }
      const SheetId s = sheet_of_edge(side_edge[4 * q0 + r0]);
      stc.sheets[s.index()].boundary_loops.push_back(std::move(loop));
    }
  }
  for (Sheet& sheet : stc.sheets) std::sort(sheet.chords.begin(), sheet.chords.end());

  // The dual graph: hexes, then boundary points; one edge per face.
  stc.dual_graph = DualGraph(num_hexes + num_quads);
  for (std::size_t h = 0; h < num_hexes; ++h)
    stc.dual_graph[h] = DualVertex{DualVertexKind::HexVertex, HexId(h), QuadId::invalid()};
  for (std::size_t q = 0; q < num_quads; ++q)
    stc.dual_graph[num_hexes + q] =
        DualVertex{DualVertexKind::BoundaryPoint, stc.boundary_points[q].hex, QuadId(q)};
  for (std::size_t slot = 0; slot < 6 * num_hexes; ++slot) {
    const std::size_t h = slot / 6;
    const auto face = static_cast<int>(slot % 6);
    const DualEdge edge{HexId(h), face,
                        stc.vertices[h].chords[static_cast<std::size_t>(kFaceAxis[face])]};
    const QuadId q = boundary_of_slot[slot];
    if (q.is_valid()) {
      boost::add_edge(h, num_hexes + q.index(), edge, stc.dual_graph);
      continue;
    }
    const std::int64_t other = faces.neighbour(slot);
    if (other > static_cast<std::int64_t>(slot))
      boost::add_edge(h, static_cast<std::size_t>(other) / 6, edge, stc.dual_graph);
  }

  // The sheet graph: one edge per chord.
  stc.sheet_graph = SheetGraph(stc.sheets.size());
  for (std::size_t s = 0; s < stc.sheets.size(); ++s) stc.sheet_graph[s] = SheetVertex{SheetId(s)};
  for (std::size_t c = 0; c < stc.chords.size(); ++c) {
    const Chord& chord = stc.chords[c];
    boost::add_edge(chord.sheets[0].index(), chord.sheets[1].index(), SheetEdge{ChordId(c)},
                    stc.sheet_graph);
  }
  return stc;
}

std::size_t num_blind_chords(const HexStc& stc) {
  return static_cast<std::size_t>(std::count_if(stc.chords.begin(), stc.chords.end(),
                                                [](const Chord& c) { return is_blind(c); }));
}

std::size_t num_blind_sheets(const HexStc& stc) {
  return static_cast<std::size_t>(std::count_if(stc.sheets.begin(), stc.sheets.end(),
                                                [](const Sheet& s) { return is_blind(s); }));
}

std::size_t num_self_intersecting_sheets(const HexStc& stc) {
  return static_cast<std::size_t>(std::count_if(
      stc.sheets.begin(), stc.sheets.end(), [](const Sheet& s) { return s.self_intersecting; }));
}

}  // namespace stcweave::stc
