/// \file
/// Per-hex and per-node data of a hex mesh: quality, sheets, chords, layers and what the
/// weave recorded (see mesh_data.hpp for the meaning of every array).

#include "stcweave/primal/mesh_data.hpp"

#include <algorithm>
#include <deque>
#include <utility>

#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/bucket_sort.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {

namespace {

const DataArray* find_array(const std::vector<DataArray>& arrays, std::string_view name) {
  for (const DataArray& a : arrays)
    if (a.name == name) return &a;
  return nullptr;
}

DataArray int_array(std::string name, std::size_t size) {
  DataArray a;
  a.name = std::move(name);
  a.type = DataType::Int32;
  a.values.assign(size, 0.0);
  return a;
}

}  // namespace

const DataArray* MeshData::cell(std::string_view name) const {
  return find_array(cells, name);
}
const DataArray* MeshData::point(std::string_view name) const {
  return find_array(points, name);
}

int rule_code(std::string_view rule) {
  if (rule == "cross") return kRuleCross;
  if (rule == "cross-relaxed") return kRuleCrossRelaxed;
  if (rule == "blind-chord") return kRuleBlindChord;
  if (rule == "parallel-merge") return kRuleParallelMerge;
  if (rule == "pillow") return kRulePillow;
  if (rule == "tet-split") return kRuleTetSplit;
  return kRuleOther;
}

std::string_view rule_name(int code) {
  switch (code) {
    case kRuleCross:
      return "cross";
    case kRuleCrossRelaxed:
      return "cross-relaxed";
    case kRuleBlindChord:
      return "blind-chord";
    case kRuleParallelMerge:
      return "parallel-merge";
    case kRulePillow:
      return "pillow";
    case kRuleTetSplit:
      return "tet-split";
    default:
      return "other";
  }
}

const ShrinkRecord* WeaveHistory::shrink(std::int32_t index) const {
  const auto it =
      std::lower_bound(shrinks.begin(), shrinks.end(), index,
                       [](const ShrinkRecord& r, std::int32_t i) { return r.shrink < i; });
  return it != shrinks.end() && it->shrink == index ? &*it : nullptr;
}

void TraceDigest::add(const weave::TraceEvent& event) {
  using Kind = weave::TraceEvent::Kind;
  switch (event.kind) {
    case Kind::Selection: {
      ShrinkRecord r;
      r.shrink = event.shrink;
      r.decided_by = event.decided_by;
      if (event.chosen >= 0 && static_cast<std::size_t>(event.chosen) < event.candidates.size()) {
        const weave::TraceCandidate& c = event.candidates[static_cast<std::size_t>(event.chosen)];
        r.loop = c.loop;
        r.side = c.side;
        r.length = c.length;
        r.depth = c.depth;
      }
      weave::file_shrink_record(shrinks_, std::move(r));
      break;
    }
    case Kind::ShrinkFailed:
      weave::mark_shrink_failed(shrinks_, event.shrink);
      break;
    case Kind::Rule:
      if (event.hex.is_valid()) {
        if (hex_nodes_.size() <= event.hex.index())
          hex_nodes_.resize(event.hex.index() + 1, NodeId::invalid());
        hex_nodes_[event.hex.index()] = event.node;
      }
      break;
  }
}

WeaveHistory weave_history(const weave::WeaveResult& woven) {
  const std::size_t m = woven.complex.hexes.size();
  if (woven.hex_shrink.size() != m || woven.hex_rule.size() != m ||
      (!woven.hex_node.empty() && woven.hex_node.size() != m)) {
    throw InvalidInput("weave history: the weave result lists the shrink of " +
                       std::to_string(woven.hex_shrink.size()) + ", the rule of " +
                       std::to_string(woven.hex_rule.size()) + " and the node of " +
                       std::to_string(woven.hex_node.size()) + " hexes for " + std::to_string(m) +
                       " hexes; pass the WeaveResult the hexes came from");
  }
  WeaveHistory h;
  h.hex_shrink = woven.hex_shrink;
  h.hex_rule = woven.hex_rule;
  h.hex_node = woven.hex_node;
  h.hex_node.resize(m, NodeId::invalid());
  h.shrinks = woven.shrinks;
  return h;
}

void append_hexes(WeaveHistory& history, std::size_t hexes, const std::string& rule) {
  if (history.hex_shrink.size() > hexes) {
    throw InvalidInput("weave history: it covers " + std::to_string(history.hex_shrink.size()) +
                       " hexes, more than the " + std::to_string(hexes) +
                       " of the mesh; pass the history of the weave that made it");
  }
  history.hex_shrink.resize(hexes, -1);
  history.hex_rule.resize(hexes, rule);
  history.hex_node.resize(hexes, NodeId::invalid());
}

std::vector<std::array<std::int32_t, 6>> hex_face_neighbours(const stc::HexComplex& complex) {
  const std::size_t m = complex.hexes.size();
  struct FaceKey {
    std::array<std::int32_t, 4> nodes;
    std::int32_t hex;
    std::int32_t face;
  };
  std::vector<FaceKey> keys;
  keys.reserve(6 * m);
  for (std::size_t h = 0; h < m; ++h) {
    for (int f = 0; f < 6; ++f) {
      const stc::Quad q = stc::hex_face(complex.hexes[h], f);
      FaceKey k{{q[0].value(), q[1].value(), q[2].value(), q[3].value()},
                static_cast<std::int32_t>(h),
                f};
      std::sort(k.nodes.begin(), k.nodes.end());
      keys.push_back(k);
    }
  }
  stc::sort_by_smallest_node(
      keys, [](const FaceKey& k) { return k.nodes[0]; },
      [](const FaceKey& a, const FaceKey& b) {
        if (a.nodes != b.nodes) return a.nodes < b.nodes;
        if (a.hex != b.hex) return a.hex < b.hex;
        return a.face < b.face;
      });
  std::vector<std::array<std::int32_t, 6>> out(m);
  for (auto& a : out) a.fill(-1);
  std::size_t i = 0;
  while (i < keys.size()) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].nodes == keys[i].nodes) ++j;
    const auto at = [&](const FaceKey& k) -> std::int32_t& {
      return out[static_cast<std::size_t>(k.hex)][static_cast<std::size_t>(k.face)];
    };
    if (j - i == 2) {
      at(keys[i]) = keys[i + 1].hex;
      at(keys[i + 1]) = keys[i].hex;
    } else if (j - i > 2) {
      for (std::size_t k = i; k < j; ++k) at(keys[k]) = -2;
    }
    i = j;
  }
  return out;
}

std::vector<std::int32_t> hex_layers(const std::vector<std::array<std::int32_t, 6>>& neighbours) {
  std::vector<std::int32_t> layer(neighbours.size(), -1);
  std::deque<std::size_t> queue;
  for (std::size_t h = 0; h < neighbours.size(); ++h) {
    if (std::any_of(neighbours[h].begin(), neighbours[h].end(),
                    [](std::int32_t n) { return n == -1; })) {
      layer[h] = 0;
      queue.push_back(h);
    }
  }
  while (!queue.empty()) {
    const std::size_t h = queue.front();
    queue.pop_front();
    for (const std::int32_t n : neighbours[h]) {
      if (n < 0 || layer[static_cast<std::size_t>(n)] >= 0) continue;
      layer[static_cast<std::size_t>(n)] = layer[h] + 1;
      queue.push_back(static_cast<std::size_t>(n));
    }
  }
  return layer;
}

MeshData hex_mesh_data(const HexMesh& mesh, const stc::HexStc& stc, const WeaveHistory* history) {
  const std::size_t m = mesh.complex.hexes.size();
  const auto n = static_cast<std::size_t>(mesh.points.rows());
  if (stc.vertices.size() != m) {
    throw InvalidInput("hex mesh data: the STC has " + std::to_string(stc.vertices.size()) +
                       " vertices for " + std::to_string(m) +
                       " hexes; build it from this mesh (stc::build_hex_stc)");
  }
  if (history != nullptr && (history->hex_shrink.size() != m || history->hex_rule.size() != m)) {
    throw InvalidInput("hex mesh data: the weave history covers " +
                       std::to_string(history->hex_shrink.size()) + " hexes, the mesh has " +
                       std::to_string(m) + "; pass the history of the weave that made it");
  }
  MeshData data;
  DataArray sj;
  sj.name = "scaled_jacobian";
  sj.values.resize(m);
  for (std::size_t h = 0; h < m; ++h)
    sj.values[h] = hex_scaled_jacobian(mesh.points, mesh.complex.hexes[h]);
  data.cells.push_back(std::move(sj));
  for (std::size_t d = 0; d < 3; ++d) {
    DataArray a = int_array("sheet_" + std::to_string(d), m);
    for (std::size_t h = 0; h < m; ++h) a.values[h] = stc.vertices[h].sheets[d].value();
    data.cells.push_back(std::move(a));
  }
  for (std::size_t d = 0; d < 3; ++d) {
    DataArray a = int_array("chord_" + std::to_string(d), m);
    for (std::size_t h = 0; h < m; ++h) a.values[h] = stc.vertices[h].chords[d].value();
    data.cells.push_back(std::move(a));
  }
  const auto neighbours = hex_face_neighbours(mesh.complex);
  {
    const std::vector<std::int32_t> layers = hex_layers(neighbours);
    DataArray a = int_array("layer", m);
    for (std::size_t h = 0; h < m; ++h) a.values[h] = layers[h];
    data.cells.push_back(std::move(a));
  }
  if (history != nullptr) {
    DataArray step = int_array("creation_step", m);
    DataArray shrink = int_array("shrink", m);
    DataArray rule = int_array("rule", m);
    DataArray depth = int_array("depth", m);
    for (std::size_t h = 0; h < m; ++h) {
      step.values[h] = static_cast<double>(h);  // the weave numbers hexes as it makes them
      shrink.values[h] = history->hex_shrink[h];
      rule.values[h] = rule_code(history->hex_rule[h]);
      const ShrinkRecord* r = history->shrink(history->hex_shrink[h]);
      depth.values[h] = r != nullptr ? r->depth : -1;
    }
    data.cells.push_back(std::move(step));
    data.cells.push_back(std::move(shrink));
    data.cells.push_back(std::move(rule));
    data.cells.push_back(std::move(depth));
  }
  DataArray boundary = int_array("boundary", n);
  DataArray valence = int_array("valence", n);
  for (std::size_t h = 0; h < m; ++h) {
    const stc::Hex& hex = mesh.complex.hexes[h];
    for (const NodeId v : hex)
      if (v.is_valid() && v.index() < n) valence.values[v.index()] += 1.0;
    for (int f = 0; f < 6; ++f) {
      if (neighbours[h][static_cast<std::size_t>(f)] != -1) continue;
      for (const NodeId v : stc::hex_face(hex, f))
        if (v.is_valid() && v.index() < n) boundary.values[v.index()] = 1.0;
    }
  }
  data.points.push_back(std::move(boundary));
  data.points.push_back(std::move(valence));
  return data;
}

}  // namespace stcweave::primal
