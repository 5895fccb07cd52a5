#include "support/compare.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <set>
#include <vector>

namespace stcweave::test {
namespace {

using FaceKey = std::array<NodeId, 4>;

FaceKey key_of(stc::Quad q) {
  std::sort(q.begin(), q.end());
  return q;
}

/// The faces of a hex mesh with the hexes holding them, and its boundary.
struct Faces {
  std::map<FaceKey, std::vector<std::size_t>> hexes_of;
  std::vector<std::size_t> used_nodes;  ///< nodes of at least one hex
  std::vector<NodeId> boundary_nodes;

  explicit Faces(const primal::HexMesh& m) {
    std::vector<bool> used(m.complex.num_nodes, false);
    for (std::size_t h = 0; h < m.complex.hexes.size(); ++h) {
      for (int f = 0; f < 6; ++f)
        hexes_of[key_of(stc::hex_face(m.complex.hexes[h], f))].push_back(h);
      for (NodeId n : m.complex.hexes[h]) used[n.index()] = true;
    }
    for (std::size_t n = 0; n < used.size(); ++n)
      if (used[n]) used_nodes.push_back(n);
    std::set<NodeId> boundary;
    for (const auto& [key, hexes] : hexes_of)
      if (hexes.size() == 1) boundary.insert(key.begin(), key.end());
    boundary_nodes.assign(boundary.begin(), boundary.end());
  }
};

/// The node joined to `n` by an edge of `hex` and not in `face`.
NodeId across(const stc::Hex& hex, NodeId n, const FaceKey& face) {
  const auto local = static_cast<int>(std::find(hex.begin(), hex.end(), n) - hex.begin());
  for (const auto& e : stc::kHexEdges) {
    const int other = e[0] == local ? e[1] : (e[1] == local ? e[0] : -1);
    if (other < 0) continue;
    const NodeId m = hex[static_cast<std::size_t>(other)];
    if (!std::binary_search(face.begin(), face.end(), m)) return m;
  }
  return NodeId::invalid();
}

class Matcher {
 public:
  Matcher(const primal::HexMesh& ours, const primal::HexMesh& reference)
      : ours_(ours), ref_(reference), our_faces_(ours), ref_faces_(reference) {
    node_to_ref_.assign(ours.complex.num_nodes, NodeId::invalid());
    node_to_ours_.assign(reference.complex.num_nodes, NodeId::invalid());
    hex_to_ref_.assign(ours.complex.hexes.size(), kNone);
    hex_to_ours_.assign(reference.complex.hexes.size(), kNone);
  }

  std::string run() {
    if (ours_.complex.hexes.size() != ref_.complex.hexes.size())
      return "hex counts differ: " + std::to_string(ours_.complex.hexes.size()) + " vs " +
             std::to_string(ref_.complex.hexes.size());
    if (our_faces_.used_nodes.size() != ref_faces_.used_nodes.size())
      return "node counts differ: " + std::to_string(our_faces_.used_nodes.size()) + " vs " +
             std::to_string(ref_faces_.used_nodes.size());
    if (std::string why = match_boundary(); !why.empty()) return why;
    std::deque<std::pair<std::size_t, FaceKey>> queue;  // (our hex, a face already matched)
    for (const auto& [key, hexes] : our_faces_.hexes_of) {
      if (hexes.size() != 1) continue;
      const FaceKey mapped = map_face(key);
      const auto it = ref_faces_.hexes_of.find(mapped);
      if (it == ref_faces_.hexes_of.end() || it->second.size() != 1)
        return "boundary quad " + str(key) + " is not a boundary quad of the reference";
      if (std::string why = pair(hexes.front(), it->second.front(), key, &queue); !why.empty())
        return why;
    }
    while (!queue.empty()) {
      const auto [h, face] = queue.front();
      queue.pop_front();
      if (std::string why = expand(h, face, &queue); !why.empty()) return why;
    }
    for (std::size_t h = 0; h < hex_to_ref_.size(); ++h)
      if (hex_to_ref_[h] == kNone) return "hex " + std::to_string(h) + " was never reached";
    return {};
  }

 private:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  static std::string str(const FaceKey& k) {
    std::string s = "(";
    for (NodeId n : k) s += (s.size() > 1 ? " " : "") + n.str();
    return s + ")";
  }

  std::string match_boundary() {
    const auto& a = our_faces_.boundary_nodes;
    const auto& b = ref_faces_.boundary_nodes;
    if (a.size() != b.size())
      return "boundary node counts differ: " + std::to_string(a.size()) + " vs " +
             std::to_string(b.size());
    if (a.empty()) return {};
    Eigen::RowVector3d lo = ref_.points.row(b.front().value()), hi = lo;
    for (NodeId n : b) {
      lo = lo.cwiseMin(ref_.points.row(n.value()));
      hi = hi.cwiseMax(ref_.points.row(n.value()));
    }
    const double tolerance = 1e-9 * std::max(1.0, (hi - lo).norm());
    for (NodeId n : a) {
      const Eigen::RowVector3d p = ours_.points.row(n.value());
      NodeId found = NodeId::invalid();
      for (NodeId m : b)
        if ((ref_.points.row(m.value()) - p).norm() <= tolerance) {
          if (found.is_valid()) return "two reference nodes at the place of " + n.str();
          found = m;
        }
      if (!found.is_valid()) return "boundary node " + n.str() + " has no reference node";
      if (std::string why = bind(n, found); !why.empty()) return why;
    }
    return {};
  }

  std::string bind(NodeId n, NodeId m) {
    if (node_to_ref_[n.index()].is_valid() && node_to_ref_[n.index()] != m)
      return n.str() + " matched to both " + node_to_ref_[n.index()].str() + " and " + m.str();
    if (node_to_ours_[m.index()].is_valid() && node_to_ours_[m.index()] != n)
      return "reference " + m.str() + " matched to both " + node_to_ours_[m.index()].str() +
             " and " + n.str();
    node_to_ref_[n.index()] = m;
    node_to_ours_[m.index()] = n;
    return {};
  }

  FaceKey map_face(const FaceKey& k) const {
    FaceKey out{};
    for (std::size_t i = 0; i < 4; ++i) out[i] = node_to_ref_[k[i].index()];
    return key_of(out);
  }

  /// Pairs our hex h with reference hex g, or checks an earlier pairing; new pairs are queued.
  std::string pair(std::size_t h, std::size_t g, const FaceKey& face,
                   std::deque<std::pair<std::size_t, FaceKey>>* queue) {
    if (hex_to_ref_[h] == g && hex_to_ours_[g] == h) return {};
    if (hex_to_ref_[h] != kNone || hex_to_ours_[g] != kNone)
      return "hex " + std::to_string(h) + " and reference hex " + std::to_string(g) +
             " are each matched elsewhere";
    hex_to_ref_[h] = g;
    hex_to_ours_[g] = h;
    queue->emplace_back(h, face);
    return {};
  }

  /// Our hex h, matched through `face`: match its other four nodes, check its six faces,
  /// then pair the hexes behind them.
  std::string expand(std::size_t h, const FaceKey& face,
                     std::deque<std::pair<std::size_t, FaceKey>>* queue) {
    const std::size_t g = hex_to_ref_[h];
    const stc::Hex& ours = ours_.complex.hexes[h];
    const stc::Hex& ref = ref_.complex.hexes[g];
    const FaceKey ref_face = map_face(face);
    for (NodeId n : face) {
      const NodeId a = across(ours, n, face);
      const NodeId b = across(ref, node_to_ref_[n.index()], ref_face);
      if (!a.is_valid() || !b.is_valid())
        return "hex " + std::to_string(h) + " does not match reference hex " + std::to_string(g);
      if (std::string why = bind(a, b); !why.empty()) return why;
    }
    std::set<FaceKey> ref_keys;
    for (int f = 0; f < 6; ++f) ref_keys.insert(key_of(stc::hex_face(ref, f)));
    for (int f = 0; f < 6; ++f) {
      const FaceKey key = key_of(stc::hex_face(ours, f));
      const FaceKey mapped = map_face(key);
      if (ref_keys.count(mapped) == 0)
        return "hex " + std::to_string(h) + " face " + str(key) + " maps to " + str(mapped) +
               ", not a face of reference hex " + std::to_string(g);
      const auto& ours_behind = our_faces_.hexes_of.at(key);
      const auto& ref_behind = ref_faces_.hexes_of.at(mapped);
      if (ours_behind.size() != ref_behind.size())
        return "face " + str(key) + " is in " + std::to_string(ours_behind.size()) +
               " hexes, its match in " + std::to_string(ref_behind.size());
      if (ours_behind.size() != 2) continue;
      const std::size_t h2 = ours_behind[0] == h ? ours_behind[1] : ours_behind[0];
      const std::size_t g2 = ref_behind[0] == g ? ref_behind[1] : ref_behind[0];
      if (std::string why = pair(h2, g2, key, queue); !why.empty()) return why;
    }
    return {};
  }

  const primal::HexMesh& ours_;
  const primal::HexMesh& ref_;
  Faces our_faces_, ref_faces_;
  std::vector<NodeId> node_to_ref_, node_to_ours_;
  std::vector<std::size_t> hex_to_ref_, hex_to_ours_;
};

}  // namespace

bool same_connectivity(const primal::HexMesh& ours, const primal::HexMesh& reference,
                       std::string* why) {
  Matcher matcher(ours, reference);
  std::string difference = matcher.run();
  const bool same = difference.empty();
  if (why != nullptr) *why = std::move(difference);
  return same;
}

}  // namespace stcweave::test
