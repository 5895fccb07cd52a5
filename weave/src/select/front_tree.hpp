#pragma once
/// Depth-first trees over a front's edges, one per component, and the loop crossing each
/// tree edge: the walk `side_parity` and `side_faces` both take (a node's side of a loop that
/// does not cross itself is the parity of that loop's crossings on its tree path).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "face_table.hpp"
#include "stcweave/weave/rules.hpp"

namespace stcweave::weave {

/// Walks one depth-first tree per component of `front`: the roots are the first nodes of the
/// first alive face slot of each component met in slot order, and a node's edges are taken
/// in the order of its incident faces (`table`), each face's edge leaving the node then the
/// one entering it. `seen(v)` says whether node v was entered; `enter(v, loop)` is called when
/// v is first reached, `loop` being the loop crossing the tree edge into it (-1 at a root),
/// and `leave(v, parent, loop)` when its subtree is done (`parent` invalid at a root).
/// \return false, at once, when an edge is crossed by no loop (not a front these walks read).
template <typename Seen, typename Enter, typename Leave>
bool walk_front_trees(const Front& front, const FaceTable& table, const FrontLoops& loops,
                      const Seen& seen, const Enter& enter, const Leave& leave) {
  struct Frame {
    NodeId node;
    std::size_t next = 0;    ///< 2 x incident face + which of the two edges at the node
    std::int32_t loop = -1;  ///< the loop crossing the tree edge into the node
  };
  std::vector<Frame> stack;
  const auto push = [&](NodeId v, std::int32_t l) {
    enter(v, l);
    stack.push_back({v, 0, l});
  };
  for (std::size_t i = 0; i < front.face_capacity(); ++i) {
    const auto f = static_cast<FaceIndex>(i);
    if (!front.is_alive(f)) continue;
    const NodeId root = table.nodes_of(f)[0];
    if (seen(root)) continue;
    push(root, -1);
    while (!stack.empty()) {
      const NodeId v = stack.back().node;
      const std::span<const FaceIndex> around = table.faces_at(v);
      if (stack.back().next >= 2 * around.size()) {
        const std::int32_t l = stack.back().loop;
        stack.pop_back();
        leave(v, stack.empty() ? NodeId() : stack.back().node, l);
        continue;
      }
      const std::size_t at = stack.back().next++;
      const FaceIndex g = around[at / 2];
      const stc::Quad& n = table.nodes_of(g);
      int corner = 0;
      while (n[static_cast<std::size_t>(corner)] != v) ++corner;
      // The edge (corner, corner + 1) is side `corner`; (corner - 1, corner) is side corner + 3.
      const bool forward = at % 2 == 0;
      const int side = forward ? corner : (corner + 3) % 4;
      const NodeId w = quad_at(n, forward ? corner + 1 : corner + 3);
      if (seen(w)) continue;
      const std::int32_t l =
          loops.loop_of[static_cast<std::size_t>(g)][static_cast<std::size_t>(side % 2)];
      if (l < 0) return false;
      push(w, l);
    }
  }
  return true;
}

}  // namespace stcweave::weave
