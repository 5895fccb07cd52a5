#include "stcweave/stc/validate.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <numeric>
#include <sstream>

#include "stcweave/stc/bucket_sort.hpp"
#include "stcweave/stc/errors.hpp"
#include "union_find.hpp"

/// How the complex is validated, and why it is linear-ish.
///
/// Faces and edges are matched once by sorting their node keys (deterministic, no hash
/// order). The face match gives, for every hex face, the hex face on its other side, which
/// is all the edge-fan walk needs: around an edge, leave a hex through the other face of
/// that hex containing the edge, and count the hexes met before coming back (interior
/// edge) or before reaching the second boundary face (boundary edge); the fan is right iff
/// every hex at the edge is met. Vertex links: the link of a node is the triangulated
/// surface with one vertex per edge at the node, one edge per face, one triangle per hex;
/// a union-find over hex corners glued through shared faces gives its components, and its
/// Euler characteristic is #edges − #faces + #hexes at the node. Once the edge fans are
/// right the link is a surface, so "one component and χ = 2 (interior) or 1 (boundary)"
/// means a sphere or a disk.

namespace stcweave::stc {
namespace {

/// kEdgeFaces[k]: the two faces of a hex containing its local edge k.
constexpr std::array<std::array<int, 2>, 12> make_edge_faces() {
  std::array<std::array<int, 2>, 12> t{};
  std::array<int, 12> n{};
  for (int f = 0; f < 6; ++f) {
    for (int s = 0; s < 4; ++s) {
      const auto& face = kHexFaces[static_cast<std::size_t>(f)];
      const int k =
          kHexLocalEdge[static_cast<std::size_t>(face[static_cast<std::size_t>(s)])]
                       [static_cast<std::size_t>(face[static_cast<std::size_t>((s + 1) % 4)])];
      t[static_cast<std::size_t>(k)][static_cast<std::size_t>(n[static_cast<std::size_t>(k)]++)] =
          f;
    }
  }
  return t;
}
constexpr auto kEdgeFaces = make_edge_faces();

/// kFaceEdges[f]: the four local edges of face f.
constexpr std::array<std::array<int, 4>, 6> make_face_edges() {
  std::array<std::array<int, 4>, 6> t{};
  for (std::size_t f = 0; f < 6; ++f) {
    for (std::size_t s = 0; s < 4; ++s)
      t[f][s] = kHexLocalEdge[static_cast<std::size_t>(kHexFaces[f][s])]
                             [static_cast<std::size_t>(kHexFaces[f][(s + 1) % 4])];
  }
  return t;
}
constexpr auto kFaceEdges = make_face_edges();

using detail::UnionFind;

/// `b` is a rotation of `a`.
bool same_cycle(const Quad& a, const Quad& b) {
  for (std::size_t r = 0; r < 4; ++r) {
    if (b[r] != a[0]) continue;
    for (std::size_t i = 1; i < 4; ++i)
      if (b[(r + i) % 4] != a[i]) return false;
    return true;
  }
  return false;
}

using FaceKey = std::array<std::int32_t, 4>;

FaceKey face_key(const Quad& q) {
  FaceKey k{q[0].value(), q[1].value(), q[2].value(), q[3].value()};
  std::sort(k.begin(), k.end());
  return k;
}

/// Collects the offending elements of one invariant.
class Collector {
 public:
  explicit Collector(Invariant invariant) { violation_.invariant = invariant; }
  void add(const std::string& example) {
    if (violation_.examples.size() < Violation::kMaxExamples)
      violation_.examples.push_back(example);
    ++violation_.count;
  }
  void flush(ValidationReport& report) {
    if (violation_.count == 0) return;
    report.valid = false;
    report.violations.push_back(std::move(violation_));
  }

 private:
  Violation violation_;
};

/// Whether a node of `hex` is invalid or not below `num_nodes` (`NodeOutOfRange`).
bool node_out_of_range(const Hex& hex, std::size_t num_nodes) {
  return std::any_of(hex.begin(), hex.end(),
                     [&](NodeId v) { return !v.is_valid() || v.index() >= num_nodes; });
}

/// Whether `hex` holds a node twice (`RepeatedNode`).
bool repeated_node(const Hex& hex) {
  for (std::size_t i = 0; i < 8; ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (hex[i] == hex[j]) return true;
  return false;
}

/// The corner masks (bit i: corner i) of the six faces of a hex.
constexpr std::array<std::uint8_t, 6> make_face_masks() {
  std::array<std::uint8_t, 6> t{};
  for (std::size_t f = 0; f < 6; ++f) {
    int all = 0;
    for (const int c : kHexFaces[f]) all |= 1 << c;
    t[f] = static_cast<std::uint8_t>(all);
  }
  return t;
}
constexpr auto kFaceMasks = make_face_masks();

bool is_face_mask(unsigned mask) {
  return std::find(kFaceMasks.begin(), kFaceMasks.end(), mask) != kFaceMasks.end();
}

/// Every pair of well-formed hexes sharing four or more nodes that are not exactly a face of
/// both: a face and one more node, two opposite edges (a diagonal section), a face of one
/// that is a section of the other, two hexes on the same 8 nodes. Some hex of such a complex
/// has a negative Jacobian somewhere, whatever the positions (validate.hpp). Fewer shared
/// nodes are not refused here. Reported as `h3+h8:n1,n4,n5,n9,n12`, the pair then the shared nodes
/// in increasing order.
///
/// Each pair is met once, from its smaller hex: a CSR of the hex corners at each node
/// (hexes in increasing order), and per hex the masks of the corners it shares with each
/// larger hex, on both sides. Time: linear in the sum over hexes of the hexes at their
/// nodes.
void find_shared_nodes_not_a_face(const HexComplex& complex, const std::vector<bool>& good,
                                  Collector& collector) {
  const std::size_t num_hexes = complex.hexes.size();
  const std::size_t num_nodes = complex.num_nodes;
  std::vector<std::uint32_t> node_begin(num_nodes + 1, 0);
  for (std::size_t h = 0; h < num_hexes; ++h) {
    if (!good[h]) continue;
    for (const NodeId v : complex.hexes[h]) ++node_begin[v.index() + 1];
  }
  for (std::size_t v = 0; v < num_nodes; ++v) node_begin[v + 1] += node_begin[v];
  std::vector<std::uint32_t> corners(node_begin[num_nodes]);
  {
    std::vector<std::uint32_t> fill(node_begin.begin(), node_begin.end() - 1);
    for (std::size_t h = 0; h < num_hexes; ++h) {
      if (!good[h]) continue;
      for (std::size_t i = 0; i < 8; ++i)
        corners[fill[complex.hexes[h][i].index()]++] = static_cast<std::uint32_t>(8 * h + i);
    }
  }
  // masks[g]: the corners of h (low byte) and of g (high byte) at the nodes h and g share.
  std::vector<std::uint16_t> masks(num_hexes, 0);
  std::vector<std::uint32_t> met;  // the larger hexes sharing a node with h
  std::vector<std::pair<std::uint32_t, std::uint16_t>> bad;  // those sharing 4+ off a face
  for (std::size_t h = 0; h < num_hexes; ++h) {
    if (!good[h]) continue;
    const Hex& hex = complex.hexes[h];
    for (std::size_t i = 0; i < 8; ++i) {
      const std::size_t v = hex[i].index();
      // The larger hexes at v, from the end of its list.
      for (std::uint32_t k = node_begin[v + 1]; k > node_begin[v]; --k) {
        const std::uint32_t c = corners[k - 1];
        const std::uint32_t g = c / 8;
        if (g <= h) break;
        if (masks[g] == 0) met.push_back(g);
        masks[g] = static_cast<std::uint16_t>(masks[g] | (1U << i) | (256U << (c % 8)));
      }
    }
    for (const std::uint32_t g : met) {
      const std::uint16_t m = masks[g];
      masks[g] = 0;
      const unsigned mine = m & 0xffU;
      const auto shared = std::popcount(mine);
      if (shared < 4 || (shared == 4 && is_face_mask(mine) && is_face_mask(m >> 8U))) continue;
      bad.emplace_back(g, m);
    }
    std::sort(bad.begin(), bad.end());  // reported in the order of the pairs
    for (const auto& [g, m] : bad) {
      std::vector<std::int32_t> shared;
      for (std::size_t i = 0; i < 8; ++i)
        if ((m >> i) & 1U) shared.push_back(hex[i].value());
      std::sort(shared.begin(), shared.end());
      std::string example = HexId(h).str() + "+" + HexId(std::size_t{g}).str() + ":";
      for (std::size_t i = 0; i < shared.size(); ++i) {
        if (i > 0) example += ',';
        example += NodeId(shared[i]).str();
      }
      collector.add(example);
    }
    met.clear();
    bad.clear();
  }
}

std::string face_slot_str(std::size_t slot) {
  return HexId(slot / 6).str() + ".f" + std::to_string(slot % 6);
}

}  // namespace

Violation shared_nodes_not_a_face(const HexComplex& complex) {
  std::vector<bool> good(complex.hexes.size());
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    const Hex& hex = complex.hexes[h];
    good[h] = !node_out_of_range(hex, complex.num_nodes) && !repeated_node(hex);
  }
  Collector collector(Invariant::SharedNodesNotAFace);
  find_shared_nodes_not_a_face(complex, good, collector);
  ValidationReport report;
  collector.flush(report);
  if (report.violations.empty()) return Violation{Invariant::SharedNodesNotAFace, 0, {}};
  return std::move(report.violations.front());
}

std::string_view invariant_name(Invariant invariant) {
  switch (invariant) {
    case Invariant::NodeOutOfRange:
      return "node_out_of_range";
    case Invariant::RepeatedNode:
      return "repeated_node";
    case Invariant::FaceInThreeHexes:
      return "face_in_three_hexes";
    case Invariant::HexesShareTwoFaces:
      return "hexes_share_two_faces";
    case Invariant::SharedNodesNotAFace:
      return "shared_nodes_not_a_face";
    case Invariant::FaceOrientation:
      return "face_orientation";
    case Invariant::InteriorEdgeCycle:
      return "interior_edge_cycle";
    case Invariant::BoundaryEdgeFan:
      return "boundary_edge_fan";
    case Invariant::VertexLink:
      return "vertex_link";
    case Invariant::MissingBoundaryQuad:
      return "missing_boundary_quad";
    case Invariant::ExtraBoundaryQuad:
      return "extra_boundary_quad";
    case Invariant::ReversedBoundaryQuad:
      return "reversed_boundary_quad";
    case Invariant::PinchedFacePair:
      return "pinched_face_pair";
    case Invariant::EulerCharacteristic:
      return "euler_characteristic";
  }
  return "unknown_invariant";
}

const Violation* ValidationReport::find(Invariant invariant) const {
  for (const Violation& v : violations)
    if (v.invariant == invariant) return &v;
  return nullptr;
}

std::string ValidationReport::summary() const {
  std::ostringstream out;
  if (valid) {
    out << "valid hex complex: " << hexes << " hexes, " << nodes << " nodes, " << edges
        << " edges, " << faces << " faces (" << boundary_faces
        << " on the boundary), chi(volume)=" << euler_volume << " chi(boundary)=" << euler_boundary
        << (boundary_compared ? ", boundary as expected" : "");
    return out.str();
  }
  out << "invalid hex complex (" << hexes << " hexes): " << violations.size()
      << " invariant(s) violated";
  for (const Violation& v : violations) {
    out << "\n  " << v.name() << ": " << v.count << " (";
    for (std::size_t i = 0; i < v.examples.size(); ++i) out << (i ? " " : "") << v.examples[i];
    if (v.count > v.examples.size()) out << " ...";
    out << ")";
  }
  return out.str();
}

std::vector<PinchedFaces> pinched_faces(const HexComplex& complex) {
  // Distinct faces (sorted node quadruples), each with its cycle.
  struct Face {
    std::array<std::int32_t, 4> key;
    std::array<std::int32_t, 4> cycle;
  };
  std::vector<Face> faces;
  faces.reserve(complex.hexes.size() * 6);
  for (const Hex& h : complex.hexes) {
    for (int f = 0; f < 6; ++f) {
      const Quad q = hex_face(h, f);
      Face face{};
      for (std::size_t i = 0; i < 4; ++i) face.cycle[i] = q[i].value();
      face.key = face.cycle;
      std::sort(face.key.begin(), face.key.end());
      faces.push_back(face);
    }
  }
  // By key, then by cycle: of the two uses of an inner face, the one kept is well defined.
  sort_by_smallest_node(
      faces, [](const Face& f) { return f.key[0]; },
      [](const Face& a, const Face& b) {
        return a.key != b.key ? a.key < b.key : a.cycle < b.cycle;
      });
  faces.erase(std::unique(faces.begin(), faces.end(),
                          [](const Face& a, const Face& b) { return a.key == b.key; }),
              faces.end());
  // Per face corner: (node, smaller neighbour, larger neighbour, face).
  std::vector<std::array<std::int32_t, 4>> corners;
  corners.reserve(faces.size() * 4);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& c = faces[f].cycle;
    for (std::size_t i = 0; i < 4; ++i) {
      const std::int32_t a = c[(i + 1) % 4];
      const std::int32_t b = c[(i + 3) % 4];
      corners.push_back({c[i], std::min(a, b), std::max(a, b), static_cast<std::int32_t>(f)});
    }
  }
  sort_by_smallest_node(corners, [](const auto& c) { return c[0]; });
  std::vector<PinchedFaces> out;
  for (std::size_t i = 0; i + 1 < corners.size(); ++i) {
    const auto& x = corners[i];
    const auto& y = corners[i + 1];
    if (x[0] != y[0] || x[1] != y[1] || x[2] != y[2]) continue;
    PinchedFaces p;
    p.node = NodeId(x[0]);
    p.a = NodeId(x[1]);
    p.b = NodeId(x[2]);
    p.first = faces[static_cast<std::size_t>(x[3])].cycle;
    p.second = faces[static_cast<std::size_t>(y[3])].cycle;
    out.push_back(p);
  }
  return out;
}

ValidationReport validate_hex_complex(const HexComplex& complex,
                                      const QuadSurface* expected_boundary,
                                      bool check_pinched_faces, bool check_shared_nodes) {
  ValidationReport report;
  const std::size_t num_hexes = complex.hexes.size();
  const std::size_t num_nodes = complex.num_nodes;
  report.hexes = num_hexes;

  // 1. Nodes.
  std::vector<bool> good(num_hexes, true);
  {
    Collector out_of_range(Invariant::NodeOutOfRange);
    Collector repeated(Invariant::RepeatedNode);
    for (std::size_t h = 0; h < num_hexes; ++h) {
      const Hex& hex = complex.hexes[h];
      const bool bad_range = node_out_of_range(hex, num_nodes);
      const bool bad_repeat = repeated_node(hex);
      if (bad_range) out_of_range.add(HexId(h).str());
      if (bad_repeat) repeated.add(HexId(h).str());
      good[h] = !bad_range && !bad_repeat;
    }
    out_of_range.flush(report);
    repeated.flush(report);
  }

  // 2. Faces, matched by sorted node keys: CSR of slots (6h+f) per face.
  constexpr std::uint32_t kNone = ~std::uint32_t{0};
  std::vector<std::uint32_t> face_of_slot(6 * num_hexes, kNone);
  std::vector<FaceKey> face_keys;
  std::vector<std::uint32_t> face_begin;
  std::vector<std::uint32_t> face_slots;
  {
    std::vector<std::pair<FaceKey, std::uint32_t>> entries;
    entries.reserve(6 * num_hexes);
    for (std::size_t h = 0; h < num_hexes; ++h) {
      if (good[h]) {
        for (int f = 0; f < 6; ++f)
          entries.emplace_back(face_key(hex_face(complex.hexes[h], f)),
                               static_cast<std::uint32_t>(6 * h + static_cast<std::size_t>(f)));
      }
    }
    sort_by_smallest_node(entries, [](const auto& e) { return e.first[0]; });
    face_slots.reserve(entries.size());
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (i == 0 || entries[i].first != entries[i - 1].first) {
        face_keys.push_back(entries[i].first);
        face_begin.push_back(static_cast<std::uint32_t>(i));
      }
      face_slots.push_back(entries[i].second);
      face_of_slot[entries[i].second] = static_cast<std::uint32_t>(face_keys.size() - 1);
    }
    face_begin.push_back(static_cast<std::uint32_t>(entries.size()));
  }
  const std::size_t num_faces = face_keys.size();
  const auto face_count = [&](std::uint32_t f) { return face_begin[f + 1] - face_begin[f]; };
  const auto slot_count = [&](std::size_t slot) { return face_count(face_of_slot[slot]); };
  const auto neighbour = [&](std::size_t slot) -> std::size_t {
    const std::uint32_t f = face_of_slot[slot];
    const std::uint32_t a = face_slots[face_begin[f]];
    return a == slot ? face_slots[face_begin[f] + 1] : a;
  };
  report.faces = num_faces;

  {
    Collector three(Invariant::FaceInThreeHexes);
    Collector orientation(Invariant::FaceOrientation);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::uint32_t f = 0; f < num_faces; ++f) {
      const std::uint32_t n = face_count(f);
      if (n == 1) ++report.boundary_faces;
      if (n > 2) {
        std::string example;
        for (std::uint32_t i = face_begin[f]; i < face_begin[f + 1]; ++i) {
          if (i > face_begin[f]) example += '+';
          example += HexId(std::size_t{face_slots[i] / 6}).str();
        }
        three.add(example);
      }
      if (n != 2) continue;
      const std::uint32_t s1 = face_slots[face_begin[f]];
      const std::uint32_t s2 = face_slots[face_begin[f] + 1];
      pairs.emplace_back(s1 / 6, s2 / 6);
      const Quad q1 = hex_face(complex.hexes[s1 / 6], static_cast<int>(s1 % 6));
      const Quad q2 = hex_face(complex.hexes[s2 / 6], static_cast<int>(s2 % 6));
      if (!same_cycle(q1, reversed(q2)))
        orientation.add(face_slot_str(s1) + "+" + face_slot_str(s2));
    }
    three.flush(report);
    std::sort(pairs.begin(), pairs.end());
    Collector share(Invariant::HexesShareTwoFaces);
    for (std::size_t i = 1; i < pairs.size(); ++i) {
      if (pairs[i] == pairs[i - 1] && (i < 2 || pairs[i - 2] != pairs[i]))
        share.add(HexId(std::size_t{pairs[i].first}).str() + "+" +
                  HexId(std::size_t{pairs[i].second}).str());
    }
    share.flush(report);
    if (check_shared_nodes) {
      Collector shared_nodes(Invariant::SharedNodesNotAFace);
      find_shared_nodes_not_a_face(complex, good, shared_nodes);
      shared_nodes.flush(report);
    }
    orientation.flush(report);
  }

  // 3. Edges, matched by sorted node pairs: CSR of slots (12h+k) per edge.
  std::vector<std::uint32_t> edge_of_slot(12 * num_hexes, kNone);
  std::vector<std::uint32_t> edge_begin;
  std::vector<std::uint32_t> edge_slots;
  std::vector<std::uint64_t> edge_keys;
  {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
    entries.reserve(12 * num_hexes);
    for (std::size_t h = 0; h < num_hexes; ++h) {
      if (!good[h]) continue;
      for (std::size_t k = 0; k < 12; ++k) {
        auto u = static_cast<std::uint64_t>(
            complex.hexes[h][static_cast<std::size_t>(kHexEdges[k][0])].value());
        auto v = static_cast<std::uint64_t>(
            complex.hexes[h][static_cast<std::size_t>(kHexEdges[k][1])].value());
        if (u > v) std::swap(u, v);
        entries.emplace_back((u << 32) | v, static_cast<std::uint32_t>(12 * h + k));
      }
    }
    sort_by_smallest_node(entries, [](const auto& e) { return e.first >> 32; });
    edge_slots.reserve(entries.size());
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (i == 0 || entries[i].first != entries[i - 1].first) {
        edge_keys.push_back(entries[i].first);
        edge_begin.push_back(static_cast<std::uint32_t>(i));
      }
      edge_slots.push_back(entries[i].second);
      edge_of_slot[entries[i].second] = static_cast<std::uint32_t>(edge_keys.size() - 1);
    }
    edge_begin.push_back(static_cast<std::uint32_t>(entries.size()));
  }
  const std::size_t num_edges = edge_keys.size();
  report.edges = num_edges;
  const auto edge_str = [&](std::size_t e) {
    return NodeId(static_cast<std::int32_t>(edge_keys[e] >> 32)).str() + "-" +
           NodeId(static_cast<std::int32_t>(edge_keys[e] & 0xffffffffU)).str();
  };

  // 4. Edge cycles and fans.
  std::vector<bool> edge_on_boundary(num_edges, false);
  {
    Collector cycle(Invariant::InteriorEdgeCycle);
    Collector fan(Invariant::BoundaryEdgeFan);
    const auto local_edge_of = [&](std::size_t h, std::uint32_t e) -> std::size_t {
      for (std::size_t k = 0; k < 12; ++k)
        if (edge_of_slot[12 * h + k] == e) return k;
      throw InternalError("validate: edge not found in its hex");
    };
    for (std::uint32_t e = 0; e < num_edges; ++e) {
      const std::uint32_t n = edge_begin[e + 1] - edge_begin[e];
      std::uint32_t boundary = 0;
      std::uint32_t nonmanifold = 0;
      std::size_t start_slot = 0;
      int start_face = -1;
      for (std::uint32_t i = edge_begin[e]; i < edge_begin[e + 1]; ++i) {
        const std::size_t h = edge_slots[i] / 12;
        const std::size_t k = edge_slots[i] % 12;
        for (int f : kEdgeFaces[k]) {
          const std::uint32_t c = slot_count(6 * h + static_cast<std::size_t>(f));
          if (c == 1) {
            ++boundary;
            if (start_face < 0) {
              start_slot = edge_slots[i];
              start_face = f;
            }
          }
          if (c > 2) ++nonmanifold;
        }
      }
      if (boundary > 0) edge_on_boundary[e] = true;
      bool ok = nonmanifold == 0 && (boundary == 0 || boundary == 2);
      if (ok) {
        // Walk around the edge through shared faces.
        std::size_t h = (boundary == 0 ? edge_slots[edge_begin[e]] : start_slot) / 12;
        std::size_t k = (boundary == 0 ? edge_slots[edge_begin[e]] : start_slot) % 12;
        const std::size_t h0 = h;
        int in_face = boundary == 0 ? kEdgeFaces[k][1] : start_face;
        std::uint32_t visited = 0;
        ok = false;
        while (visited <= n) {
          ++visited;
          const int out_face = kEdgeFaces[k][0] == in_face ? kEdgeFaces[k][1] : kEdgeFaces[k][0];
          const std::size_t out_slot = 6 * h + static_cast<std::size_t>(out_face);
          if (slot_count(out_slot) == 1) {
            ok = boundary == 2 && visited == n;
            break;
          }
          const std::size_t next = neighbour(out_slot);
          h = next / 6;
          in_face = static_cast<int>(next % 6);
          k = local_edge_of(h, e);
          if (h == h0) {
            ok = boundary == 0 && visited == n;
            break;
          }
        }
      }
      if (!ok) (boundary == 0 && nonmanifold == 0 ? cycle : fan).add(edge_str(e));
    }
    cycle.flush(report);
    fan.flush(report);
  }

  // 5. Vertex links.
  {
    UnionFind corners(8 * num_hexes);
    for (std::uint32_t f = 0; f < num_faces; ++f) {
      if (face_count(f) != 2) continue;
      const std::uint32_t s1 = face_slots[face_begin[f]];
      const std::uint32_t s2 = face_slots[face_begin[f] + 1];
      const std::size_t h1 = s1 / 6;
      const std::size_t h2 = s2 / 6;
      for (int i : kHexFaces[s1 % 6]) {
        const NodeId v = complex.hexes[h1][static_cast<std::size_t>(i)];
        for (std::size_t j = 0; j < 8; ++j) {
          if (complex.hexes[h2][j] == v)
            corners.unite(static_cast<std::uint32_t>(8 * h1 + static_cast<std::size_t>(i)),
                          static_cast<std::uint32_t>(8 * h2 + j));
        }
      }
    }
    std::vector<std::int64_t> chi(num_nodes, 0);
    std::vector<std::uint32_t> components(num_nodes, 0);
    std::vector<bool> used(num_nodes, false);
    std::vector<bool> on_boundary(num_nodes, false);
    for (std::size_t h = 0; h < num_hexes; ++h) {
      if (!good[h]) continue;
      for (std::size_t i = 0; i < 8; ++i) {
        const std::size_t v = complex.hexes[h][i].index();
        used[v] = true;
        chi[v] += 1;  // a triangle of the link
        if (corners.find(static_cast<std::uint32_t>(8 * h + i)) == 8 * h + i) ++components[v];
      }
    }
    for (std::uint32_t e = 0; e < num_edges; ++e) {
      chi[edge_keys[e] >> 32] += 1;  // a vertex of the link
      chi[edge_keys[e] & 0xffffffffU] += 1;
    }
    for (std::uint32_t f = 0; f < num_faces; ++f) {
      for (std::int32_t v : face_keys[f]) {
        chi[static_cast<std::size_t>(v)] -= 1;  // an edge of the link
        if (face_count(f) == 1) on_boundary[static_cast<std::size_t>(v)] = true;
      }
    }
    Collector link(Invariant::VertexLink);
    for (std::size_t v = 0; v < num_nodes; ++v) {
      if (!used[v]) continue;
      ++report.nodes;
      if (components[v] != 1 || chi[v] != (on_boundary[v] ? 1 : 2)) link.add(NodeId(v).str());
    }
    link.flush(report);

    // χ of the volume and of the boundary (faces used once).
    std::int64_t boundary_nodes = 0;
    for (std::size_t v = 0; v < num_nodes; ++v) boundary_nodes += on_boundary[v] ? 1 : 0;
    std::int64_t boundary_edges = 0;
    for (std::uint32_t e = 0; e < num_edges; ++e) boundary_edges += edge_on_boundary[e] ? 1 : 0;
    std::int64_t good_hexes = 0;
    for (std::size_t h = 0; h < num_hexes; ++h) good_hexes += good[h] ? 1 : 0;
    report.euler_volume = static_cast<std::int64_t>(report.nodes) -
                          static_cast<std::int64_t>(num_edges) +
                          static_cast<std::int64_t>(num_faces) - good_hexes;
    report.euler_boundary =
        boundary_nodes - boundary_edges + static_cast<std::int64_t>(report.boundary_faces);
  }

  // 6. The boundary against the expected quads.
  if (expected_boundary != nullptr) {
    report.boundary_compared = true;
    Collector missing(Invariant::MissingBoundaryQuad);
    Collector extra(Invariant::ExtraBoundaryQuad);
    Collector reversed_quads(Invariant::ReversedBoundaryQuad);
    std::vector<bool> matched(num_faces, false);
    for (std::size_t i = 0; i < expected_boundary->quads.size(); ++i) {
      const Quad& q = expected_boundary->quads[i];
      const FaceKey key = face_key(q);
      const auto it = std::lower_bound(face_keys.begin(), face_keys.end(), key);
      const auto f = static_cast<std::uint32_t>(it - face_keys.begin());
      if (it == face_keys.end() || *it != key || face_count(f) != 1 || matched[f]) {
        missing.add(QuadId(i).str());
        continue;
      }
      matched[f] = true;
      const std::uint32_t slot = face_slots[face_begin[f]];
      const Quad actual = hex_face(complex.hexes[slot / 6], static_cast<int>(slot % 6));
      if (!same_cycle(q, actual)) reversed_quads.add(QuadId(i).str());
    }
    for (std::uint32_t f = 0; f < num_faces; ++f)
      if (face_count(f) == 1 && !matched[f]) extra.add(face_slot_str(face_slots[face_begin[f]]));
    missing.flush(report);
    extra.flush(report);
    reversed_quads.flush(report);
  }

  // 7. Euler characteristic.
  if (report.euler_boundary % 2 != 0 || 2 * report.euler_volume != report.euler_boundary) {
    Collector euler(Invariant::EulerCharacteristic);
    euler.add("chi(volume)=" + std::to_string(report.euler_volume) +
              " chi(boundary)=" + std::to_string(report.euler_boundary));
    euler.flush(report);
  }

  // 8. Pinched face pairs (`pinched_faces`), over the hexes step 1 kept, reported as n-a-b:
  // the node and the two shared neighbours.
  if (check_pinched_faces) {
    Collector pinched(Invariant::PinchedFacePair);
    HexComplex kept;
    const bool all_good = std::find(good.begin(), good.end(), false) == good.end();
    if (!all_good) {
      kept.num_nodes = complex.num_nodes;
      for (std::size_t h = 0; h < num_hexes; ++h)
        if (good[h]) kept.hexes.push_back(complex.hexes[h]);
    }
    for (const PinchedFaces& p : pinched_faces(all_good ? complex : kept))
      pinched.add(p.node.str() + "-" + p.a.str() + "-" + p.b.str());
    pinched.flush(report);
  }
  return report;
}

void require_valid(const ValidationReport& report) {
  if (report.valid) return;
  const Violation& v = report.violations.front();
  std::string message = "invalid hex complex: " + std::string(v.name()) + " violated by " +
                        std::to_string(v.count) + " element(s)";
  if (!v.examples.empty()) message += ", first " + v.examples.front();
  if (report.violations.size() > 1)
    message += " (and " + std::to_string(report.violations.size() - 1) + " more invariant(s))";
  throw InternalError(message);
}

}  // namespace stcweave::stc
