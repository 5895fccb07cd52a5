#include "side_faces.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "front_tree.hpp"

namespace stcweave::weave {

namespace {

constexpr std::uint32_t kUnseen = 0xffffffffU;

struct Scratch {
  std::vector<std::size_t> subtree;  ///< 0 between calls
  std::vector<std::uint32_t> tin;    ///< kUnseen between calls
  std::vector<std::uint32_t> tout;
  std::vector<std::int32_t> entry_loop;
  std::vector<NodeId> order;  ///< empty between calls
};

Scratch& scratch_for(std::size_t num_nodes) {
  thread_local Scratch scratch;
  if (scratch.tin.size() < num_nodes) {
    scratch.subtree.resize(num_nodes, 0);
    scratch.tin.resize(num_nodes, kUnseen);
    scratch.tout.resize(num_nodes, 0);
    scratch.entry_loop.resize(num_nodes, -1);
  }
  return scratch;
}

/// Puts back the entries a call touched: the nodes it entered and the first nodes of the
/// alive faces (given a face each before the trees are built, so also on an early return).
struct Release {
  Scratch& scratch;
  const Front& front;
  const FaceTable& table;
  Release(Scratch& s, const Front& f, const FaceTable& t) : scratch(s), front(f), table(t) {}
  Release(const Release&) = delete;
  Release& operator=(const Release&) = delete;
  Release(Release&&) = delete;
  Release& operator=(Release&&) = delete;
  ~Release() {
    for (const NodeId v : scratch.order) scratch.tin[v.index()] = kUnseen;
    for (std::size_t i = 0; i < front.face_capacity(); ++i) {
      const auto f = static_cast<FaceIndex>(i);
      if (front.is_alive(f)) scratch.subtree[table.nodes_of(f)[0].index()] = 0;
    }
    for (const NodeId v : scratch.order) scratch.subtree[v.index()] = 0;
    scratch.order.clear();
  }
};

}  // namespace

SideFaces side_faces(const Front& front, const FaceTable& table, const FrontLoops& loops,
                     const FrontComponents& components,
                     std::span<const std::size_t> component_faces,
                     const std::vector<char>& self_intersecting) {
  const std::size_t num_loops = loops.strips.size();
  SideFaces out;
  out.known.assign(num_loops, 0);
  out.faces_collapsed.assign(num_loops, {0, 0});
  if (num_loops == 0) return out;
  const std::size_t num_nodes = front.num_nodes();

  // Per node scratch, kept between calls and grown with the front's node ids: a weave makes
  // many more node ids than a front holds at once, so clearing arrays over all of them at
  // every selection cost more than the counting. Only the entries of the nodes this call
  // touches are reset, on every way out (`Release`).
  Scratch& scratch = scratch_for(num_nodes);
  std::vector<std::size_t>& subtree = scratch.subtree;
  std::vector<std::uint32_t>& tin = scratch.tin;
  std::vector<std::uint32_t>& tout = scratch.tout;
  std::vector<std::int32_t>& entry_loop = scratch.entry_loop;
  std::vector<NodeId>& order = scratch.order;  // nodes in entry order
  const Release release(scratch, front, table);

  // Each alive face is given to its first node.
  for (std::size_t i = 0; i < front.face_capacity(); ++i) {
    const auto f = static_cast<FaceIndex>(i);
    if (front.is_alive(f)) ++subtree[table.nodes_of(f)[0].index()];
  }

  // One depth-first tree per component: entry time, last entry time in the subtree (so v is
  // in u's subtree iff tin[u] <= tin[v] <= tout[u]), the faces given to the subtree's nodes,
  // and the loop crossing the tree edge into the node (-1 at a root).
  const bool walked = walk_front_trees(
      front, table, loops, [&](NodeId v) { return tin[v.index()] != kUnseen; },
      [&](NodeId v, std::int32_t l) {
        tin[v.index()] = static_cast<std::uint32_t>(order.size());
        entry_loop[v.index()] = l;
        order.push_back(v);
      },
      [&](NodeId v, NodeId parent, std::int32_t /*loop*/) {
        tout[v.index()] = static_cast<std::uint32_t>(order.size() - 1);
        if (parent.is_valid()) subtree[parent.index()] += subtree[v.index()];
      });
  if (!walked) return out;  // an edge no loop crosses: not a front this reads; flood instead

  // Per loop, the nodes whose tree edge it crosses, in entry order (buckets back to back).
  std::vector<std::size_t> first(num_loops + 1, 0);
  for (const NodeId v : order)
    if (entry_loop[v.index()] >= 0) ++first[static_cast<std::size_t>(entry_loop[v.index()]) + 1];
  for (std::size_t l = 0; l < num_loops; ++l) first[l + 1] += first[l];
  std::vector<NodeId> below(first[num_loops]);
  std::vector<std::size_t> fill(first.begin(), first.end() - 1);
  for (const NodeId v : order)
    if (entry_loop[v.index()] >= 0)
      below[fill[static_cast<std::size_t>(entry_loop[v.index()])]++] = v;

  std::vector<std::uint32_t> open;  // last entry times of the enclosing subtrees
  for (std::size_t l = 0; l < num_loops; ++l) {
    const Strip& strip = loops.strips[l];
    const stc::StripStep& p0 = strip.front();
    const NodeId corner_a = quad_at(table.nodes_of(face_of(p0)), p0.entry);
    const std::size_t c = components.component_of[corner_a.index()];
    if (self_intersecting[l] != 0 || components.size[c] != component_faces[c] + 2) continue;
    // Faces given to nodes on the side away from the root: subtree totals, each signed by
    // the parity of the loop's tree edges above it.
    long long away = 0;
    bool a_away = false;
    open.clear();
    const std::uint32_t at_a = tin[corner_a.index()];
    for (std::size_t i = first[l]; i < first[l + 1]; ++i) {
      const NodeId v = below[i];
      while (!open.empty() && open.back() < tin[v.index()]) open.pop_back();
      const auto total = static_cast<long long>(subtree[v.index()]);
      away += open.size() % 2 == 0 ? total : -total;
      open.push_back(tout[v.index()]);
      if (tin[v.index()] <= at_a && at_a <= tout[v.index()]) a_away = !a_away;
    }
    const auto faces = static_cast<long long>(component_faces[c]);
    const long long given_a = a_away ? away : faces - away;
    // The strip's faces given to a node of side A (corners entry and entry + 3) or side B.
    long long strip_a = 0;
    for (const stc::StripStep& p : strip) {
      const int at = (4 - p.entry % 4) % 4;  // where the face's first node sits in the step
      if (at == 0 || at == 3) ++strip_a;
    }
    const auto length = static_cast<long long>(strip.size());
    const long long side_a = given_a - strip_a;
    const long long side_b = (faces - given_a) - (length - strip_a);
    if (side_a < 0 || side_b < 0) continue;  // not a front this reads; flood instead
    out.known[l] = 1;
    out.faces_collapsed[l] = {static_cast<std::size_t>(side_a + length),
                              static_cast<std::size_t>(side_b + length)};
  }
  return out;
}

}  // namespace stcweave::weave
