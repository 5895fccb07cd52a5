#include "stcweave/weave/front.hpp"

#include <algorithm>
#include <unordered_map>

#include "stcweave/stc/errors.hpp"

namespace stcweave::weave {

std::string FaceOwner::str() const {
  if (is_input()) return QuadId(id).str();
  return HexId(id).str() + "." + std::to_string(local_face);
}

Front::Front(const stc::QuadSurface& surface) : num_input_nodes_(surface.num_nodes) {
  parent_.resize(surface.num_nodes);
  for (std::size_t i = 0; i < parent_.size(); ++i) parent_[i] = NodeId(i);
  incident_.resize(surface.num_nodes);
  faces_.reserve(surface.quads.size() * 2);
  for (std::size_t q = 0; q < surface.quads.size(); ++q) {
    const stc::Quad& quad = surface.quads[q];
    for (int i = 0; i < 4; ++i) {
      const NodeId n = quad[static_cast<std::size_t>(i)];
      if (!n.is_valid() || n.index() >= surface.num_nodes) {
        throw InvalidInput("weave: " + QuadId(q).str() + " uses node " + n.str() +
                           " out of range (surface has " + std::to_string(surface.num_nodes) +
                           " nodes)");
      }
      for (int j = 0; j < i; ++j) {
        if (quad[static_cast<std::size_t>(j)] == n)
          throw InvalidInput("weave: " + QuadId(q).str() + " repeats node " + n.str() +
                             " (degenerate quad): remove or repair it");
      }
    }
    add_face(quad, FaceOwner{FaceOwner::Kind::Input, static_cast<std::int32_t>(q), -1}, 0);
  }
}

NodeId Front::find(NodeId n) const {
  auto& p = parent_;
  while (p[n.index()] != n) {
    p[n.index()] = p[p[n.index()].index()];
    n = p[n.index()];
  }
  return n;
}

NodeId Front::new_node() {
  const NodeId n(parent_.size());
  parent_.push_back(n);
  incident_.emplace_back();
  return n;
}

void Front::merge_nodes(NodeId keep, NodeId gone) {
  auto& moved = incident_[gone.index()];
  for (FaceIndex f : moved) {
    for (NodeId& n : faces_[static_cast<std::size_t>(f)].nodes)
      if (n == gone) n = keep;
    log_face(f);
  }
  if (change_log_ != nullptr) change_log_->nodes.push_back(gone);
  auto& kept = incident_[keep.index()];
  if (open_checkpoints_ > 0) {
    journal_.push_back({IncidenceChange::Kind::Merge, static_cast<std::uint32_t>(keep.index()),
                        static_cast<std::uint32_t>(gone.index()),
                        static_cast<std::uint32_t>(kept.size()), kNoFace});
  }
  kept.insert(kept.end(), moved.begin(), moved.end());
  moved.clear();
  moved.shrink_to_fit();
  parent_[gone.index()] = keep;
}

FaceIndex Front::add_face(const stc::Quad& nodes, FaceOwner owner, std::int32_t depth,
                          const std::array<float, 4>& side_angle) {
  FaceIndex f;
  if (!free_.empty()) {
    f = free_.back();
    free_.pop_back();
  } else {
    f = static_cast<FaceIndex>(faces_.size());
    faces_.emplace_back();
  }
  FrontFace& face = faces_[static_cast<std::size_t>(f)];
  face.nodes = nodes;
  face.owner = owner;
  face.depth = depth;
  face.side_angle = side_angle;
  face.alive = true;
  log_face(f);
  for (NodeId n : nodes) {
    incident_[n.index()].push_back(f);
    if (open_checkpoints_ > 0) {
      journal_.push_back(
          {IncidenceChange::Kind::Push, static_cast<std::uint32_t>(n.index()), 0, 0, f});
    }
  }
  ++alive_;
  return f;
}

void Front::remove_face(FaceIndex f) {
  log_face(f);
  FrontFace& face = faces_[static_cast<std::size_t>(f)];
  for (NodeId n : face.nodes) {
    auto& list = incident_[n.index()];
    const auto it = std::find(list.begin(), list.end(), f);
    if (it == list.end()) continue;
    if (open_checkpoints_ > 0) {
      journal_.push_back({IncidenceChange::Kind::Erase, static_cast<std::uint32_t>(n.index()), 0,
                          static_cast<std::uint32_t>(it - list.begin()), f});
    }
    list.erase(it);
  }
  face.alive = false;
  free_.push_back(f);
  --alive_;
}

Front::Checkpoint Front::checkpoint() {
  ++open_checkpoints_;
  return {faces_, free_, parent_, alive_, journal_.size()};
}

void Front::roll_back(Checkpoint&& c) {
  while (journal_.size() > c.journal) {
    const IncidenceChange e = journal_.back();
    journal_.pop_back();
    auto& list = incident_[e.node];
    switch (e.kind) {
      case IncidenceChange::Kind::Push:
        list.pop_back();
        break;
      case IncidenceChange::Kind::Erase:
        list.insert(list.begin() + e.pos, e.face);
        break;
      case IncidenceChange::Kind::Merge:
        incident_[e.other].assign(list.begin() + e.pos, list.end());
        list.resize(e.pos);
        break;
    }
  }
  incident_.resize(c.parent.size());
  faces_ = std::move(c.faces);
  free_ = std::move(c.free);
  parent_ = std::move(c.parent);
  alive_ = c.alive;
  --open_checkpoints_;
}

void Front::release(Checkpoint&& c) {
  --open_checkpoints_;
  if (open_checkpoints_ == 0) journal_.clear();
  c = Checkpoint{};
}

int Front::corner_of(FaceIndex f, NodeId v) const {
  const auto& nodes = face(f).nodes;
  for (int i = 0; i < 4; ++i)
    if (nodes[static_cast<std::size_t>(i)] == v) return i;
  return -1;
}

FaceSide Front::find_edge(NodeId from, NodeId to) const {
  for (FaceIndex f : incident_[from.index()]) {
    const auto& n = face(f).nodes;
    for (int i = 0; i < 4; ++i)
      if (n[static_cast<std::size_t>(i)] == from && n[static_cast<std::size_t>((i + 1) % 4)] == to)
        return {f, i};
  }
  return {};
}

FaceSide Front::across(FaceIndex f, int side) const {
  const auto& n = face(f).nodes;
  const NodeId from = n[static_cast<std::size_t>((side + 1) % 4)];
  const NodeId to = n[static_cast<std::size_t>(side)];
  const auto fi = static_cast<std::size_t>(f);
  if (fi >= across_hint_.size()) across_hint_.resize(faces_.size());
  FaceSide& hint = across_hint_[fi][static_cast<std::size_t>(side)];
  if (hint.face != kNoFace && is_alive(hint.face)) {
    const auto& m = face(hint.face).nodes;
    if (m[static_cast<std::size_t>(hint.index)] == from &&
        m[static_cast<std::size_t>((hint.index + 1) % 4)] == to)
      return hint;
  }
  hint = find_edge(from, to);
  return hint;
}

std::optional<std::string> Front::check_invariants() const {
  struct PairHash {
    std::size_t operator()(const std::pair<std::int32_t, std::int32_t>& p) const noexcept {
      return std::hash<std::int64_t>()((static_cast<std::int64_t>(p.first) << 32) ^
                                       static_cast<std::uint32_t>(p.second));
    }
  };
  std::unordered_map<std::pair<std::int32_t, std::int32_t>, FaceIndex, PairHash> directed;
  std::size_t alive = 0;
  for (std::size_t fi = 0; fi < faces_.size(); ++fi) {
    const FrontFace& face = faces_[fi];
    if (!face.alive) continue;
    ++alive;
    const auto f = static_cast<FaceIndex>(fi);
    for (int i = 0; i < 4; ++i) {
      const NodeId a = face.nodes[static_cast<std::size_t>(i)];
      const NodeId b = face.nodes[static_cast<std::size_t>((i + 1) % 4)];
      if (find(a) != a) return "front face " + std::to_string(f) + " uses merged node " + a.str();
      for (int j = i + 1; j < 4; ++j)
        if (face.nodes[static_cast<std::size_t>(j)] == a)
          return "front face " + std::to_string(f) + " repeats node " + a.str();
      const auto& list = incident_[a.index()];
      if (std::count(list.begin(), list.end(), f) != 1)
        return "incidence list of " + a.str() + " misses front face " + std::to_string(f);
      const auto [it, fresh] = directed.emplace(std::make_pair(a.value(), b.value()), f);
      if (!fresh)
        return "directed edge " + a.str() + "->" + b.str() + " in front faces " +
               std::to_string(it->second) + " and " + std::to_string(f) + " (pinched front)";
    }
  }
  if (alive != alive_) return "alive face count out of date";
  for (const auto& [edge, f] : directed) {
    if (!directed.contains({edge.second, edge.first}))
      return "edge " + NodeId(edge.first).str() + "-" + NodeId(edge.second).str() +
             " of front face " + std::to_string(f) + " is open";
  }
  // every vertex link is one cycle
  for (std::size_t v = 0; v < incident_.size(); ++v) {
    const auto& list = incident_[v];
    if (list.empty()) continue;
    for (FaceIndex f : list)
      if (!is_alive(f)) return "incidence list of n" + std::to_string(v) + " holds a dead face";
    // walk the rotation: from (f, corner i) go across side i to (g, j) holding v at j+1
    const NodeId node(v);
    FaceIndex f = list.front();
    std::size_t steps = 0;
    do {
      const int i = corner_of(f, node);
      const FaceSide next = across(f, i);
      if (next.face == kNoFace) return "rotation around " + node.str() + " is broken";
      f = next.face;
      ++steps;
    } while (f != list.front() && steps <= list.size());
    if (steps != list.size())
      return "faces around " + node.str() + " do not form one cycle (pinched at a node)";
  }
  return std::nullopt;
}

}  // namespace stcweave::weave
