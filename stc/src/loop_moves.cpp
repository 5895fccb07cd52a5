#include "stcweave/stc/loop_moves.hpp"

#include <algorithm>
#include <array>
#include <deque>
#include <functional>
#include <limits>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "stcweave/stc/errors.hpp"

// The search works on its own compact front: face slots (four nodes, outward from the region
// still to mesh) with, per side, the slot side across it. Faces are never moved, only killed
// and appended, so slot numbers (and the whole run) are deterministic. A state is copied for
// every candidate move it evaluates that leads to a front not seen before (the signature is
// updated by the move's faces before the copy): the copy is O(front) and so is re-tracing the
// loops; the preconditions look only at the front and the attached hexes around the move.

namespace stcweave::stc {

std::string to_string(FrontMove move) {
  switch (move) {
    case FrontMove::Bump:
      return "bump";
    case FrontMove::BlindChord:
      return "blind-chord";
    case FrontMove::Cross:
      return "cross";
    case FrontMove::Surgery:
      return "surgery";
    case FrontMove::Bigon:
      return "bigon";
    case FrontMove::Tube:
      return "tube";
    case FrontMove::Cap:
      return "cap";
    case FrontMove::Close:
      return "close";
  }
  return "?";
}

namespace {

using Slot = std::int32_t;
constexpr Slot kNone = -1;

/// A move's shape: the hex faces (kHexFaces indices) lying on the front.
struct Pattern {
  FrontMove move;
  std::vector<int> chosen;
};

/// Why a search stopped at its evaluation bound.
std::string evaluation_bound_words(const LoopMoveOptions& options) {
  std::string words = "evaluation bound (" + std::to_string(options.max_evaluations) +
                      " moves or " + std::to_string(options.max_work) + " face evaluations";
  if (options.shared_evaluations && *options.shared_evaluations == 0)
    words += ", or the shared pool of evaluations, now empty";
  return words + ") reached";
}

const std::vector<Pattern>& patterns() {
  static const std::vector<Pattern> p = {
      {FrontMove::Bump, {0}},
      {FrontMove::BlindChord, {0, 2}},
      {FrontMove::Cross, {0, 2, 5}},
      {FrontMove::Surgery, {0, 2, 4}},
      {FrontMove::Bigon, {0, 2, 4, 5}},
      {FrontMove::Tube, {2, 3, 4, 5}},
      {FrontMove::Cap, {0, 2, 3, 4, 5}},
      {FrontMove::Close, {0, 1, 2, 3, 4, 5}},
  };
  return p;
}

/// Lexicographic score: loops crossing themselves an odd number of times, self-crossing quads,
/// self-intersecting loops, front faces.
using Score = std::tuple<std::size_t, std::size_t, std::size_t, std::size_t>;
/// The order a search keeps candidates in: the score (then 0), `surgery_rank` or `slide_rank`.
using Rank = std::tuple<std::size_t, std::size_t, std::size_t, std::size_t, std::size_t>;

struct State {
  std::vector<Quad> faces;
  std::vector<std::int32_t> owner;  ///< >= 0: attached hex; < 0: input quad -(id)-1
  std::vector<std::uint8_t> alive;
  std::vector<Slot> nbr;        ///< 4 per slot: slot*4 + side across
  std::vector<Slot> node_face;  ///< per node: a live slot holding it, or kNone
  std::vector<Hex> hexes;
  /// The attached hexes at each node, as lists through (hex * 8 + corner) entries: the head
  /// per node and the next entry per hex corner (-1 ends a list). Flat, so a copy is cheap;
  /// the preconditions look up only the hexes at one node instead of scanning them all.
  std::vector<std::int32_t> hex_head;
  std::vector<std::int32_t> hex_next;
  std::vector<AppliedMove> moves;
  std::size_t num_nodes = 0;
  std::size_t live = 0;
  /// `LoopMoveOptions::strict_contacts`.
  bool strict_contacts = false;
  /// `signature` of the live faces, kept up to date by `apply`.
  std::uint64_t signature = 0;
  Score score{};
  Rank rank{};               ///< the order a search keeps candidates in
  std::size_t curl_gap = 0;  ///< `LoopMoveOptions::curl_gap_crossings`, from the last evaluation
  std::vector<std::int32_t> face_loop;  ///< 2 per slot, from the last evaluation
  /// Per loop, the quads where it crosses itself (> 0: the loop crosses itself; loops a move
  /// took apart keep their entry and no live face refers to them), and the score's loop
  /// figures: loops with an odd count, self-crossing quads, loops that cross themselves. Set
  /// by `evaluate`, updated by `retrace`.
  std::vector<std::uint32_t> loop_crossings;
  std::size_t odd_loops = 0;
  std::size_t self_quads = 0;
  std::size_t self_loops = 0;
};

/// Inserts `t` into `list` (kept sorted by `rank`, equal ranks in insertion order) and keeps
/// at most `width` of them.
void insert_ranked(std::vector<State>& list, State&& t, std::size_t width) {
  const auto pos = std::upper_bound(list.begin(), list.end(), t.rank,
                                    [](const Rank& v, const State& b) { return v < b.rank; });
  if (static_cast<std::size_t>(pos - list.begin()) >= width) return;
  list.insert(pos, std::move(t));
  if (list.size() > width) list.pop_back();
}

/// The order of the surgery look-ahead: self-crossing quads first, then odd loops. A surgery
/// that takes one crossing of an even loop apart leaves an odd loop (one crossing left), which
/// the score ranks behind every front that keeps the even loop; this order keeps it.
Rank surgery_rank(const Score& s) {
  return {std::get<1>(s), std::get<0>(s), std::get<2>(s), std::get<3>(s), 0};
}

Rank score_rank(const Score& s) {
  return {std::get<0>(s), std::get<1>(s), std::get<2>(s), std::get<3>(s), 0};
}

/// The order of the curl slide: the score with the curl gap before the front faces.
Rank slide_rank(const State& s) {
  return {std::get<0>(s.score), std::get<1>(s.score), std::get<2>(s.score), s.curl_gap,
          std::get<3>(s.score)};
}

int corner(const Quad& q, NodeId v) {
  for (int i = 0; i < 4; ++i)
    if (q[static_cast<std::size_t>(i)] == v) return i;
  return -1;
}

/// What the search minimises first: the self-crossings (untangle) or the front (fill).
enum class Goal { SimpleLoops, EmptyFront };

/// The curl gap of one loop, given its passes in travel order (slot, side entered) and, per
/// pass, whether its slot is a self-crossing of the loop: 0 unless the loop has two curls,
/// else the least distance between two of them. A curl is a self-crossing whose two passes
/// follow each other among the loop's self-crossing passes (no other self-crossing on the
/// arc between them), its arc the passes strictly between. Distance: with `surface`, the
/// fewest steps across front edges from a face of one curl's arc to a face of the other's;
/// else the fewest passes strictly between the two curls along the loop. With
/// `opposite_only`, only pairs of curls of opposite sense count (+1 when the second pass
/// enters the quad one side after the first in the quad's order, else -1).
std::size_t loop_curl_gap(const State& s, const std::vector<std::pair<Slot, int>>& passes,
                          const std::vector<std::uint8_t>& crossing, bool surface,
                          bool opposite_only) {
  std::vector<std::size_t> at;  // positions of the self-crossing passes, in travel order
  for (std::size_t i = 0; i < passes.size(); ++i)
    if (crossing[i] != 0U) at.push_back(i);
  const std::size_t k = at.size();
  if (k < 4) return 0;
  const std::size_t len = passes.size();
  struct Curl {
    std::size_t first;  // position of the pass opening the curl
    std::size_t last;   // position of the pass closing it
    int sense;
  };
  std::vector<Curl> curls;
  for (std::size_t j = 0; j < k; ++j) {
    const auto& a = passes[at[j]];
    const auto& b = passes[at[(j + 1) % k]];
    if (a.first != b.first) continue;
    const int turn = ((b.second - a.second) % 4 + 4) % 4;
    curls.push_back({at[j], at[(j + 1) % k], turn == 1 ? 1 : -1});
  }
  std::size_t best = std::numeric_limits<std::size_t>::max();
  for (std::size_t i = 0; i < curls.size(); ++i) {
    for (std::size_t j = i + 1; j < curls.size(); ++j) {
      if (opposite_only && curls[i].sense == curls[j].sense) continue;
      if (!surface) {
        // Passes strictly between the end of one curl and the start of the other, either way.
        const std::size_t ij = (curls[j].first + len - curls[i].last) % len - 1;
        const std::size_t ji = (curls[i].first + len - curls[j].last) % len - 1;
        best = std::min({best, ij, ji});
        continue;
      }
      // Breadth-first from curl i's arc to curl j's, over face adjacency.
      std::vector<std::int32_t> dist(s.faces.size(), -1);
      std::vector<std::uint8_t> target(s.faces.size(), 0);
      std::deque<Slot> queue;
      for (std::size_t p = (curls[i].first + 1) % len; p != curls[i].last; p = (p + 1) % len) {
        const auto f = static_cast<std::size_t>(passes[p].first);
        if (dist[f] < 0) {
          dist[f] = 0;
          queue.push_back(passes[p].first);
        }
      }
      for (std::size_t p = (curls[j].first + 1) % len; p != curls[j].last; p = (p + 1) % len)
        target[static_cast<std::size_t>(passes[p].first)] = 1;
      while (!queue.empty()) {
        const auto f = static_cast<std::size_t>(queue.front());
        queue.pop_front();
        if (target[f] != 0U) {
          best = std::min(best, static_cast<std::size_t>(dist[f]));
          break;
        }
        if (static_cast<std::size_t>(dist[f]) + 1 >= best) break;
        for (int side = 0; side < 4; ++side) {
          const auto g =
              static_cast<std::size_t>(s.nbr[4 * f + static_cast<std::size_t>(side)] / 4);
          if (dist[g] >= 0) continue;
          dist[g] = dist[f] + 1;
          queue.push_back(static_cast<Slot>(g));
        }
      }
    }
  }
  return best == std::numeric_limits<std::size_t>::max() ? 0 : best;
}

/// The score of `s` from its loop figures and live faces.
void set_score(State& s, Goal goal) {
  s.score = goal == Goal::SimpleLoops ? Score{s.odd_loops, s.self_quads, s.self_loops, s.live}
                                      : Score{s.live, s.self_quads, s.self_loops, 0};
}

/// Traces every loop; sets face_loop, the loop figures and the score. With `curl` (the search's
/// options), the score's curl gap (`LoopMoveOptions::curl_gap_crossings`); without, 0.
void evaluate(State& s, Goal goal = Goal::SimpleLoops, const LoopMoveOptions* curl = nullptr) {
  const std::size_t curl_crossings = curl != nullptr ? curl->curl_gap_crossings : 0;
  const std::size_t n = s.faces.size();
  s.face_loop.assign(2 * n, -1);
  std::int32_t loops = 0;
  const bool curls = curl_crossings > 0 && goal == Goal::SimpleLoops;
  // With the curl gap: every loop's passes in travel order, and where each loop starts.
  std::vector<std::pair<Slot, int>> passes;
  std::vector<std::size_t> loop_start;
  for (std::size_t f = 0; f < n; ++f) {
    if (s.alive[f] == 0U) continue;
    for (int d = 0; d < 2; ++d) {
      if (s.face_loop[2 * f + static_cast<std::size_t>(d)] >= 0) continue;
      std::size_t g = f;
      int entry = d;
      if (curls) loop_start.push_back(passes.size());
      while (s.face_loop[2 * g + static_cast<std::size_t>(entry % 2)] < 0) {
        s.face_loop[2 * g + static_cast<std::size_t>(entry % 2)] = loops;
        if (curls) passes.emplace_back(static_cast<Slot>(g), entry);
        const Slot across = s.nbr[4 * g + static_cast<std::size_t>((entry + 2) % 4)];
        g = static_cast<std::size_t>(across / 4);
        entry = across % 4;
      }
      ++loops;
    }
  }
  std::vector<std::uint32_t>& per_loop = s.loop_crossings;
  per_loop.assign(static_cast<std::size_t>(loops), 0);
  s.self_quads = 0;
  for (std::size_t f = 0; f < n; ++f) {
    if (s.alive[f] != 0U && s.face_loop[2 * f] == s.face_loop[2 * f + 1]) {
      ++s.self_quads;
      ++per_loop[static_cast<std::size_t>(s.face_loop[2 * f])];
    }
  }
  s.self_loops = static_cast<std::size_t>(
      std::count_if(per_loop.begin(), per_loop.end(), [](std::uint32_t c) { return c > 0; }));
  s.odd_loops = static_cast<std::size_t>(
      std::count_if(per_loop.begin(), per_loop.end(), [](std::uint32_t c) { return c % 2 == 1; }));
  std::size_t gap = 0;
  if (curls) {
    loop_start.push_back(passes.size());
    std::vector<std::pair<Slot, int>> one;
    std::vector<std::uint8_t> crossing;
    for (std::size_t l = 0; l < static_cast<std::size_t>(loops); ++l) {
      if (per_loop[l] < 2 || per_loop[l] > curl_crossings) continue;
      one.assign(passes.begin() + static_cast<std::ptrdiff_t>(loop_start[l]),
                 passes.begin() + static_cast<std::ptrdiff_t>(loop_start[l + 1]));
      crossing.assign(one.size(), 0);
      for (std::size_t i = 0; i < one.size(); ++i) {
        const auto f = static_cast<std::size_t>(one[i].first);
        crossing[i] = s.face_loop[2 * f] == s.face_loop[2 * f + 1] ? 1 : 0;
      }
      gap += loop_curl_gap(s, one, crossing, curl->curl_gap_surface, curl->curl_gap_opposite);
    }
  }
  s.curl_gap = gap;
  set_score(s, goal);
}

/// `evaluate` without the curl gap after one `apply` to an evaluated state, in time
/// proportional to the loops the move changed rather than the front: the loops through the
/// `removed` faces are taken off the figures, and the loops through the new faces (slots from
/// `first_new` on) traced afresh; every other loop, and its id, stays. Every surviving strand
/// of a loop that ran through a removed face is now on a loop through a new face (the face
/// across the side it shared with the removed face is new), so tracing from the new faces
/// reaches all of them; a loop lying wholly in the removed faces (around a tube, on a cap, a
/// closed component) just disappears. Loop ids then differ from a full evaluation's, which
/// nothing orders by; the figures, and so the score, are the same.
/// \pre `s` is a state whose loops were traced (`evaluate` or `retrace`) with exactly one
///      `apply` since, which removed the faces `removed` and appended slots from `first_new`.
void retrace(State& s, const std::vector<Slot>& removed, std::size_t first_new, Goal goal) {
  std::array<std::int32_t, 12> gone{};
  std::size_t num_gone = 0;
  for (const Slot f : removed) {
    for (std::size_t d = 0; d < 2; ++d) {
      const std::int32_t l = s.face_loop[2 * static_cast<std::size_t>(f) + d];
      if (std::find(gone.begin(), gone.begin() + static_cast<std::ptrdiff_t>(num_gone), l) !=
          gone.begin() + static_cast<std::ptrdiff_t>(num_gone))
        continue;
      gone[num_gone++] = l;
      const std::uint32_t c = s.loop_crossings[static_cast<std::size_t>(l)];
      s.self_quads -= c;
      s.self_loops -= c > 0 ? 1 : 0;
      s.odd_loops -= c % 2;
    }
  }
  const std::size_t n = s.faces.size();
  s.face_loop.resize(2 * n, -1);
  const auto first_id = static_cast<std::int32_t>(s.loop_crossings.size());
  for (std::size_t f = first_new; f < n; ++f) {
    for (int d = 0; d < 2; ++d) {
      if (s.face_loop[2 * f + static_cast<std::size_t>(d)] >= first_id) continue;
      const auto id = static_cast<std::int32_t>(s.loop_crossings.size());
      std::uint32_t crossings = 0;
      std::size_t g = f;
      int entry = d;
      while (s.face_loop[2 * g + static_cast<std::size_t>(entry % 2)] != id) {
        s.face_loop[2 * g + static_cast<std::size_t>(entry % 2)] = id;
        if (s.face_loop[2 * g + static_cast<std::size_t>(1 - entry % 2)] == id) ++crossings;
        const Slot across = s.nbr[4 * g + static_cast<std::size_t>((entry + 2) % 4)];
        g = static_cast<std::size_t>(across / 4);
        entry = across % 4;
      }
      s.loop_crossings.push_back(crossings);
      s.self_quads += crossings;
      s.self_loops += crossings > 0 ? 1 : 0;
      s.odd_loops += crossings % 2;
    }
  }
  s.curl_gap = 0;
  set_score(s, goal);
}

/// The faces around node `v` in order (walking across the side leaving v), and their count.
template <class Visit>
std::size_t walk_fan(const State& s, NodeId v, Visit&& visit) {
  const Slot start = s.node_face[v.index()];
  if (start == kNone) return 0;
  Slot f = start;
  std::size_t count = 0;
  do {
    const int i = corner(s.faces[static_cast<std::size_t>(f)], v);
    if (i < 0 || count > s.faces.size()) return count;  // broken front: caller's checks fail
    visit(f, i);
    ++count;
    const Slot across = s.nbr[4 * static_cast<std::size_t>(f) + static_cast<std::size_t>(i)];
    f = across / 4;
  } while (f != start);
  return count;
}

bool front_edge(const State& s, NodeId a, NodeId b) {
  bool found = false;
  walk_fan(s, a, [&](Slot f, int i) {
    const Quad& q = s.faces[static_cast<std::size_t>(f)];
    if (q[static_cast<std::size_t>((i + 1) % 4)] == b ||
        q[static_cast<std::size_t>((i + 3) % 4)] == b)
      found = true;
  });
  return found;
}

bool same_nodes(Quad a, Quad b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  return a == b;
}

bool front_face_on(const State& s, const Quad& q) {
  bool found = false;
  walk_fan(s, q[0], [&](Slot f, int) {
    if (same_nodes(s.faces[static_cast<std::size_t>(f)], q)) found = true;
  });
  return found;
}

/// `LoopMoveOptions::check_scores`: the figures `retrace` left in `s` against a full trace.
std::uint64_t signature(const State& s);

void check_retrace(const State& s, Goal goal) {
  State full = s;
  evaluate(full, goal);
  const auto words = [](const State& x) {
    return "(" + std::to_string(std::get<0>(x.score)) + ", " +
           std::to_string(std::get<1>(x.score)) + ", " + std::to_string(std::get<2>(x.score)) +
           ", " + std::to_string(std::get<3>(x.score)) + "; odd loops " +
           std::to_string(x.odd_loops) + ")";
  };
  if (full.score != s.score || full.self_quads != s.self_quads || full.odd_loops != s.odd_loops ||
      full.self_loops != s.self_loops) {
    throw InternalError("loop moves: the score updated from the loops a move changed " + words(s) +
                        " is not the full trace's " + words(full));
  }
  if (signature(s) != s.signature)
    throw InternalError("loop moves: the front's signature updated by the move is not its own");
  // The strands of the live faces fall into the same loops (ids matched one to one), each
  // with the full trace's crossings.
  std::unordered_map<std::int32_t, std::int32_t> to_full;
  std::unordered_map<std::int32_t, std::int32_t> from_full;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    if (s.alive[f] == 0U) continue;
    for (std::size_t d = 0; d < 2; ++d) {
      const std::int32_t a = s.face_loop[2 * f + d];
      const std::int32_t b = full.face_loop[2 * f + d];
      const auto mine = static_cast<std::size_t>(a);
      const auto theirs = static_cast<std::size_t>(b);
      if (to_full.emplace(a, b).first->second != b || from_full.emplace(b, a).first->second != a ||
          s.loop_crossings[mine] != full.loop_crossings[theirs]) {
        throw InternalError(
            "loop moves: loop figures updated from a move differ from the full "
            "trace's at face slot " +
            std::to_string(f));
      }
    }
  }
}

/// Calls `visit(h)` for every attached hex at node `v`, latest first, until it returns true;
/// true when one did.
template <class Visit>
bool any_hex_at(const State& s, NodeId v, Visit&& visit) {
  if (v.index() >= s.hex_head.size()) return false;
  for (std::int32_t e = s.hex_head[v.index()]; e >= 0; e = s.hex_next[static_cast<std::size_t>(e)])
    if (visit(s.hexes[static_cast<std::size_t>(e / 8)])) return true;
  return false;
}

bool hex_edge_on(const State& s, NodeId a, NodeId b) {
  return any_hex_at(s, a, [&](const Hex& h) {
    for (const auto& e : kHexEdges) {
      const NodeId x = h[static_cast<std::size_t>(e[0])];
      const NodeId y = h[static_cast<std::size_t>(e[1])];
      if ((x == a && y == b) || (x == b && y == a)) return true;
    }
    return false;
  });
}

bool hex_face_on(const State& s, const Quad& q) {
  return any_hex_at(s, q[0], [&](const Hex& h) {
    for (int f = 0; f < 6; ++f)
      if (same_nodes(hex_face(h, f), q)) return true;
    return false;
  });
}

/// True when a hex on the existing nodes `mapped` (sorted) would share more than four nodes
/// with an attached hex, or four nodes with one that is not among `glued` (the owners of the
/// front faces it is built on): two hexes share at most one face, and four shared nodes must
/// be that face.
bool shares_too_much(const State& s, const std::vector<NodeId>& mapped,
                     const std::vector<std::int32_t>& glued) {
  std::vector<std::int32_t> seen;
  for (const NodeId v : mapped) {
    if (v.index() >= s.hex_head.size()) continue;
    for (std::int32_t e = s.hex_head[v.index()]; e >= 0;
         e = s.hex_next[static_cast<std::size_t>(e)]) {
      const std::int32_t id = e / 8;
      if (std::find(seen.begin(), seen.end(), id) != seen.end()) continue;
      seen.push_back(id);
      std::size_t common = 0;
      for (const NodeId w : s.hexes[static_cast<std::size_t>(id)])
        if (std::binary_search(mapped.begin(), mapped.end(), w)) ++common;
      if (common > 4) return true;
      if (common == 4 && std::find(glued.begin(), glued.end(), id) == glued.end()) return true;
    }
  }
  return false;
}

/// Adds `h` to the attached hexes and to the lists of its nodes (`State::hex_head`).
void add_hex(State& s, const Hex& h) {
  const auto id = static_cast<std::int32_t>(s.hexes.size());
  s.hexes.push_back(h);
  if (s.hex_head.size() < s.num_nodes) s.hex_head.resize(s.num_nodes, -1);
  for (std::size_t k = 0; k < 8; ++k) {
    s.hex_next.push_back(s.hex_head[h[k].index()]);
    s.hex_head[h[k].index()] = 8 * id + static_cast<std::int32_t>(k);
  }
}

/// A candidate: the pattern, the front node of every hex local node (invalid: a new node)
/// and the slot of every chosen hex face.
struct Candidate {
  const Pattern* pattern = nullptr;
  std::array<NodeId, 8> map{};
  std::array<Slot, 6> slot_of{};
};

bool hex_face_has(int face, int local) {
  const auto& idx = kHexFaces[static_cast<std::size_t>(face)];
  return std::find(idx.begin(), idx.end(), local) != idx.end();
}

/// Maps `pattern` onto the front with its hex face `pattern.chosen[seed]` on slot `f`
/// rotated by `rot`, then checks every precondition. False when any fails.
bool try_candidate(const State& s, const Pattern& pattern, std::size_t seed, Slot f, int rot,
                   int min_valence, Candidate& c) {
  c.pattern = &pattern;
  c.map.fill(NodeId::invalid());
  c.slot_of.fill(kNone);
  const auto assign = [&](int hf, Slot slot, int r) {
    const Quad& q = s.faces[static_cast<std::size_t>(slot)];
    for (int i = 0; i < 4; ++i) {
      const auto local = static_cast<std::size_t>(
          kHexFaces[static_cast<std::size_t>(hf)][static_cast<std::size_t>(i)]);
      const NodeId node = q[static_cast<std::size_t>((i + r) % 4)];
      if (!c.map[local].is_valid()) {
        c.map[local] = node;
      } else if (c.map[local] != node) {
        return false;
      }
    }
    c.slot_of[static_cast<std::size_t>(hf)] = slot;
    return true;
  };
  if (!assign(pattern.chosen[seed], f, rot)) return false;
  // Grow through shared hex edges, in pattern order (deterministic).
  bool grew = true;
  while (grew) {
    grew = false;
    for (const int t : pattern.chosen) {
      if (c.slot_of[static_cast<std::size_t>(t)] != kNone) continue;
      for (const int u : pattern.chosen) {
        const Slot us = c.slot_of[static_cast<std::size_t>(u)];
        if (us == kNone) continue;
        // A directed edge a->b of hex face u that hex face t holds as b->a.
        const auto& iu = kHexFaces[static_cast<std::size_t>(u)];
        const auto& it = kHexFaces[static_cast<std::size_t>(t)];
        int side_u = -1;
        int side_t = -1;
        for (int i = 0; i < 4 && side_u < 0; ++i) {
          for (int k = 0; k < 4; ++k) {
            if (it[static_cast<std::size_t>(k)] == iu[static_cast<std::size_t>((i + 1) % 4)] &&
                it[static_cast<std::size_t>((k + 1) % 4)] == iu[static_cast<std::size_t>(i)]) {
              side_u = i;
              side_t = k;
              break;
            }
          }
        }
        if (side_u < 0) continue;
        // The slot side holding map[a] -> map[b] in slot us.
        const Quad& uq = s.faces[static_cast<std::size_t>(us)];
        const NodeId a = c.map[static_cast<std::size_t>(iu[static_cast<std::size_t>(side_u)])];
        int j = corner(uq, a);
        if (j < 0) return false;
        const Slot across = s.nbr[4 * static_cast<std::size_t>(us) + static_cast<std::size_t>(j)];
        const Slot g = across / 4;
        const int jg = across % 4;
        if (!assign(t, g, ((jg - side_t) % 4 + 4) % 4)) return false;
        grew = true;
        break;
      }
    }
  }
  // Distinct slots, distinct owners (a hex never gets two faces of one attached hex).
  std::vector<Slot> slots;
  std::vector<std::int32_t> owners;
  for (const int t : pattern.chosen) {
    const Slot sl = c.slot_of[static_cast<std::size_t>(t)];
    if (sl == kNone) return false;
    slots.push_back(sl);
    const std::int32_t o = s.owner[static_cast<std::size_t>(sl)];
    if (o >= 0) owners.push_back(o);
  }
  std::sort(slots.begin(), slots.end());
  if (std::adjacent_find(slots.begin(), slots.end()) != slots.end()) return false;
  std::sort(owners.begin(), owners.end());
  if (std::adjacent_find(owners.begin(), owners.end()) != owners.end()) return false;
  // Every chosen face must match its slot exactly (the growth checked the nodes it met).
  for (const int t : pattern.chosen) {
    const Quad& q = s.faces[static_cast<std::size_t>(c.slot_of[static_cast<std::size_t>(t)])];
    const Quad h = hex_face(
        Hex{NodeId(0), NodeId(1), NodeId(2), NodeId(3), NodeId(4), NodeId(5), NodeId(6), NodeId(7)},
        t);
    const int r = corner(q, c.map[h[0].index()]);
    if (r < 0) return false;
    for (int i = 0; i < 4; ++i)
      if (q[static_cast<std::size_t>((i + r) % 4)] != c.map[h[static_cast<std::size_t>(i)].index()])
        return false;
  }
  // Injective node map.
  std::vector<NodeId> mapped;
  for (const NodeId v : c.map)
    if (v.is_valid()) mapped.push_back(v);
  std::sort(mapped.begin(), mapped.end());
  if (std::adjacent_find(mapped.begin(), mapped.end()) != mapped.end()) return false;
  if (s.strict_contacts && mapped.size() >= 4 && shares_too_much(s, mapped, owners)) return false;
  // Valence: a node with all three of its hex faces chosen leaves the front and must have
  // exactly those three faces; any other node keeps faces outside and valence >= 3.
  for (int local = 0; local < 8; ++local) {
    const NodeId v = c.map[static_cast<std::size_t>(local)];
    if (!v.is_valid()) continue;
    int j = 0;
    for (const int t : pattern.chosen)
      if (hex_face_has(t, local)) ++j;
    const auto d = static_cast<int>(walk_fan(s, v, [](Slot, int) {}));
    if (j == 3) {
      if (d != 3) return false;
    } else if (d <= j || d + 3 - 2 * j < min_valence) {
      return false;
    }
  }
  // New edges between existing nodes must be new to the front and to the attached hexes.
  for (const auto& e : kHexEdges) {
    const NodeId a = c.map[static_cast<std::size_t>(e[0])];
    const NodeId b = c.map[static_cast<std::size_t>(e[1])];
    if (!a.is_valid() || !b.is_valid()) continue;
    bool on_chosen = false;
    for (const int t : pattern.chosen)
      if (hex_face_has(t, e[0]) && hex_face_has(t, e[1])) on_chosen = true;
    if (on_chosen) continue;
    if (front_edge(s, a, b) || hex_edge_on(s, a, b)) return false;
  }
  // New faces on existing nodes only must be new faces.
  for (int u = 0; u < 6; ++u) {
    if (std::find(pattern.chosen.begin(), pattern.chosen.end(), u) != pattern.chosen.end())
      continue;
    Quad q{};
    bool all = true;
    for (int i = 0; i < 4; ++i) {
      q[static_cast<std::size_t>(i)] = c.map[static_cast<std::size_t>(
          kHexFaces[static_cast<std::size_t>(u)][static_cast<std::size_t>(i)])];
      all = all && q[static_cast<std::size_t>(i)].is_valid();
    }
    if (all && (front_face_on(s, q) || hex_face_on(s, q))) return false;
  }
  return true;
}

/// One face's part of a front's signature: a mix of its nodes as a sorted set (so a face
/// and its reversal count alike).
std::uint64_t face_hash(Quad q) {
  std::sort(q.begin(), q.end());
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (const NodeId v : q) {
    h ^= static_cast<std::uint32_t>(v.value());
    // splitmix64's finaliser after each id
    h += 0x9e3779b97f4a7c15ULL;
    h = (h ^ (h >> 30U)) * 0xbf58476d1ce4e5b9ULL;
    h = (h ^ (h >> 27U)) * 0x94d049bb133111ebULL;
    h ^= h >> 31U;
  }
  return h;
}

/// A signature of the front, to skip fronts the search has already seen: the sum of its live
/// faces' `face_hash`, so that it depends on the set of faces only (not on slots) and a move
/// updates it by its removed and added faces (`signature_after`) without a pass over the
/// front.
std::uint64_t signature(const State& s) {
  std::uint64_t h = 0;
  for (std::size_t f = 0; f < s.faces.size(); ++f)
    if (s.alive[f] != 0U) h += face_hash(s.faces[f]);
  return h;
}

/// The hex a checked candidate attaches: its mapped nodes, new nodes numbered from
/// `s.num_nodes` in the order of the hex's corners (as `apply` numbers them).
Hex hex_of(const State& s, const Candidate& c) {
  Hex h{};
  std::size_t next = s.num_nodes;
  for (std::size_t local = 0; local < 8; ++local)
    h[local] = c.map[local].is_valid() ? c.map[local] : NodeId(next++);
  return h;
}

bool is_chosen(const Pattern& p, int f) {
  return std::find(p.chosen.begin(), p.chosen.end(), f) != p.chosen.end();
}

/// The signature of `s` after `apply(s, c)`, without applying it.
std::uint64_t signature_after(const State& s, const Candidate& c) {
  const Hex h = hex_of(s, c);
  std::uint64_t sig = s.signature;
  for (int u = 0; u < 6; ++u) {
    if (is_chosen(*c.pattern, u)) {
      sig -= face_hash(s.faces[static_cast<std::size_t>(c.slot_of[static_cast<std::size_t>(u)])]);
    } else {
      sig += face_hash(hex_face(h, u));
    }
  }
  return sig;
}

/// Applies a checked candidate: the hex, its new nodes, the new front faces and their sides.
void apply(State& s, const Candidate& c) {
  s.signature = signature_after(s, c);
  const Hex h = hex_of(s, c);
  s.num_nodes += static_cast<std::size_t>(
      std::count_if(c.map.begin(), c.map.end(), [](NodeId v) { return !v.is_valid(); }));
  s.node_face.resize(s.num_nodes, kNone);
  const auto hex_id = static_cast<std::int32_t>(s.hexes.size());
  add_hex(s, h);
  const Pattern& p = *c.pattern;
  const auto chosen = [&](int f) { return is_chosen(p, f); };
  // New slots for the unchosen faces, reversed (outward from the rest).
  std::array<Slot, 6> new_slot{};
  new_slot.fill(kNone);
  for (int u = 0; u < 6; ++u) {
    if (chosen(u)) continue;
    new_slot[static_cast<std::size_t>(u)] = static_cast<Slot>(s.faces.size());
    s.faces.push_back(reversed(hex_face(h, u)));
    s.owner.push_back(hex_id);
    s.alive.push_back(1);
    s.nbr.insert(s.nbr.end(), 4, kNone);
    ++s.live;
  }
  for (int u = 0; u < 6; ++u) {
    const Slot ns = new_slot[static_cast<std::size_t>(u)];
    if (ns == kNone) continue;
    const Quad q = s.faces[static_cast<std::size_t>(ns)];
    for (int i = 0; i < 4; ++i) {
      const NodeId x = q[static_cast<std::size_t>(i)];
      const NodeId y = q[static_cast<std::size_t>((i + 1) % 4)];
      // The other hex face on edge {x, y}.
      for (int t = 0; t < 6; ++t) {
        if (t == u) continue;
        const Quad ht = hex_face(h, t);
        if (corner(ht, x) < 0 || corner(ht, y) < 0) continue;
        const Slot ts = new_slot[static_cast<std::size_t>(t)];
        if (ts != kNone) {  // another new face: it holds y -> x
          const Quad& tq = s.faces[static_cast<std::size_t>(ts)];
          const int k = corner(tq, y);
          s.nbr[4 * static_cast<std::size_t>(ns) + static_cast<std::size_t>(i)] = 4 * ts + k;
        } else {  // a chosen face: it held x -> y; take over its neighbour
          const Slot cs = c.slot_of[static_cast<std::size_t>(t)];
          const int k = corner(s.faces[static_cast<std::size_t>(cs)], x);
          const Slot o = s.nbr[4 * static_cast<std::size_t>(cs) + static_cast<std::size_t>(k)];
          s.nbr[4 * static_cast<std::size_t>(ns) + static_cast<std::size_t>(i)] = o;
          s.nbr[static_cast<std::size_t>(o)] = 4 * ns + i;
        }
        break;
      }
    }
  }
  for (const int t : p.chosen) {
    const Slot cs = c.slot_of[static_cast<std::size_t>(t)];
    s.alive[static_cast<std::size_t>(cs)] = 0;
    --s.live;
    for (const NodeId v : s.faces[static_cast<std::size_t>(cs)]) s.node_face[v.index()] = kNone;
  }
  for (int u = 0; u < 6; ++u) {
    const Slot ns = new_slot[static_cast<std::size_t>(u)];
    if (ns == kNone) continue;
    for (const NodeId v : s.faces[static_cast<std::size_t>(ns)]) s.node_face[v.index()] = ns;
  }
  s.moves.push_back({p.move, HexId(static_cast<std::size_t>(hex_id)), 0, s.live});
}

/// Seeds of the candidate moves: the live faces crossed by a self-intersecting loop, nearest
/// a self-crossing quad first (breadth-first over face adjacency), ties by slot.
std::vector<Slot> hot_faces(const State& s, Goal goal) {
  const std::size_t n = s.faces.size();
  if (goal == Goal::EmptyFront) {
    std::vector<Slot> all;
    for (std::size_t f = 0; f < n; ++f)
      if (s.alive[f] != 0U) all.push_back(static_cast<Slot>(f));
    return all;
  }
  std::vector<std::int32_t> dist(n, -1);
  std::deque<Slot> queue;
  for (std::size_t f = 0; f < n; ++f) {
    if (s.alive[f] != 0U && s.face_loop[2 * f] == s.face_loop[2 * f + 1]) {
      dist[f] = 0;
      queue.push_back(static_cast<Slot>(f));
    }
  }
  std::vector<Slot> order;
  while (!queue.empty()) {
    const Slot f = queue.front();
    queue.pop_front();
    const auto fi = static_cast<std::size_t>(f);
    const bool hot = s.loop_crossings[static_cast<std::size_t>(s.face_loop[2 * fi])] > 0 ||
                     s.loop_crossings[static_cast<std::size_t>(s.face_loop[2 * fi + 1])] > 0;
    if (hot) order.push_back(f);
    for (int i = 0; i < 4; ++i) {
      const Slot g = s.nbr[4 * fi + static_cast<std::size_t>(i)] / 4;
      if (dist[static_cast<std::size_t>(g)] < 0) {
        dist[static_cast<std::size_t>(g)] = dist[fi] + 1;
        queue.push_back(g);
      }
    }
  }
  return order;
}

/// The candidate of `pattern` whose front faces are exactly the slots `want`; false if none
/// passes the preconditions.
bool candidate_on(const State& s, const Pattern& pattern, std::vector<Slot> want, Candidate& c) {
  std::sort(want.begin(), want.end());
  for (std::size_t seed = 0; seed < pattern.chosen.size(); ++seed) {
    for (int rot = 0; rot < 4; ++rot) {
      if (!try_candidate(s, pattern, seed, want.front(), rot, 3, c)) continue;
      std::vector<Slot> got;
      for (const int t : pattern.chosen) got.push_back(c.slot_of[static_cast<std::size_t>(t)]);
      std::sort(got.begin(), got.end());
      if (got == want) return true;
    }
  }
  return false;
}

/// A straight strip of the front: faces F0 .. F(m+1) that one loop P passes through in turn,
/// with `enter[i]` the side of F(i) facing F(i-1) (`enter[0]` unused).
struct Strip {
  std::vector<Slot> faces;
  std::vector<int> enter;
};

/// The strips a tunnel may run along: from a face crossed by a self-intersecting loop (not
/// where it crosses itself), along the other loop P through that face, to a face that a
/// self-intersecting loop crosses again, passing at most `hits` such faces on the way and at
/// most `length` faces between the ends. Each strip once (its first slot below its last), in
/// slot order.
std::vector<Strip> tunnel_strips(const State& s, std::size_t length, std::size_t hits) {
  std::vector<Strip> out;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    if (s.alive[f] == 0U) continue;
    for (int dl = 0; dl < 2; ++dl) {
      const std::int32_t l = s.face_loop[2 * f + static_cast<std::size_t>(dl)];
      const std::int32_t loop_p = s.face_loop[2 * f + static_cast<std::size_t>(1 - dl)];
      if (s.loop_crossings[static_cast<std::size_t>(l)] == 0 || l == loop_p) continue;
      for (const int exit0 : {1 - dl, 3 - dl}) {
        Strip st;
        st.faces.push_back(static_cast<Slot>(f));
        st.enter.push_back(-1);
        std::size_t seen_hits = 0;
        auto g = static_cast<std::size_t>(f);
        int exit = exit0;
        while (st.faces.size() <= length + 1) {
          const Slot across = s.nbr[4 * g + static_cast<std::size_t>(exit)];
          g = static_cast<std::size_t>(across / 4);
          const int k = across % 4;
          if (std::find(st.faces.begin(), st.faces.end(), static_cast<Slot>(g)) != st.faces.end())
            break;  // P closed up (or crossed itself) before another hit
          st.faces.push_back(static_cast<Slot>(g));
          st.enter.push_back(k);
          const std::int32_t t = s.face_loop[2 * g + static_cast<std::size_t>(1 - k % 2)];
          if (s.loop_crossings[static_cast<std::size_t>(t)] > 0) {
            if (st.faces.size() >= 3 && st.faces.front() < st.faces.back()) out.push_back(st);
            if (++seen_hits > hits) break;
          }
          exit = (k + 2) % 4;
        }
      }
    }
  }
  return out;
}

/// The faces a tunnel's hex must also take at an end of the row: around each node of the
/// edge between `strip.faces[i - 1]` and `strip.faces[i]` that has valence 3, the third face
/// (a node of valence 3 on that edge would be left with valence 2 otherwise; taking its third
/// face too takes it off the front).
void end_faces(const State& s, const Strip& strip, std::size_t i, std::vector<Slot>& want) {
  const Slot f = strip.faces[i];
  const auto side = static_cast<std::size_t>(strip.enter[i]);
  const Quad& q = s.faces[static_cast<std::size_t>(f)];
  for (const NodeId v : {q[side], q[(side + 1) % 4]}) {
    std::vector<Slot> fan;
    if (walk_fan(s, v, [&](Slot g, int) { fan.push_back(g); }) != 3) continue;
    for (const Slot g : fan)
      if (g != f && g != strip.faces[i - 1] && std::find(want.begin(), want.end(), g) == want.end())
        want.push_back(g);
  }
}

/// Attaches a row of m = faces - 2 hexes on the strip: hex i on F(i), with F(0) and F(m+1) as
/// the row's end faces. Built one hex at a time: a blind chord on the previous hex's far face
/// (F(0) for the first) and F(i), then a surgery on the last far face, F(m) and F(m+1). At an
/// end of the row a node of valence 3 on the end edge makes the hex take that node's third
/// face too (a cross, bigon, tube or cap instead of the blind chord or surgery). Each step
/// passes `try_candidate`'s preconditions or the whole tunnel is refused (false; `s` is then
/// partly changed and must be dropped). With `trace`, the front is evaluated after every hex
/// so that each applied move records its self-crossing quads.
bool apply_tunnel(State& s, const Strip& strip, bool trace) {
  const std::size_t m = strip.faces.size() - 2;
  Slot prev = strip.faces[0];
  for (std::size_t i = 1; i <= m; ++i) {
    const bool last = i == m;
    std::vector<Slot> want{prev, strip.faces[i]};
    if (last) want.push_back(strip.faces[i + 1]);
    if (i == 1) end_faces(s, strip, 1, want);
    if (last) end_faces(s, strip, m + 1, want);
    Candidate c;
    bool found = false;
    for (const Pattern& p : patterns()) {
      if (p.chosen.size() != want.size()) continue;
      if (want.size() == 2 && p.move != FrontMove::BlindChord) continue;
      if (want.size() == 3 && p.move == FrontMove::Cross && !(last || i == 1)) continue;
      if (candidate_on(s, p, want, c)) {
        found = true;
        break;
      }
    }
    if (!found) return false;
    const auto hex_id = static_cast<std::int32_t>(s.hexes.size());
    apply(s, c);
    if (trace) {
      evaluate(s);
      s.moves.back().self_crossing_quads = s.self_quads;
    }
    if (last) break;
    // The new face of hex i on the edge F(i) shared with F(i+1): the next hex's other face.
    const auto next = static_cast<std::size_t>(strip.faces[i + 1]);
    prev = s.nbr[4 * next + static_cast<std::size_t>(strip.enter[i + 1])] / 4;
    if (s.owner[static_cast<std::size_t>(prev)] != hex_id) return false;
  }
  return true;
}

/// The part of the score a look-ahead must lower: (odd loops, self-crossing quads) when
/// untangling, (front faces, self-crossing quads) when filling.
std::tuple<std::size_t, std::size_t> goal_key(const State& s) {
  return {std::get<0>(s.score), std::get<1>(s.score)};
}

/// The placement of candidate `c` of pattern `p`: its front faces, sorted, and the move (one
/// placement may be reached from several seeds and rotations).
std::array<Slot, 7> placement_key(const Pattern& p, const Candidate& c) {
  std::array<Slot, 7> key{};
  key.fill(kNone);
  for (std::size_t i = 0; i < p.chosen.size(); ++i)
    key[i] = c.slot_of[static_cast<std::size_t>(p.chosen[i])];
  std::sort(key.begin(), key.begin() + 6);  // the unused places (kNone) first
  key[6] = static_cast<Slot>(p.move);
  return key;
}

class Search {
 public:
  Search(const LoopMoveOptions& options, std::size_t input_quads, Goal goal)
      : options_(options), max_faces_(input_quads + options.max_extra_faces), goal_(goal) {}

  /// What a call of `successors` looks for.
  enum class Mode {
    Beam,     ///< every move, ranked by the score
    Surgery,  ///< the surgery look-ahead (`surgery_rank`)
    Slide,    ///< the curl slide: every move, ranked by `slide_rank` (the curl gap counted)
  };

  /// The candidate fronts one move away from `s`, best first, at most `keep` of them.
  std::vector<State> successors(const State& s, std::size_t keep) {
    return successors(s, keep, Mode::Beam, options_.max_candidates);
  }

  /// The next level of a look-ahead: the successors in `mode` of every front of `level`, the
  /// best `keep` of them all by rank (in `Mode::Beam` the rank orders as the score does).
  std::vector<State> next_level(const std::vector<State>& level, std::size_t keep, Mode mode,
                                std::size_t max_tried) {
    std::vector<State> next;
    for (const State& s : level)
      for (State& t : successors(s, keep, mode, max_tried)) insert_ranked(next, std::move(t), keep);
    return next;
  }

  /// With `Mode::Surgery`: only the two surgeries (the moves that reconnect loops), seeded
  /// at every face of a self-intersecting loop however far from its crossings, at most
  /// `max_tried` evaluated, ranked by `surgery_rank` (self-crossing quads before odd loops).
  /// With `Mode::Slide`: as the beam, but each front's curl gap is evaluated and ranks it
  /// (`slide_rank`). The surgery look-ahead and the slide keep their own record of the fronts
  /// seen.
  std::vector<State> successors(const State& s, std::size_t keep, Mode mode,
                                std::size_t max_tried) {
    const bool surgeries_only = mode == Mode::Surgery;
    std::vector<State> best;
    // The (faces, move) of every candidate tried from `s`: one placement may be reached from
    // several seeds and rotations.
    std::set<std::array<Slot, 7>> seen;
    std::size_t tried = 0;
    for (const Slot f : hot_faces(s, goal_)) {
      if (tried >= max_tried || exhausted()) break;
      for (const Pattern& p : patterns()) {
        if (surgeries_only && p.move != FrontMove::Surgery && p.move != FrontMove::Tube) continue;
        for (std::size_t seed = 0; seed < p.chosen.size(); ++seed) {
          for (int rot = 0; rot < 4; ++rot) {
            Candidate c;
            if (!try_candidate(s, p, seed, f, rot, 3, c)) continue;
            if (!seen.insert(placement_key(p, c)).second) continue;
            if (s.live + 6 - 2 * p.chosen.size() > max_faces_) continue;
            // The surgery look-ahead keeps its own record: the beam may have seen (and
            // dropped, by its order) the very fronts it needs.
            auto& seen_fronts = mode == Mode::Surgery ? seen_surgery_fronts_
                                : mode == Mode::Slide ? seen_slide_fronts_
                                                      : seen_fronts_;
            if (!seen_fronts.insert(signature_after(s, c)).second) continue;
            State next = moved(s, p, c, mode == Mode::Slide);
            ++tried;
            next.rank = mode == Mode::Surgery ? surgery_rank(next.score)
                        : mode == Mode::Slide ? slide_rank(next)
                                              : score_rank(next.score);
            insert_ranked(best, std::move(next), keep);
          }
        }
      }
    }
    return best;
  }

  /// The tunnels from `s` (see `LoopMoveOptions::tunnel_length`): every strip of
  /// `tunnel_strips` tried on a copy of `s`, the `keep` best kept by `surgery_rank`
  /// (self-crossing quads first), each ranked front without its trace (`trace` false).
  std::vector<std::pair<State, Strip>> tunnels(const State& s, std::size_t keep) {
    std::vector<std::pair<State, Strip>> best;
    for (const Strip& st : tunnel_strips(s, options_.tunnel_length, options_.tunnel_hits)) {
      if (exhausted()) break;
      const std::size_t m = st.faces.size() - 2;
      if (s.live + 2 * m - 2 > max_faces_ || s.moves.size() + m > options_.max_moves) continue;
      State next = s;
      if (!apply_tunnel(next, st, false)) continue;
      evaluate(next, goal_);
      count_evaluation();
      work_ += next.faces.size() * m;
      next.rank = surgery_rank(next.score);
      const auto pos = std::upper_bound(
          best.begin(), best.end(), next.rank,
          [](const Rank& v, const std::pair<State, Strip>& b) { return v < b.first.rank; });
      if (static_cast<std::size_t>(pos - best.begin()) >= keep) continue;
      best.insert(pos, {std::move(next), st});
      if (best.size() > keep) best.pop_back();
    }
    return best;
  }

  /// The tunnel stage: one tunnel, or two in a row (the first taking one crossing of a loop
  /// apart and leaving it odd, the second the other crossing), whose result has (odd loops,
  /// self-crossing quads) below `s`'s; the lowest score wins. True and `out` set when found:
  /// `s` with the tunnels replayed, every hex's self-crossings traced.
  bool tunnel(const State& s, State& out) {
    std::vector<Strip> chosen;
    Score best_score{};
    const auto consider = [&](const State& t, const std::vector<Strip>& path) {
      if (goal_key(t) >= goal_key(s) || (!chosen.empty() && t.score >= best_score)) return;
      chosen = path;
      best_score = t.score;
    };
    auto first = tunnels(s, std::max<std::size_t>(1, options_.tunnel_width));
    for (const auto& [t, st] : first) consider(t, {st});
    if (chosen.empty()) {
      for (const auto& [t, st] : first) {
        // Only a front with fewer self-crossing quads is worth a second tunnel.
        if (std::get<1>(t.score) > std::get<1>(s.score)) break;
        for (const auto& [u, st2] : tunnels(t, 1)) consider(u, {st, st2});
      }
    }
    if (chosen.empty()) return false;
    out = s;
    for (const Strip& st : chosen)
      if (!apply_tunnel(out, st, true))
        throw InternalError("loop moves: a tunnel that applied once does not apply again");
    evaluate(out, goal_);
    return true;
  }

  /// Iterative deepening over every move of every face (its own record of fronts: per
  /// signature, the most moves left it was searched with), up to `max_depth` moves and
  /// `max_evaluations` evaluations: the first front found whose (odd loops, self-crossing
  /// quads) or (front faces, self-crossing quads) is below `s`'s. True and `out` set when
  /// found.
  bool deepen(const State& s, std::size_t max_depth, std::size_t max_evaluations, State& out) {
    const auto target = goal_key(s);
    std::unordered_map<std::uint64_t, std::size_t> table;
    std::size_t spent = 0;
    const std::function<bool(const State&, std::size_t)> dfs = [&](const State& x,
                                                                   std::size_t left) -> bool {
      if (left == 0) return false;
      std::set<std::array<Slot, 7>> seen;
      for (std::size_t f = 0; f < x.faces.size(); ++f) {
        if (x.alive[f] == 0U) continue;
        for (const Pattern& p : patterns()) {
          for (std::size_t seed = 0; seed < p.chosen.size(); ++seed) {
            for (int rot = 0; rot < 4; ++rot) {
              if (spent >= max_evaluations || exhausted()) return false;
              Candidate c;
              if (!try_candidate(x, p, seed, static_cast<Slot>(f), rot, 3, c)) continue;
              if (!seen.insert(placement_key(p, c)).second) continue;
              if (x.live + 6 - 2 * p.chosen.size() > max_faces_) continue;
              const std::uint64_t sig = signature_after(x, c);
              const auto it = table.find(sig);
              if (it != table.end() && it->second >= left - 1) continue;
              table[sig] = left - 1;
              State next = moved(x, p, c, false);
              ++spent;
              if (goal_key(next) < target) {
                out = std::move(next);
                return true;
              }
              if (dfs(next, left - 1)) return true;
            }
          }
        }
      }
      return false;
    };
    for (std::size_t depth = 1; depth <= max_depth; ++depth) {
      table.clear();
      if (dfs(s, depth)) return true;
      if (spent >= max_evaluations || exhausted()) return false;
    }
    return false;
  }

  [[nodiscard]] std::size_t evaluations() const { return evaluations_; }
  /// Called every `LoopMoveOptions::progress_every` evaluations when the options have a
  /// progress callback (the caller reports its own current front).
  void on_tick(std::function<void()> tick) { tick_ = std::move(tick); }

  [[nodiscard]] bool exhausted() const {
    return evaluations_ >= options_.max_evaluations || work_ >= options_.max_work ||
           (options_.shared_evaluations && *options_.shared_evaluations == 0);
  }

 private:
  /// `s` with candidate `c` of pattern `p` applied and scored (with `full_trace`, every loop
  /// traced again and the curl gap evaluated, as the curl slide ranks; else the loops the move
  /// changed re-traced), counted as one evaluation.
  State moved(const State& s, const Pattern& p, const Candidate& c, bool full_trace) {
    State next = s;
    const std::size_t first_new = next.faces.size();
    apply(next, c);
    if (full_trace) {
      evaluate(next, goal_, &options_);
    } else {
      std::vector<Slot> removed;
      for (const int t : p.chosen) removed.push_back(c.slot_of[static_cast<std::size_t>(t)]);
      retrace(next, removed, first_new, goal_);
      if (options_.check_scores) check_retrace(next, goal_);
    }
    next.moves.back().self_crossing_quads = next.self_quads;
    count_evaluation();
    work_ += next.faces.size();
    return next;
  }

  void count_evaluation() {
    ++evaluations_;
    if (options_.shared_evaluations && *options_.shared_evaluations > 0)
      --*options_.shared_evaluations;
    if (tick_ && options_.progress_every > 0 && evaluations_ % options_.progress_every == 0)
      tick_();
  }

  const LoopMoveOptions& options_;
  std::function<void()> tick_;
  std::size_t max_faces_;
  Goal goal_;
  std::size_t evaluations_ = 0;
  std::size_t work_ = 0;
  std::unordered_set<std::uint64_t> seen_fronts_;
  std::unordered_set<std::uint64_t> seen_surgery_fronts_;
  std::unordered_set<std::uint64_t> seen_slide_fronts_;
};

State initial_state(const QuadSurface& surface) {
  State s;
  s.num_nodes = surface.num_nodes;
  s.faces = surface.quads;
  const std::size_t n = surface.quads.size();
  s.owner.resize(n);
  for (std::size_t q = 0; q < n; ++q) s.owner[q] = -static_cast<std::int32_t>(q) - 1;
  s.alive.assign(n, 1);
  s.live = n;
  s.nbr.assign(4 * n, kNone);
  s.node_face.assign(s.num_nodes, kNone);
  std::unordered_map<std::uint64_t, Slot> directed;
  directed.reserve(4 * n);
  const auto key = [](NodeId a, NodeId b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a.value())) << 32U) |
           static_cast<std::uint32_t>(b.value());
  };
  for (std::size_t q = 0; q < n; ++q) {
    for (int i = 0; i < 4; ++i) {
      const NodeId a = s.faces[q][static_cast<std::size_t>(i)];
      const NodeId b = s.faces[q][static_cast<std::size_t>((i + 1) % 4)];
      if (!a.is_valid() || a.index() >= s.num_nodes || a == b)
        throw InvalidInput("untangle_loops: quad q" + std::to_string(q) +
                           " has a node out of range or a repeated node");
      if (!directed.emplace(key(a, b), static_cast<Slot>(4 * q + static_cast<std::size_t>(i)))
               .second) {
        throw InvalidInput("untangle_loops: edge " + a.str() + "-" + b.str() +
                           " is used twice in the same direction: the surface must be "
                           "manifold and consistently oriented");
      }
      s.node_face[a.index()] = static_cast<Slot>(q);
    }
  }
  for (std::size_t q = 0; q < n; ++q) {
    for (int i = 0; i < 4; ++i) {
      const NodeId a = s.faces[q][static_cast<std::size_t>(i)];
      const NodeId b = s.faces[q][static_cast<std::size_t>((i + 1) % 4)];
      const auto it = directed.find(key(b, a));
      if (it == directed.end()) {
        throw InvalidInput("untangle_loops: edge " + a.str() + "-" + b.str() + " of quad q" +
                           std::to_string(q) +
                           " has no reverse: the surface must be closed and consistently oriented");
      }
      s.nbr[4 * q + static_cast<std::size_t>(i)] = it->second;
    }
  }
  s.hex_head.assign(s.num_nodes, -1);
  s.signature = signature(s);
  evaluate(s);
  return s;
}

LoopMoveResult result_of(const State& s, std::size_t num_input_nodes) {
  LoopMoveResult r;
  r.num_input_nodes = num_input_nodes;
  r.hexes.hexes = s.hexes;
  r.hexes.num_nodes = s.num_nodes;
  r.front.num_nodes = s.num_nodes;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    if (s.alive[f] == 0U) continue;
    r.front.quads.push_back(s.faces[f]);
    const std::int32_t o = s.owner[f];
    r.front_hex.push_back(o >= 0 ? o : -1);
    r.front_input.push_back(o >= 0 ? -1 : -o - 1);
  }
  r.moves = s.moves;
  r.self_crossing_quads_after = std::get<1>(s.score);
  r.simple = std::get<1>(s.score) == 0;
  return r;
}

/// The search loop shared by `untangle_loops` and `fill_front`: greedy while a single move
/// lowers the score, a beam search when none does; stops at the goal or at a bound.
void run(State& current, const LoopMoveOptions& options, Goal goal, std::size_t input_quads,
         LoopMoveResult& r) {
  Search search(options, input_quads, goal);
  const auto done = [&](const State& s) {
    return goal == Goal::SimpleLoops ? std::get<1>(s.score) == 0 : s.live == 0;
  };
  // Progress: every 10th attached hex (checked after each step, which may attach several)
  // and, through the search, every `progress_every` evaluations.
  std::size_t reported_tens = current.moves.size() / 10;
  const auto report = [&] {
    LoopMoveProgress p;
    p.filling = goal == Goal::EmptyFront;
    p.hexes = current.moves.size();
    p.self_crossing_quads = current.self_quads;
    p.front_faces = current.live;
    p.evaluations = search.evaluations();
    options.progress(p);
  };
  if (options.progress) search.on_tick(report);
  const auto after_step = [&] {
    if (!options.progress || current.moves.size() / 10 == reported_tens) return;
    reported_tens = current.moves.size() / 10;
    report();
  };
  std::string stop;
  bool sliding = false;  // a curl slide was taken and (odd loops, self-crossings) not lowered
  std::tuple<std::size_t, std::size_t> sliding_from{};
  while (!done(current)) {
    after_step();
    if (current.moves.size() >= options.max_moves) {
      stop = "move bound (" + std::to_string(options.max_moves) + " moves) reached";
      break;
    }
    if (search.exhausted()) {
      stop = evaluation_bound_words(options);
      break;
    }
    const bool small = current.live <= options.small_front;
    const std::size_t width = std::max<std::size_t>(
        1, small ? std::max(options.beam_width, options.small_beam_width) : options.beam_width);
    const std::size_t depth_bound = std::min(
        small ? std::max(options.beam_depth, options.small_beam_depth) : options.beam_depth,
        options.max_moves - current.moves.size());
    // After a curl slide, and until (odd loops, self-crossing quads) fall, the greedy step
    // ranks by `slide_rank` so that it does not undo the slide to save front faces.
    if (sliding && goal_key(current) < sliding_from) sliding = false;
    if (sliding) evaluate(current, goal, &options);
    std::vector<State> level =
        sliding ? search.successors(current, width, Search::Mode::Slide, options.max_candidates)
                : search.successors(current, width);
    if (!level.empty() && (sliding ? slide_rank(level.front()) < slide_rank(current)
                                   : level.front().score < current.score)) {
      current = std::move(level.front());
      continue;
    }
    // No single move helps: look ahead for a lower score.
    ++r.beam_searches;
    bool improved = false;
    for (std::size_t depth = 2; depth <= depth_bound && !level.empty() && !improved; ++depth) {
      level = search.next_level(level, width, Search::Mode::Beam, options.max_candidates);
      if (!level.empty() && goal_key(level.front()) < goal_key(current)) {
        current = std::move(level.front());
        improved = true;
      }
    }
    if (!improved && goal == Goal::SimpleLoops && options.surgery_depth > 0) {
      // The surgery look-ahead: sequences of surgeries anywhere on the self-intersecting
      // loops, ranked so that taking one crossing apart counts as progress even when it
      // leaves an odd loop for the next surgery to fix.
      ++r.surgery_searches;
      std::vector<State> surgeries = search.successors(
          current, options.surgery_width, Search::Mode::Surgery, options.surgery_candidates);
      for (std::size_t depth = 1; depth <= options.surgery_depth && !surgeries.empty(); ++depth) {
        if (goal_key(surgeries.front()) < goal_key(current)) {
          current = std::move(surgeries.front());
          improved = true;
          break;
        }
        if (depth == options.surgery_depth) break;
        surgeries = search.next_level(surgeries, options.surgery_width, Search::Mode::Surgery,
                                      options.surgery_candidates);
      }
    }
    if (!improved && goal == Goal::SimpleLoops && options.tunnel_length > 0) {
      // The tunnel: a row of hexes reconnecting two strands of self-intersecting loops that
      // are too far apart for any sequence of local moves (two opposite curls of one loop).
      State best;
      if (search.tunnel(current, best)) {
        current = std::move(best);
        improved = true;
        ++r.tunnels;
      }
    }
    if (!improved && goal == Goal::SimpleLoops && options.curl_gap_crossings > 0 &&
        options.curl_slide_depth > 0) {
      // The curl slide: a loop left with two curls (two self-crossings, each with no other on
      // the arc between its passes) cancels them only once they are side by side; moves that
      // bring them closer change no figure of the score, so look for a sequence that lowers
      // the curl gap, (odd loops, self-crossing quads) not rising.
      evaluate(current, goal, &options);
      if (current.curl_gap > 0) {
        const auto slide_key = [](const State& s) {
          return std::make_tuple(std::get<0>(s.score), std::get<1>(s.score), s.curl_gap);
        };
        std::vector<State> slide{current};
        for (std::size_t depth = 1; depth <= options.curl_slide_depth && !slide.empty(); ++depth) {
          slide = search.next_level(slide, options.curl_slide_width, Search::Mode::Slide,
                                    options.max_candidates);
          if (!slide.empty() && slide_key(slide.front()) < slide_key(current)) {
            if (!sliding) sliding_from = goal_key(current);
            sliding = true;
            current = std::move(slide.front());
            improved = true;
            ++r.curl_slides;
            break;
          }
        }
      }
    }
    if (!improved && current.live <= options.tiny_front && options.tiny_depth > 0) {
      State found;
      // The move bound holds through it as through the beam (`depth_bound`).
      const std::size_t depth =
          std::min(options.tiny_depth, options.max_moves - current.moves.size());
      if (search.deepen(current, depth, options.tiny_evaluations, found)) {
        current = std::move(found);
        improved = true;
        ++r.deepenings;
      }
    }
    if (!improved && search.exhausted()) {
      stop = evaluation_bound_words(options);
      break;
    }
    if (!improved) {
      stop = "no sequence of up to " + std::to_string(depth_bound) + " moves lowers " +
             (goal == Goal::SimpleLoops
                  ? "the self-crossings (" + std::to_string(std::get<1>(current.score)) +
                        " quads left)"
                  : "the front (" + std::to_string(current.live) + " faces left)");
      break;
    }
  }
  r.evaluations += search.evaluations();
  r.stop_reason = done(current) ? (goal == Goal::SimpleLoops ? "simple" : "empty") : stop;
}

}  // namespace

LoopMoveResult untangle_loops(const QuadSurface& surface, const LoopMoveOptions& options) {
  State current = initial_state(surface);
  current.strict_contacts = options.strict_contacts;
  const std::size_t before = std::get<1>(current.score);
  LoopMoveResult stats;
  run(current, options, Goal::SimpleLoops, surface.num_quads(), stats);
  LoopMoveResult r = result_of(current, surface.num_nodes);
  r.self_crossing_quads_before = before;
  r.evaluations = stats.evaluations;
  r.beam_searches = stats.beam_searches;
  r.surgery_searches = stats.surgery_searches;
  r.tunnels = stats.tunnels;
  r.curl_slides = stats.curl_slides;
  r.deepenings = stats.deepenings;
  r.stop_reason = stats.stop_reason;
  return r;
}

LoopMoveResult fill_front(const LoopMoveResult& start, const LoopMoveOptions& options) {
  for (std::size_t h = 0; h < start.hexes.hexes.size(); ++h) {
    for (const NodeId v : start.hexes.hexes[h]) {
      if (!v.is_valid() || v.index() >= start.hexes.num_nodes) {
        throw InvalidInput("fill_front: attached hex h" + std::to_string(h) +
                           " has a node out of range (" + std::to_string(start.hexes.num_nodes) +
                           " nodes): `start` must be a result of untangle_loops");
      }
    }
  }
  State current = initial_state(start.front);
  current.strict_contacts = options.strict_contacts;
  for (std::size_t f = 0; f < current.owner.size(); ++f)
    current.owner[f] = start.front_hex[f] >= 0 ? start.front_hex[f] : -start.front_input[f] - 1;
  current.num_nodes = std::max(current.num_nodes, start.hexes.num_nodes);
  for (const Hex& h : start.hexes.hexes) add_hex(current, h);
  current.moves = start.moves;
  evaluate(current, Goal::EmptyFront);
  LoopMoveResult stats;
  run(current, options, Goal::EmptyFront, start.front.quads.size(), stats);
  LoopMoveResult r = result_of(current, start.num_input_nodes);
  r.self_crossing_quads_before = start.self_crossing_quads_before;
  r.evaluations = start.evaluations + stats.evaluations;
  r.beam_searches = start.beam_searches + stats.beam_searches;
  r.surgery_searches = start.surgery_searches + stats.surgery_searches;
  r.tunnels = start.tunnels + stats.tunnels;
  r.curl_slides = start.curl_slides + stats.curl_slides;
  r.deepenings = start.deepenings + stats.deepenings;
  r.stop_reason = stats.stop_reason;
  r.simple = current.live == 0;
  return r;
}

}  // namespace stcweave::stc
