#include "stcweave/primal/cut.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iterator>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <tuple>

#include "chord_disc.hpp"
#include "slab_band.hpp"
#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/primal/handles.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/loops.hpp"
#include "stcweave/stc/surface_topology.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/attached.hpp"

namespace stcweave::primal {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// A disc choice: a grid_a x grid_b grid whose boundary walk starts at cycle position `start`.
struct DiscChoice {
  int a = 0;
  int b = 0;
  std::size_t start = 0;
  double score = 0.0;
  bool ring = false;  ///< an O-grid: the grid is an inner block ringed by one layer of quads
  /// A chord disc (`chord_disc`) when not empty: boundary edge p paired with `partner[p]`
  /// (edge p runs from cycle position p to p + 1; `a`, `b`, `start` unused).
  std::vector<std::size_t> partner;
  std::size_t quads = 0;  ///< of a chord disc
};

constexpr std::size_t kNoPartner = static_cast<std::size_t>(-1);

/// Inner block of an O-grid disc: the grid's transfinite positions scaled by this factor
/// about the cycle's centroid.
constexpr double kRingShrink = 0.6;

/// Disc choices for a cycle, best first: the four grid corners where the cycle turns most
/// (sum of turning angles), then the squarest grid, then the smallest start.
std::vector<DiscChoice> disc_choices(const Points& points, const std::vector<NodeId>& cycle) {
  const std::size_t len = cycle.size();
  std::vector<double> turn(len, 0.0);
  const auto at = [&](std::size_t k) -> Eigen::Vector3d {
    return points.row(cycle[k % len].value()).transpose();
  };
  for (std::size_t k = 0; k < len; ++k) {
    const Eigen::Vector3d in = (at(k) - at(k + len - 1)).normalized();
    const Eigen::Vector3d out = (at(k + 1) - at(k)).normalized();
    turn[k] = std::acos(std::clamp(in.dot(out), -1.0, 1.0));
  }
  std::vector<DiscChoice> choices;
  const int half = static_cast<int>(len / 2);
  for (int a = 1; a < half; ++a) {
    const int b = half - a;
    if (a > b) break;  // (a, b) and (b, a) differ by the start only
    for (std::size_t s = 0; s < len; ++s) {
      // a x b and b x a starting at s are the same corners shifted: enumerate both starts.
      DiscChoice c;
      c.a = a;
      c.b = b;
      c.start = s;
      const std::size_t ua = static_cast<std::size_t>(a);
      const std::size_t ub = static_cast<std::size_t>(b);
      c.score = turn[s % len] + turn[(s + ua) % len] + turn[(s + ua + ub) % len] +
                turn[(s + 2 * ua + ub) % len];
      choices.push_back(c);
    }
  }
  std::stable_sort(choices.begin(), choices.end(), [](const DiscChoice& p, const DiscChoice& q) {
    if (std::abs(p.score - q.score) > 1e-9) return p.score > q.score;
    if (std::abs(p.a - p.b) != std::abs(q.a - q.b))
      return std::abs(p.a - p.b) < std::abs(q.a - q.b);
    return p.start < q.start;
  });
  // Same corner set reached from two starts (a == b symmetric shifts): keep the first.
  std::vector<DiscChoice> unique;
  std::vector<std::vector<std::size_t>> seen;
  for (const DiscChoice& c : choices) {
    const std::size_t ua = static_cast<std::size_t>(c.a);
    const std::size_t ub = static_cast<std::size_t>(c.b);
    std::vector<std::size_t> corners{c.start % len, (c.start + ua) % len, (c.start + ua + ub) % len,
                                     (c.start + 2 * ua + ub) % len};
    std::sort(corners.begin(), corners.end());
    if (std::find(seen.begin(), seen.end(), corners) != seen.end()) continue;
    seen.push_back(corners);
    unique.push_back(c);
  }
  // O-grid discs come after every plain grid: measured, their ring loops make the weave add
  // pillow layers on both copies of the disc (torus_tf_coarse: 306 hexes, min scaled Jacobian
  // 0.18, against 108 and 0.48 with the plain 3 x 3 grid).
  const std::size_t plain = unique.size();
  for (std::size_t k = 0; k < plain; ++k) {
    DiscChoice ring = unique[k];
    ring.ring = true;
    unique.push_back(ring);
  }
  return unique;
}

/// Per edge p of `cycle` (from cycle[p] to cycle[p + 1]), the loop of `loops` crossing it.
std::vector<LoopId> crossing_loops(const stc::QuadSurface& surface, const stc::LoopSet& loops,
                                   const std::vector<NodeId>& cycle) {
  const std::size_t len = cycle.size();
  std::map<std::pair<NodeId, NodeId>, std::pair<std::size_t, int>> side_of;
  for (std::size_t q = 0; q < surface.num_quads(); ++q) {
    for (int i = 0; i < 4; ++i) {
      side_of[{surface.quads[q][static_cast<std::size_t>(i)],
               surface.quads[q][static_cast<std::size_t>((i + 1) % 4)]}] = {q, i};
    }
  }
  std::vector<LoopId> out(len, LoopId::invalid());
  for (std::size_t p = 0; p < len; ++p) {
    const auto it = side_of.find({cycle[p], cycle[(p + 1) % len]});
    if (it == side_of.end()) continue;
    out[p] = loops.quad_loops[it->second.first][static_cast<std::size_t>(it->second.second % 2)];
  }
  return out;
}

/// Pairings of the cycle's edges that follow the loops crossing it, so that a loop's pieces
/// on the two sides of the cut close up across the disc instead of merging with a loop they
/// cross (the merged loop would cross itself). A depth-first search over perfect matchings:
/// the lowest unpaired edge is paired with, in order, an edge crossed by the same loop, then
/// one crossed by a loop that does not cross its own loop, nearest along the cycle first;
/// never two adjacent edges (that chord would cross no other: no disc). At most `wanted`
/// pairings, fewest disc quads first.
std::vector<DiscChoice> loop_following_choices(const std::vector<LoopId>& crossing,
                                               const stc::LoopSet& loops, std::size_t wanted = 4) {
  const std::size_t len = crossing.size();
  if (len < 4 ||
      std::any_of(crossing.begin(), crossing.end(), [](LoopId l) { return !l.is_valid(); }))
    return {};
  const auto cross = [&](LoopId x, LoopId y) {
    const stc::Loop& lx = loops.loops[x.index()];
    return std::any_of(lx.crossings.begin(), lx.crossings.end(),
                       [&](const stc::LoopCrossing& c) { return c.other == y; });
  };
  const auto adjacent = [&](std::size_t x, std::size_t y) {
    return (x + 1) % len == y || (y + 1) % len == x;
  };
  std::vector<DiscChoice> out;
  std::vector<std::size_t> partner(len, kNoPartner);
  std::size_t budget = 20000;
  const std::function<void()> search = [&]() {
    if (out.size() >= wanted || budget == 0) return;
    --budget;
    const auto first = std::find(partner.begin(), partner.end(), kNoPartner);
    if (first == partner.end()) {
      // Realisable: every chord crosses another, and the arrangement makes a disc.
      if (!chord_disc(std::vector<Eigen::RowVector3d>(len, Eigen::RowVector3d::Zero()), partner))
        return;
      DiscChoice c;
      c.partner = partner;
      c.quads = chord_crossings(partner);
      out.push_back(std::move(c));
      return;
    }
    const std::size_t p = static_cast<std::size_t>(first - partner.begin());
    std::vector<std::tuple<int, std::size_t, std::size_t>> options;  // (cost, distance, q)
    for (std::size_t q = p + 1; q < len; ++q) {
      if (partner[q] != kNoPartner || adjacent(p, q)) continue;
      int cost = 0;
      if (crossing[q] != crossing[p]) {
        if (cross(crossing[p], crossing[q])) continue;
        cost = 1;
      }
      options.emplace_back(cost, std::min(q - p, len - (q - p)), q);
    }
    std::sort(options.begin(), options.end());
    for (const auto& [cost, distance, q] : options) {
      partner[p] = q;
      partner[q] = p;
      search();
      partner[p] = kNoPartner;
      partner[q] = kNoPartner;
      if (out.size() >= wanted || budget == 0) return;
    }
  };
  search();
  std::stable_sort(out.begin(), out.end(),
                   [](const DiscChoice& x, const DiscChoice& y) { return x.quads < y.quads; });
  return out;
}

/// "3x3", "3x3 O-grid" or "loop-following (14 quads)".
std::string disc_name(const DiscChoice& c) {
  if (!c.partner.empty()) return "loop-following (" + std::to_string(c.quads) + " quads)";
  return std::to_string(c.a) + "x" + std::to_string(c.b) + (c.ring ? " O-grid" : "");
}

/// A surface being cut: quads and points over its own node ids, and per node the id of the
/// final mesh node it stands for.
struct CutSurface {
  SurfaceMesh mesh;
  std::vector<NodeId> final_id;
};

/// Per node of `cycle` (a simple cycle of `surface`'s edges), the quads on its + side: the
/// quad traversing the outgoing cycle edge forward, and the fan from it round the node to the
/// incoming cycle edge.
std::vector<std::vector<std::size_t>> plus_fans(const stc::QuadSurface& surface,
                                                const std::vector<NodeId>& cycle) {
  const stc::SurfaceTopology topo = stc::surface_topology(surface);
  const std::size_t len = cycle.size();
  const std::size_t n = surface.num_nodes;
  std::vector<std::size_t> position(n, static_cast<std::size_t>(-1));
  for (std::size_t k = 0; k < len; ++k) position[cycle[k].index()] = k;
  const auto is_cycle_edge = [&](NodeId x, NodeId y) {
    const std::size_t px = position[x.index()];
    const std::size_t py = position[y.index()];
    if (px == static_cast<std::size_t>(-1) || py == static_cast<std::size_t>(-1)) return false;
    return (px + 1) % len == py || (py + 1) % len == px;
  };
  // Per cycle node, the quads on the + side (those traversing the outgoing cycle edge
  // forward, and the fan from there to the incoming cycle edge).
  std::vector<std::vector<std::size_t>> plus(len);
  for (std::size_t k = 0; k < len; ++k) {
    const NodeId v = cycle[k];
    const NodeId next = cycle[(k + 1) % len];
    std::size_t quad = static_cast<std::size_t>(-1);
    int side = -1;
    for (std::size_t q = 0; q < surface.num_quads() && side < 0; ++q) {
      for (int i = 0; i < 4; ++i) {
        if (surface.quads[q][static_cast<std::size_t>(i)] == v &&
            surface.quads[q][static_cast<std::size_t>((i + 1) % 4)] == next) {
          quad = q;
          side = i;
          break;
        }
      }
    }
    if (side < 0)
      throw InternalError("cut: cycle edge " + v.str() + "-" + next.str() + " is not an edge");
    for (std::size_t guard = 0; guard <= surface.num_quads(); ++guard) {
      plus[k].push_back(quad);
      // The other side of `quad` at v ends at v: side (i-1), from q[i-1] to v.
      const int back = (side + 3) % 4;
      const stc::Quad& qq = surface.quads[quad];
      if (is_cycle_edge(qq[static_cast<std::size_t>(back)], v)) break;
      const stc::QuadSide across = topo.neighbour(stc::QuadSide{QuadId(quad), back});
      quad = across.quad.index();
      // In the neighbour, v starts side `across.side`.
      side = across.side;
    }
  }
  return plus;
}

/// The grid (or O-grid) disc of `choice`, its walk positions counted from `choice.start`.
Disc grid_disc(const CutSurface& s, const std::vector<NodeId>& cycle, const DiscChoice& choice) {
  const std::size_t len = cycle.size();
  // The disc over its own ids: a grid (a+1) x (b+1), node (i, j) at i + (a+1) j, whose
  // boundary walk (0,0) -> (a,0) -> (a,b) -> (0,b) -> (0,0) follows the cycle from `start`;
  // with a ring, that grid is an inner block and one layer of quads joins its boundary to the
  // cycle (an O-grid).
  const std::size_t a = static_cast<std::size_t>(choice.a);
  const std::size_t b = static_cast<std::size_t>(choice.b);
  const std::size_t grid = (a + 1) * (b + 1);
  const auto gid = [&](std::size_t i, std::size_t j) { return i + (a + 1) * j; };
  std::vector<std::size_t> walk_node(len);  // grid node at each walk position
  for (std::size_t i = 0; i < a; ++i) walk_node[i] = gid(i, 0);
  for (std::size_t j = 0; j < b; ++j) walk_node[a + j] = gid(a, j);
  for (std::size_t i = a; i > 0; --i) walk_node[a + b + (a - i)] = gid(i, b);
  for (std::size_t j = b; j > 0; --j) walk_node[2 * a + b + (b - j)] = gid(0, j);
  const auto cycle_at = [&](std::size_t p) { return (choice.start + p) % len; };
  std::vector<Eigen::RowVector3d> grid_pos(grid);
  std::vector<std::size_t> walk_of(grid, static_cast<std::size_t>(-1));
  for (std::size_t p = 0; p < len; ++p) {
    walk_of[walk_node[p]] = p;
    grid_pos[walk_node[p]] = s.mesh.points.row(cycle[cycle_at(p)].value());
  }
  const auto bp = [&](std::size_t i, std::size_t j) { return grid_pos[gid(i, j)]; };
  for (std::size_t j = 1; j < b; ++j) {
    for (std::size_t i = 1; i < a; ++i) {
      const double u = static_cast<double>(i) / static_cast<double>(a);
      const double w = static_cast<double>(j) / static_cast<double>(b);
      grid_pos[gid(i, j)] = (1 - w) * bp(i, 0) + w * bp(i, b) + (1 - u) * bp(0, j) + u * bp(a, j) -
                            ((1 - u) * (1 - w) * bp(0, 0) + u * (1 - w) * bp(a, 0) +
                             (1 - u) * w * bp(0, b) + u * w * bp(a, b));
    }
  }
  // Disc nodes: boundary ones are walk positions, the others interior.
  Disc disc;
  std::vector<std::size_t> grid_disc(grid);
  if (!choice.ring) {
    for (std::size_t g = 0; g < grid; ++g) {
      grid_disc[g] = disc.walk.size();
      disc.walk.push_back(walk_of[g] == static_cast<std::size_t>(-1)
                              ? std::nullopt
                              : std::optional<std::size_t>(walk_of[g]));
      disc.positions.push_back(grid_pos[g]);
    }
  } else {
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (std::size_t p = 0; p < len; ++p) centre += grid_pos[walk_node[p]];
    centre /= static_cast<double>(len);
    std::vector<std::size_t> rim(len);
    for (std::size_t p = 0; p < len; ++p) {
      rim[p] = disc.walk.size();
      disc.walk.emplace_back(p);
      disc.positions.push_back(grid_pos[walk_node[p]]);
    }
    for (std::size_t g = 0; g < grid; ++g) {
      grid_disc[g] = disc.walk.size();
      disc.walk.emplace_back(std::nullopt);
      disc.positions.push_back(centre + kRingShrink * (grid_pos[g] - centre));
    }
    for (std::size_t p = 0; p < len; ++p) {
      const std::size_t p1 = (p + 1) % len;
      disc.quads.push_back({rim[p], rim[p1], grid_disc[walk_node[p1]], grid_disc[walk_node[p]]});
    }
  }
  for (std::size_t j = 0; j < b; ++j) {
    for (std::size_t i = 0; i < a; ++i) {
      disc.quads.push_back({grid_disc[gid(i, j)], grid_disc[gid(i + 1, j)],
                            grid_disc[gid(i + 1, j + 1)], grid_disc[gid(i, j + 1)]});
    }
  }
  return disc;
}

/// The cut of `s` along `cycle` (node ids of `s`, a simple cycle) with `disc`, whose walk
/// position p stands for cycle position (start + p) mod L: the cycle's nodes are duplicated
/// (the quads on the + side take the copies) and the disc added once facing each side. New
/// disc interior nodes get final ids from `*next_final` on.
CutSurface cut_along(const CutSurface& s, const std::vector<NodeId>& cycle, std::size_t start,
                     const Disc& disc, std::size_t* next_final) {
  const stc::QuadSurface& surface = s.mesh.surface;
  const std::size_t len = cycle.size();
  const std::size_t n = surface.num_nodes;
  const std::vector<std::vector<std::size_t>> plus = plus_fans(surface, cycle);
  const auto cycle_at = [&](std::size_t p) { return (start + p) % len; };
  std::vector<std::size_t> interior_index(disc.walk.size(), 0);
  std::size_t interior = 0;
  for (std::size_t d = 0; d < disc.walk.size(); ++d)
    if (!disc.walk[d]) interior_index[d] = interior++;

  CutSurface out;
  const std::size_t n_new = n + len + 2 * interior;
  out.mesh.points.resize(static_cast<Eigen::Index>(n_new), 3);
  out.mesh.points.topRows(static_cast<Eigen::Index>(n)) =
      s.mesh.points.topRows(static_cast<Eigen::Index>(n));
  out.final_id = s.final_id;
  out.final_id.resize(n_new);
  for (std::size_t k = 0; k < len; ++k) {
    out.mesh.points.row(static_cast<Eigen::Index>(n + k)) = s.mesh.points.row(cycle[k].value());
    out.final_id[n + k] = s.final_id[cycle[k].index()];
  }
  out.mesh.surface.quads = surface.quads;
  for (std::size_t k = 0; k < len; ++k) {
    for (std::size_t q : plus[k]) {
      for (NodeId& v : out.mesh.surface.quads[q]) {
        if (v == cycle[k]) v = NodeId(n + k);
      }
    }
  }
  // Minus copy: the cycle's own ids; plus copy: n + k; interior: minus at n + len + t, plus
  // at n + len + interior + t, both standing for one new final node.
  const auto node_minus = [&](std::size_t d) {
    if (disc.walk[d]) return cycle[cycle_at(*disc.walk[d])];
    return NodeId(n + len + interior_index[d]);
  };
  const auto node_plus = [&](std::size_t d) {
    if (disc.walk[d]) return NodeId(n + cycle_at(*disc.walk[d]));
    return NodeId(n + len + interior + interior_index[d]);
  };
  for (std::size_t d = 0; d < disc.walk.size(); ++d) {
    if (disc.walk[d]) continue;
    const NodeId m = node_minus(d);
    const NodeId pl = node_plus(d);
    out.mesh.points.row(m.value()) = disc.positions[d];
    out.mesh.points.row(pl.value()) = disc.positions[d];
    const NodeId f((*next_final)++);
    out.final_id[m.index()] = f;
    out.final_id[pl.index()] = f;
  }
  for (const auto& q : disc.quads) {
    // Minus copy: traverses the cycle forward; plus copy: reversed.
    out.mesh.surface.quads.push_back(
        {node_minus(q[0]), node_minus(q[1]), node_minus(q[2]), node_minus(q[3])});
    out.mesh.surface.quads.push_back(
        {node_plus(q[0]), node_plus(q[3]), node_plus(q[2]), node_plus(q[1])});
  }
  out.mesh.surface.num_nodes = n_new;
  return out;
}

/// The woven STC of a complex: face neighbours by matching faces, boundary faces by matching
/// the quads of `boundary`.
std::vector<std::array<weave::DualLink, 6>> dual_of(const stc::HexComplex& complex,
                                                    const stc::QuadSurface& boundary) {
  std::map<std::array<NodeId, 4>, std::vector<std::pair<std::int32_t, std::int8_t>>> faces;
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (int f = 0; f < 6; ++f) {
      stc::Quad q = stc::hex_face(complex.hexes[h], f);
      std::sort(q.begin(), q.end());
      faces[q].emplace_back(static_cast<std::int32_t>(h), static_cast<std::int8_t>(f));
    }
  }
  std::map<std::array<NodeId, 4>, std::int32_t> quads;
  for (std::size_t q = 0; q < boundary.quads.size(); ++q) {
    stc::Quad k = boundary.quads[q];
    std::sort(k.begin(), k.end());
    quads[k] = static_cast<std::int32_t>(q);
  }
  std::vector<std::array<weave::DualLink, 6>> dual(complex.hexes.size());
  for (const auto& [key, uses] : faces) {
    if (uses.size() == 2) {
      for (int s = 0; s < 2; ++s) {
        const auto& me = uses[static_cast<std::size_t>(s)];
        const auto& other = uses[static_cast<std::size_t>(1 - s)];
        dual[static_cast<std::size_t>(me.first)][static_cast<std::size_t>(me.second)] =
            weave::DualLink{false, other.first, other.second};
      }
    } else if (uses.size() == 1) {
      const auto it = quads.find(key);
      if (it != quads.end()) {
        dual[static_cast<std::size_t>(uses[0].first)][static_cast<std::size_t>(uses[0].second)] =
            weave::DualLink{true, it->second, -1};
      }
    }
  }
  return dual;
}

/// A woven ball mapped to final ids.
struct BallWeave {
  weave::WeaveResult woven;
  std::vector<stc::Hex> hexes;  ///< over final ids (interior nodes from the given offset)
  std::size_t interior = 0;
};

/// `attached`: hexes on nodes of `s` put on its front before the weave (`weave_attached`;
/// then `cut_options.ball_weaver` is not used: the solids that have them are loop-clean).
BallWeave weave_ball(const CutSurface& s, const weave::WeaveOptions& options,
                     std::size_t first_interior, const CutOptions& cut_options,
                     const std::vector<stc::Hex>& attached = {}) {
  BallWeave out;
  if (cut_options.ball_weaver && attached.empty()) {
    out.woven = cut_options.ball_weaver(s.mesh, options);
  } else {
    const std::vector<std::array<double, 4>> angles = options.rules == weave::RuleSet::Extended
                                                          ? dihedral_angles(s.mesh)
                                                          : std::vector<std::array<double, 4>>{};
    if (attached.empty()) {
      out.woven = weave::weave(s.mesh.surface, options, angles);
    } else {
      stc::HexComplex hexes;
      hexes.hexes = attached;
      hexes.num_nodes = s.mesh.surface.num_nodes;
      out.woven = weave::weave_attached(s.mesh.surface, hexes, options, angles);
    }
  }
  const std::size_t inputs = out.woven.num_input_nodes;
  out.interior = out.woven.complex.num_nodes - inputs;
  for (const stc::Hex& h : out.woven.complex.hexes) {
    stc::Hex m{};
    for (std::size_t i = 0; i < 8; ++i) {
      m[i] = h[i].index() < inputs ? s.final_id[h[i].index()]
                                   : NodeId(first_interior + (h[i].index() - inputs));
    }
    out.hexes.push_back(m);
  }
  return out;
}

/// The number of quads of `s` where a loop crosses itself.
std::size_t self_crossing_quads_of(const CutSurface& s) {
  return stc::find_loops(s.mesh.surface, stc::FindLoopsOptions{false}).num_self_crossing_quads();
}

void add_stats(weave::WeaveStats& sum, const weave::WeaveStats& s) {
  sum.selections += s.selections;
  sum.shrinks += s.shrinks;
  sum.failed_shrinks += s.failed_shrinks;
  sum.seams += s.seams;
  sum.coincident_glues += s.coincident_glues;
  sum.crosses += s.crosses;
  sum.blind_chords += s.blind_chords;
  sum.blocked_seams += s.blocked_seams;
  sum.relaxed_preconditions += s.relaxed_preconditions;
  sum.parallel_merges += s.parallel_merges;
  sum.nonconvexity_seams += s.nonconvexity_seams;
  sum.rolled_back_shrinks += s.rolled_back_shrinks;
  sum.front_pillows += s.front_pillows;
  sum.recoveries += s.recoveries;
  sum.recovery_trials += s.recovery_trials;
  sum.seam_undo_retries += s.seam_undo_retries;
  sum.fill_hexes += s.fill_hexes;
  sum.reliable_from_start += s.reliable_from_start;
}

/// The glued complex of `hexes` (over final ids, `num_nodes` final nodes) checked by
/// `stc::validate_hex_complex`: empty when valid, else the summary of what it breaks.
std::string glue_problem(const std::vector<stc::Hex>& hexes, std::size_t num_nodes,
                         SolidsReport& rep) {
  const auto t = std::chrono::steady_clock::now();
  stc::HexComplex glued;
  glued.hexes = hexes;
  glued.num_nodes = num_nodes;
  const stc::ValidationReport v = stc::validate_hex_complex(glued);
  rep.glue_seconds += seconds_since(t);
  return v.valid ? std::string() : v.summary();
}

/// Appends a woven (and glued) ball to `result`: hexes, their shrink, rule and node records
/// (nodes in the ball weave's numbering), its shrink records, the weave's statistics and its
/// trace (hex ids shifted). Each ball numbers its shrinks from 0: they are shifted past those
/// already in `result`, so that every shrink keeps its own record (its depth, its loop).
void append_ball(weave::WeaveResult& result, const BallWeave& ball) {
  const std::size_t hex_offset = result.complex.hexes.size();
  std::int32_t shrink_offset = 0;
  for (std::int32_t sh : result.hex_shrink) shrink_offset = std::max(shrink_offset, sh + 1);
  for (const weave::ShrinkRecord& r : result.shrinks)
    shrink_offset = std::max(shrink_offset, r.shrink + 1);
  for (const weave::TraceEvent& e : result.trace)
    shrink_offset = std::max(shrink_offset, e.shrink + 1);
  const auto shifted = [&](std::int32_t sh) { return sh >= 0 ? sh + shrink_offset : sh; };
  for (const stc::Hex& h : ball.hexes) result.complex.hexes.push_back(h);
  for (std::int32_t sh : ball.woven.hex_shrink) result.hex_shrink.push_back(shifted(sh));
  for (const std::string& r : ball.woven.hex_rule) result.hex_rule.push_back(r);
  result.hex_node.resize(hex_offset, NodeId::invalid());
  result.hex_node.insert(result.hex_node.end(), ball.woven.hex_node.begin(),
                         ball.woven.hex_node.end());
  result.hex_node.resize(result.complex.hexes.size(), NodeId::invalid());
  for (weave::ShrinkRecord r : ball.woven.shrinks) {
    r.shrink = shifted(r.shrink);
    weave::file_shrink_record(result.shrinks, std::move(r));
  }
  add_stats(result.stats, ball.woven.stats);
  result.recoveries.insert(result.recoveries.end(), ball.woven.recoveries.begin(),
                           ball.woven.recoveries.end());
  for (weave::TraceEvent e : ball.woven.trace) {
    if (e.hex.is_valid()) e.hex = HexId(e.hex.index() + hex_offset);
    e.shrink = shifted(e.shrink);
    result.trace.push_back(std::move(e));
  }
}

/// The cut of `s` along an annulus of one layer of quads between two node-disjoint cycles of
/// equal length on different shells: quad p = (outer[p], outer[p+1], inner[p+1], inner[p]).
/// Both cycles' nodes are duplicated and the annulus added once facing each side; no new
/// interior node.
CutSurface cut_annulus(const CutSurface& s, const std::vector<NodeId>& outer,
                       const std::vector<NodeId>& inner) {
  const stc::QuadSurface& surface = s.mesh.surface;
  const std::size_t len = outer.size();
  const std::size_t n = surface.num_nodes;
  // The annulus traverses the outer cycle forward and the inner one backward.
  std::vector<NodeId> inner_forward(inner.rbegin(), inner.rend());
  const auto plus_outer = plus_fans(surface, outer);
  const auto plus_inner = plus_fans(surface, inner_forward);
  CutSurface out;
  out.mesh.points.resize(static_cast<Eigen::Index>(n + 2 * len), 3);
  out.mesh.points.topRows(static_cast<Eigen::Index>(n)) =
      s.mesh.points.topRows(static_cast<Eigen::Index>(n));
  out.final_id = s.final_id;
  out.final_id.resize(n + 2 * len);
  std::vector<NodeId> copy(n, NodeId::invalid());
  for (std::size_t k = 0; k < len; ++k) {
    copy[outer[k].index()] = NodeId(n + k);
    copy[inner[k].index()] = NodeId(n + len + k);
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (!copy[v].is_valid()) continue;
    out.mesh.points.row(copy[v].value()) = s.mesh.points.row(static_cast<Eigen::Index>(v));
    out.final_id[copy[v].index()] = s.final_id[v];
  }
  out.mesh.surface.quads = surface.quads;
  const auto apply = [&](const std::vector<NodeId>& cycle,
                         const std::vector<std::vector<std::size_t>>& plus) {
    for (std::size_t k = 0; k < cycle.size(); ++k) {
      for (std::size_t q : plus[k]) {
        for (NodeId& v : out.mesh.surface.quads[q]) {
          if (v == cycle[k]) v = copy[cycle[k].index()];
        }
      }
    }
  };
  apply(outer, plus_outer);
  apply(inner_forward, plus_inner);
  for (std::size_t p = 0; p < len; ++p) {
    const std::size_t p1 = (p + 1) % len;
    out.mesh.surface.quads.push_back({outer[p], outer[p1], inner[p1], inner[p]});
    out.mesh.surface.quads.push_back({copy[outer[p].index()], copy[inner[p].index()],
                                      copy[inner[p1].index()], copy[outer[p1].index()]});
  }
  out.mesh.surface.num_nodes = n + 2 * len;
  return out;
}

/// Disc choices tried per rail by the slab route.
constexpr std::size_t kSlabChoices = 8;
/// Weaves of slab balls per solid by the slab route.
constexpr std::size_t kSlabWeaves = 60;

/// A band of quads between a handle cycle and a second cycle of its class (slab_band.hpp).
using Band = SlabBand;
/// Far bands (`far_bands`) tried per handle by the slab route before the band beside the
/// cycle.
constexpr std::size_t kFarBands = 3;

/// The band of `cycle` on `surface`: none when the quads touching the cycle on its minus side
/// do not make an annulus whose other boundary is one simple cycle off the cycle.
std::optional<Band> band_of(const stc::QuadSurface& surface, const std::vector<NodeId>& cycle) {
  const std::vector<std::vector<std::size_t>> plus = plus_fans(surface, cycle);
  std::vector<char> on_cycle(surface.num_nodes, 0);
  for (NodeId v : cycle) on_cycle[v.index()] = 1;
  std::vector<char> is_plus(surface.num_quads(), 0);
  for (const auto& fan : plus)
    for (std::size_t q : fan) is_plus[q] = 1;
  Band band;
  for (std::size_t q = 0; q < surface.num_quads(); ++q) {
    const stc::Quad& quad = surface.quads[q];
    if (std::none_of(quad.begin(), quad.end(), [&](NodeId v) { return on_cycle[v.index()] != 0; }))
      continue;
    if (is_plus[q] != 0) {
      // A plus quad is one on the minus side too when it touches the cycle elsewhere.
      continue;
    }
    band.quads.push_back(q);
  }
  std::set<std::pair<NodeId, NodeId>> sides;
  for (std::size_t q : band.quads)
    for (std::size_t i = 0; i < 4; ++i)
      sides.emplace(surface.quads[q][i], surface.quads[q][(i + 1) % 4]);
  std::map<NodeId, NodeId> next;
  for (const auto& [x, y] : sides) {
    if (sides.count({y, x}) != 0) continue;
    if (on_cycle[x.index()] != 0 && on_cycle[y.index()] != 0) continue;  // a cycle edge
    if (on_cycle[x.index()] != 0 || on_cycle[y.index()] != 0) return std::nullopt;
    if (!next.emplace(x, y).second) return std::nullopt;  // pinched
  }
  if (next.size() < 4) return std::nullopt;
  NodeId v = next.begin()->first;
  for (std::size_t k = 0; k < next.size(); ++k) {
    band.outer.push_back(v);
    const auto it = next.find(v);
    if (it == next.end()) return std::nullopt;
    v = it->second;
  }
  if (v != band.outer.front()) return std::nullopt;
  std::vector<NodeId> sorted = band.outer;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return std::nullopt;
  // Every cycle edge must be traversed backward by a band quad (the band lies on the minus
  // side all along).
  for (std::size_t k = 0; k < cycle.size(); ++k)
    if (sides.count({cycle[(k + 1) % cycle.size()], cycle[k]}) == 0) return std::nullopt;
  return band;
}

/// The disc of `choice` spanning `rail` (a cycle of `s`): a grid, an O-grid or a chord disc.
std::optional<Disc> disc_on(const CutSurface& s, const std::vector<NodeId>& rail,
                            const DiscChoice& choice) {
  if (choice.partner.empty()) return grid_disc(s, rail, choice);
  std::vector<Eigen::RowVector3d> points;
  points.reserve(rail.size());
  for (NodeId v : rail) points.emplace_back(s.mesh.points.row(v.value()));
  return chord_disc(points, choice.partner);
}

/// Disc choices for `rail` on `s`: loop-following chord discs, then grids, then O-grids; at
/// most kSlabChoices.
std::vector<DiscChoice> rail_choices(const CutSurface& s, const std::vector<NodeId>& rail) {
  std::vector<DiscChoice> choices = disc_choices(s.mesh.points, rail);
  const stc::LoopSet loops = stc::find_loops(s.mesh.surface, stc::FindLoopsOptions{false});
  std::vector<DiscChoice> follow =
      loop_following_choices(crossing_loops(s.mesh.surface, loops, rail), loops);
  choices.insert(choices.begin(), follow.begin(), follow.end());
  if (choices.size() > kSlabChoices) choices.resize(kSlabChoices);
  return choices;
}

/// `s` with its unused nodes dropped; `*renumber` maps old ids to new (invalid: dropped).
CutSurface compacted(const CutSurface& s, std::vector<NodeId>* renumber) {
  std::vector<NodeId>& map = *renumber;
  map.assign(s.mesh.surface.num_nodes, NodeId::invalid());
  for (const stc::Quad& q : s.mesh.surface.quads)
    for (NodeId v : q) map[v.index()] = NodeId(0);
  CutSurface out;
  for (std::size_t v = 0; v < map.size(); ++v) {
    if (!map[v].is_valid()) continue;
    map[v] = NodeId(out.final_id.size());
    out.final_id.push_back(s.final_id[v]);
  }
  out.mesh.points.resize(static_cast<Eigen::Index>(out.final_id.size()), 3);
  for (std::size_t v = 0; v < map.size(); ++v)
    if (map[v].is_valid())
      out.mesh.points.row(map[v].value()) = s.mesh.points.row(static_cast<Eigen::Index>(v));
  for (stc::Quad q : s.mesh.surface.quads) {
    for (NodeId& v : q) v = map[v.index()];
    out.mesh.surface.quads.push_back(q);
  }
  out.mesh.surface.num_nodes = out.final_id.size();
  return out;
}

/// A slab cut of a handle: the rest of the solid and the slab, two surfaces over their own
/// node ids (final ids in `final_id`).
struct SlabCut {
  CutSurface rest;
  CutSurface slab;
  std::vector<NodeId> rest_renumber;  ///< node of the surface cut -> node of `rest`
};

/// The cut of `s` along discs on both boundaries of `band` (`cycle` and `band.outer`): the
/// slab is the band closed by the two discs, the rest is `s` without the band, closed by the
/// same two discs facing the other way. The discs' interior nodes are new final nodes (from
/// `*next_final` on), each one node shared by the slab and the rest: nothing is identified
/// at the glue. None when a disc choice has no disc.
std::optional<SlabCut> cut_slab(const CutSurface& s, const std::vector<NodeId>& cycle,
                                const Band& band, const DiscChoice& inner_choice,
                                const DiscChoice& outer_choice, std::size_t* next_final) {
  const std::optional<Disc> di = disc_on(s, cycle, inner_choice);
  const std::optional<Disc> dout = disc_on(s, band.outer, outer_choice);
  if (!di || !dout) return std::nullopt;
  const stc::QuadSurface& surface = s.mesh.surface;
  const std::size_t n = surface.num_nodes;
  CutSurface all;  // both discs' nodes added to s
  std::size_t interior = 0;
  for (const auto& w : di->walk) interior += w ? 0 : 1;
  for (const auto& w : dout->walk) interior += w ? 0 : 1;
  all.mesh.points.resize(static_cast<Eigen::Index>(n + interior), 3);
  all.mesh.points.topRows(static_cast<Eigen::Index>(n)) =
      s.mesh.points.topRows(static_cast<Eigen::Index>(n));
  all.final_id = s.final_id;
  all.final_id.resize(n + interior);
  std::size_t t = n;
  const auto place = [&](const Disc& d, const std::vector<NodeId>& rail, std::size_t start) {
    std::vector<NodeId> node(d.walk.size());
    for (std::size_t k = 0; k < d.walk.size(); ++k) {
      if (d.walk[k]) {
        node[k] = rail[(start + *d.walk[k]) % rail.size()];
        continue;
      }
      node[k] = NodeId(t);
      all.mesh.points.row(static_cast<Eigen::Index>(t)) = d.positions[k];
      all.final_id[t] = NodeId((*next_final)++);
      ++t;
    }
    return node;
  };
  const std::vector<NodeId> ni = place(*di, cycle, inner_choice.start);
  const std::vector<NodeId> no = place(*dout, band.outer, outer_choice.start);
  all.mesh.surface.num_nodes = n + interior;
  CutSurface rest = all;
  CutSurface slab = all;
  std::vector<char> in_band(surface.num_quads(), 0);
  for (std::size_t q : band.quads) in_band[q] = 1;
  for (std::size_t q = 0; q < surface.num_quads(); ++q)
    (in_band[q] != 0 ? slab : rest).mesh.surface.quads.push_back(surface.quads[q]);
  // The disc on the cycle: forward (walk p to p + 1) in the slab, reversed in the rest; the
  // disc on the outer cycle the other way round.
  for (const auto& q : di->quads) {
    slab.mesh.surface.quads.push_back({ni[q[0]], ni[q[1]], ni[q[2]], ni[q[3]]});
    rest.mesh.surface.quads.push_back({ni[q[0]], ni[q[3]], ni[q[2]], ni[q[1]]});
  }
  for (const auto& q : dout->quads) {
    rest.mesh.surface.quads.push_back({no[q[0]], no[q[1]], no[q[2]], no[q[3]]});
    slab.mesh.surface.quads.push_back({no[q[0]], no[q[3]], no[q[2]], no[q[1]]});
  }
  SlabCut out;
  std::vector<NodeId> unused;
  out.slab = compacted(slab, &unused);
  out.rest = compacted(rest, &out.rest_renumber);
  return out;
}

/// What the slab route kept: the woven rest, the slabs' hexes, the next free final id.
struct SlabRoute {
  BallWeave ball;
  std::vector<BallWeave> slabs;
  std::size_t next_final = 0;
  std::vector<HandleCut> cuts;
};

/// Whether the surface of `s` has one component of genus `genus` and no self-intersecting
/// loop.
bool clean_of_genus(const CutSurface& s, int genus) {
  const stc::SurfaceTopology topo = stc::surface_topology(s.mesh.surface);
  if (topo.components.size() != 1 || topo.components[0].genus != genus) return false;
  return stc::find_loops(s.mesh.surface, topo, stc::FindLoopsOptions{false})
             .num_self_intersecting() == 0;
}

/// The slab route for a solid whose handle cycles are `sets[0]` (or one of the other sets):
/// handle by handle, the band of quads beside the cycle, closed by a disc on each of its two
/// boundary cycles, is woven as a ball of its own (the slab), and the rest of the solid,
/// closed by the same discs, loses the handle; the last rest is woven as a ball. Every piece
/// is glued to the others by node ids alone (docs/topology.md, "Slabs"). None when no choice
/// within the budgets gives a valid complex; `*why` then says what was tried.
std::optional<SlabRoute> slab_route(const CutSurface& solid,
                                    const std::vector<std::vector<std::vector<NodeId>>>& sets,
                                    const std::vector<weave::WeaveOptions>& chain,
                                    const CutOptions& cut_options, std::size_t first_final,
                                    SolidsReport& rep, std::string* why) {
  std::size_t loop_checks = 0;
  std::size_t weaves = 0;
  std::size_t no_band = 0;
  std::string failures;
  std::optional<SlabRoute> found;
  std::vector<std::vector<NodeId>> cycles;
  std::vector<HandleCut> cuts;
  std::vector<BallWeave> slabs;
  const auto out_of_budget = [&]() {
    return weaves >= kSlabWeaves || loop_checks >= cut_options.max_loop_checks;
  };
  const auto note = [&](const std::string& what) {
    if (failures.size() < 400) failures += "; " + what;
  };
  // The first weave of `chain` that completes; none when every one blocks.
  const auto weave_first = [&](const CutSurface& s, std::size_t first) -> std::optional<BallWeave> {
    ++weaves;
    for (const weave::WeaveOptions& attempt : chain) {
      const auto t1 = std::chrono::steady_clock::now();
      try {
        BallWeave w = weave_ball(s, attempt, first, cut_options);
        rep.weave_seconds += seconds_since(t1);
        return w;
      } catch (const WeaveError& e) {
        rep.weave_seconds += seconds_since(t1);
        note(std::string("slab weave blocked: ") + std::string(e.what()).substr(0, 60));
      } catch (const InvalidInput& e) {
        rep.weave_seconds += seconds_since(t1);
        note(std::string("slab cut refused by the weave: ") + std::string(e.what()).substr(0, 60));
      }
    }
    return std::nullopt;
  };
  const std::function<bool(const CutSurface&, std::size_t, std::size_t)> cut_from =
      [&](const CutSurface& current, std::size_t k, std::size_t final_start) -> bool {
    if (out_of_budget()) return false;
    auto t1 = std::chrono::steady_clock::now();
    // The bands to a far partner cycle first (both pieces thick), then the band beside it.
    std::vector<Band> bands = far_bands(current.mesh.surface, cycles[k], kFarBands);
    if (std::optional<Band> beside = band_of(current.mesh.surface, cycles[k]))
      bands.push_back(std::move(*beside));
    if (bands.empty()) {
      rep.cut_seconds += seconds_since(t1);
      ++no_band;
      return false;
    }
    const std::vector<DiscChoice> inner = rail_choices(current, cycles[k]);
    rep.cut_seconds += seconds_since(t1);
    HandleCut& hc = cuts[k];
    hc.cycle.clear();
    for (NodeId v : cycles[k]) hc.cycle.push_back(current.final_id[v.index()]);
    const int genus_after = static_cast<int>(cycles.size() - k - 1);
    for (const Band& band_k : bands) {
      const Band* band = &band_k;
      t1 = std::chrono::steady_clock::now();
      const std::vector<DiscChoice> outer = rail_choices(current, band->outer);
      rep.cut_seconds += seconds_since(t1);
      for (const DiscChoice& ci : inner) {
        for (const DiscChoice& co : outer) {
          if (out_of_budget()) return false;
          ++hc.attempts;
          t1 = std::chrono::steady_clock::now();
          std::size_t trial_final = final_start;
          std::optional<SlabCut> cut = cut_slab(current, cycles[k], *band, ci, co, &trial_final);
          if (!cut) {
            rep.cut_seconds += seconds_since(t1);
            continue;
          }
          ++loop_checks;
          const bool clean = clean_of_genus(cut->slab, 0) && clean_of_genus(cut->rest, genus_after);
          rep.cut_seconds += seconds_since(t1);
          if (!clean) continue;
          // The other handles' cycles must stay on the rest.
          bool kept_cycles = true;
          std::vector<std::vector<NodeId>> saved = cycles;
          for (std::size_t j = k + 1; j < cycles.size() && kept_cycles; ++j) {
            for (NodeId& v : cycles[j]) {
              v = cut->rest_renumber[v.index()];
              if (!v.is_valid()) kept_cycles = false;
            }
          }
          if (!kept_cycles) {
            cycles = saved;
            continue;
          }
          std::optional<BallWeave> slab = weave_first(cut->slab, trial_final);
          if (!slab) {
            cycles = saved;
            continue;
          }
          const std::size_t after_slab = trial_final + slab->interior;
          hc.grid_a = ci.a;
          hc.grid_b = ci.b;
          hc.disc = "slab: " + disc_name(ci) + " and " + disc_name(co) + ", " +
                    std::to_string(slab->hexes.size()) + " hexes, band of " +
                    std::to_string(band->quads.size()) + " quads";
          slabs.push_back(std::move(*slab));
          if (k + 1 < cycles.size()) {
            if (cut_from(cut->rest, k + 1, after_slab)) return true;
          } else if (std::optional<BallWeave> w = weave_first(cut->rest, after_slab)) {
            std::vector<stc::Hex> all = w->hexes;
            for (const BallWeave& b : slabs) all.insert(all.end(), b.hexes.begin(), b.hexes.end());
            const std::string problem = glue_problem(all, after_slab + w->interior, rep);
            if (problem.empty()) {
              found = SlabRoute{std::move(*w), slabs, after_slab, cuts};
              return true;
            }
            note("slabs glued invalid (" + problem.substr(0, 100) + ")");
          }
          slabs.pop_back();
          cycles = saved;
        }
      }
    }
    return false;
  };
  for (const auto& set : sets) {
    cycles = set;
    cuts.assign(set.size(), HandleCut{});
    slabs.clear();
    if (cut_from(solid, 0, first_final)) return found;
    if (out_of_budget()) break;
  }
  *why = std::to_string(loop_checks) + " slab cuts tried, " + std::to_string(no_band) +
         " cycles without a band beside them, " + std::to_string(weaves) + " weaves" + failures;
  return std::nullopt;
}

/// Whether the ray from `o` along `dir` crosses triangle (a, b, c) at t > 0.
bool ray_hits(const Eigen::Vector3d& o, const Eigen::Vector3d& dir, const Eigen::Vector3d& a,
              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a;
  const Eigen::Vector3d e2 = c - a;
  const Eigen::Vector3d p = dir.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return false;
  const Eigen::Vector3d t = o - a;
  const double u = t.dot(p) / det;
  if (u < 0.0 || u > 1.0) return false;
  const Eigen::Vector3d q = t.cross(e1);
  const double v = dir.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  return e2.dot(q) / det > 0.0;
}

}  // namespace

weave::WeaveResult weave_solids(const SurfaceMesh& mesh, const weave::WeaveOptions& uncut_options,
                                const CutOptions& cut_options, SolidsReport* report) {
  // The weaves of cut balls (CutOptions::ball_depth_filter); an uncut shell takes
  // `uncut_options` as they are.
  weave::WeaveOptions options = uncut_options;
  if (!cut_options.ball_depth_filter) options.extended.depth_filter = false;
  SolidsReport local_report;
  SolidsReport& rep = report != nullptr ? *report : local_report;
  rep = SolidsReport{};
  const stc::QuadSurface& surface = mesh.surface;
  const stc::SurfaceTopology topo = stc::surface_topology(surface);
  const std::size_t num_components = topo.components.size();

  weave::WeaveResult result;
  result.num_input_nodes = surface.num_nodes;
  std::size_t next_final = surface.num_nodes;  // interior nodes, solid by solid

  // Cavities: shells of negative signed volume (orient_outward points them into the
  // cavity), each given to the smallest positive shell that encloses it (ray parity).
  const auto point = [&](NodeId v) -> Eigen::Vector3d {
    return mesh.points.row(v.value()).transpose();
  };
  std::vector<double> volume(num_components, 0.0);
  for (std::size_t q = 0; q < surface.num_quads(); ++q) {
    const stc::Quad& quad = surface.quads[q];
    volume[topo.quad_components[q].index()] +=
        (point(quad[0]).dot(point(quad[1]).cross(point(quad[2]))) +
         point(quad[0]).dot(point(quad[2]).cross(point(quad[3])))) /
        6.0;
  }
  std::vector<std::vector<std::size_t>> cavities(num_components);
  for (std::size_t c = 0; c < num_components; ++c) {
    if (volume[c] >= 0.0) continue;
    std::size_t first_quad = 0;
    while (topo.quad_components[first_quad].index() != c) ++first_quad;
    const Eigen::Vector3d o = point(surface.quads[first_quad][0]);
    const Eigen::Vector3d dir = Eigen::Vector3d(0.5390117, 0.6421423, 0.5449871).normalized();
    std::size_t owner = num_components;
    for (std::size_t other = 0; other < num_components; ++other) {
      if (volume[other] <= 0.0) continue;
      std::size_t hits = 0;
      for (std::size_t q = 0; q < surface.num_quads(); ++q) {
        if (topo.quad_components[q].index() != other) continue;
        const stc::Quad& quad = surface.quads[q];
        hits += ray_hits(o, dir, point(quad[0]), point(quad[1]), point(quad[2])) ? 1 : 0;
        hits += ray_hits(o, dir, point(quad[0]), point(quad[2]), point(quad[3])) ? 1 : 0;
      }
      if (hits % 2 == 1 && (owner == num_components || volume[other] < volume[owner]))
        owner = other;
    }
    if (owner == num_components) {
      throw Unsupported(ComponentId(c).str() +
                        " is oriented as a cavity but no shell encloses it: check the input");
    }
    cavities[owner].push_back(c);
  }
  rep.solids = 0;
  for (std::size_t c = 0; c < num_components; ++c) rep.solids += volume[c] >= 0.0 ? 1 : 0;

  for (std::size_t c = 0; c < num_components; ++c) {
    if (volume[c] < 0.0) continue;
    auto t0 = std::chrono::steady_clock::now();
    // The solid's own surface (its shell and its cavities), nodes in increasing global order.
    std::vector<char> in_solid(num_components, 0);
    in_solid[c] = 1;
    for (std::size_t k : cavities[c]) in_solid[k] = 1;
    CutSurface solid;
    std::vector<NodeId> local(surface.num_nodes, NodeId::invalid());
    std::vector<std::size_t> solid_quad_component;
    for (std::size_t q = 0; q < surface.num_quads(); ++q) {
      if (in_solid[topo.quad_components[q].index()] == 0) continue;
      solid_quad_component.push_back(topo.quad_components[q].index());
      stc::Quad quad = surface.quads[q];
      solid.mesh.surface.quads.push_back(quad);
      for (NodeId v : quad) local[v.index()] = NodeId(0);
    }
    for (std::size_t v = 0; v < surface.num_nodes; ++v) {
      if (!local[v].is_valid()) continue;
      local[v] = NodeId(solid.final_id.size());
      solid.final_id.push_back(NodeId(v));
    }
    for (stc::Quad& q : solid.mesh.surface.quads)
      for (NodeId& v : q) v = local[v.index()];
    solid.mesh.surface.num_nodes = solid.final_id.size();
    solid.mesh.points.resize(static_cast<Eigen::Index>(solid.final_id.size()), 3);
    for (std::size_t v = 0; v < solid.final_id.size(); ++v)
      solid.mesh.points.row(static_cast<Eigen::Index>(v)) =
          mesh.points.row(solid.final_id[v].value());

    // The handle cycles of `shell` (genus `shell_genus`): disjoint simple cycles that bound
    // inside, one per handle, in `found`, and other choices of them in `alternatives`.
    const auto choose_cycles = [&](const CutSurface& shell, int shell_genus,
                                   std::vector<std::vector<NodeId>>& found,
                                   std::vector<std::vector<std::vector<NodeId>>>& alternatives) {
      const HandleDiagnosis h = diagnose_handles(shell.mesh);
      if (!h.decided) {
        throw Unsupported(ComponentId(c).str() +
                          ": cannot tell which cycles bound inside the "
                          "solid (" +
                          h.undecided_reason + "), so its handles cannot be cut");
      }
      if (!h.all_even()) {
        std::string which = "a combination of cycles over several shells";
        if (h.odd_handle >= 0) {
          const HandleCycle& odd = h.handles[static_cast<std::size_t>(h.odd_handle)];
          which = "the cycle " + cycle_name(odd, shell.final_id) + " (" +
                  std::to_string(odd.length()) + " edges)";
        }
        throw TopologyError(ComponentId(c).str() + ": " + which +
                            " bounds inside the solid and has odd length: no hex mesh with this "
                            "boundary exists (Erickson 2014); re-mesh the surface so that its "
                            "handle cycles are even");
      }
      if (h.handles.size() != static_cast<std::size_t>(shell_genus)) {
        throw Unsupported(ComponentId(c).str() + ": " +
                          std::to_string(shell_genus - static_cast<int>(h.handles.size())) +
                          " of its handle cycles have no simple representative: cutting them is "
                          "not supported yet");
      }
      // Cycles that touch: one of them replaced by another of its class (handles.hpp).
      found = disjoint_handle_cycles(h, shell.final_id.size());
      if (found.empty()) {
        std::vector<char> used(shell.final_id.size(), 0);
        for (const HandleCycle& hc : h.handles) {
          for (NodeId v : hc.nodes) {
            if (used[v.index()] != 0) {
              throw Unsupported(ComponentId(c).str() + ": its handle cycles share node " +
                                shell.final_id[v.index()].str() +
                                " and no choice among the other cycles of their classes is "
                                "disjoint: cutting handles whose cycles touch is not supported");
            }
            used[v.index()] = 1;
          }
        }
        throw InternalError(ComponentId(c).str() + ": no disjoint handle cycles were chosen");
      }
      // Fallbacks: one handle's cycle replaced by another of its class, when disjoint from
      // the other handles' cycles.
      for (std::size_t k = 0; k < h.alternatives.size(); ++k) {
        for (const HandleCycle& alt : h.alternatives[k]) {
          std::vector<char> other(shell.final_id.size(), 0);
          for (std::size_t j = 0; j < found.size(); ++j)
            if (j != k)
              for (NodeId v : found[j]) other[v.index()] = 1;
          if (std::any_of(alt.nodes.begin(), alt.nodes.end(),
                          [&](NodeId v) { return other[v.index()] != 0; }))
            continue;
          std::vector<std::vector<NodeId>> set = found;
          set[k] = alt.nodes;
          alternatives.push_back(std::move(set));
        }
      }
    };
    int genus = topo.components[c].genus.value_or(0);
    std::vector<std::vector<NodeId>> cycles;
    std::vector<std::vector<std::vector<NodeId>>> fallbacks;
    // A solid with handles and cavities: per cavity, the hex joining a cavity quad to an
    // outer-shell quad, put on the front of every ball the handle route weaves.
    std::vector<stc::Hex> columns;
    if (!cavities[c].empty()) {
      // A solid with cavities: one annulus (a ladder of 4 quads) per cavity, from the
      // boundary of a cavity quad to that of the nearest quad of the outer shell, cuts off a
      // column (the 6 quads of one hex) and joins the cavity's shell to the outer one. Without
      // handles the pieces are balls, woven together and glued back; with handles on the outer
      // shell the columns are not cut off but attached to the front of the handle route's
      // balls, and the solid goes on to the handle route below.
      for (std::size_t k : cavities[c]) {
        // Its handle classes would cross the annulus that joins it to the outer shell twice:
        // no set of disjoint simple cycles spans them there (docs/topology.md).
        if (topo.components[k].genus.value_or(0) > 0) {
          throw Unsupported(
              ComponentId(k).str() +
              ": a cavity with handles is not supported yet (its handle cycles would cross the "
              "hex joining it to the outer shell twice, docs/topology.md); a triangle-split "
              "surface of the same solid is meshed through the tet interior (--interior tets)");
        }
      }
      CutSurface current = solid;
      std::vector<char> used(solid.final_id.size(), 0);
      std::vector<char> rim(solid.final_id.size(), 0);  // the annuli's cycles
      if (genus > 0) {
        // Balls taken out of a solid change none of its handles: the cycles are those of the
        // outer shell alone (the joined shell folds at the annuli, where the handle diagnosis
        // cannot push cycles off the surface), chosen before the annuli, which avoid them.
        CutSurface shell;
        shell.mesh.points = solid.mesh.points;
        shell.final_id = solid.final_id;
        shell.mesh.surface.num_nodes = solid.mesh.surface.num_nodes;
        for (std::size_t q = 0; q < solid_quad_component.size(); ++q)
          if (solid_quad_component[q] == c)
            shell.mesh.surface.quads.push_back(solid.mesh.surface.quads[q]);
        std::vector<NodeId> renumber;
        shell = compacted(shell, &renumber);
        std::vector<NodeId> back(shell.final_id.size());
        for (std::size_t v = 0; v < renumber.size(); ++v)
          if (renumber[v].is_valid()) back[renumber[v].index()] = NodeId(v);
        choose_cycles(shell, genus, cycles, fallbacks);
        const auto to_solid = [&](std::vector<NodeId>& cycle) {
          for (NodeId& v : cycle) v = back[v.index()];
        };
        for (auto& cycle : cycles) to_solid(cycle);
        for (auto& set : fallbacks)
          for (auto& cycle : set) to_solid(cycle);
        // The disc spanning a cycle must stay clear of the cavities: the set of cycles whose
        // worst clearance is largest comes first (ties: the order of choose_cycles).
        // Clearance of a cycle: the distance from its centroid to the nearest cavity node,
        // less its radius (the farthest cycle node from the centroid).
        std::vector<char> cavity_node(solid.final_id.size(), 0);
        for (std::size_t q = 0; q < solid_quad_component.size(); ++q)
          if (solid_quad_component[q] != c)
            for (NodeId v : solid.mesh.surface.quads[q]) cavity_node[v.index()] = 1;
        const auto clearance = [&](const std::vector<std::vector<NodeId>>& set) {
          double worst = INFINITY;
          for (const auto& cycle : set) {
            Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
            for (NodeId v : cycle) centre += solid.mesh.points.row(v.value());
            centre /= static_cast<double>(cycle.size());
            double radius = 0.0;
            for (NodeId v : cycle)
              radius = std::max(radius, (solid.mesh.points.row(v.value()) - centre).norm());
            double nearest = INFINITY;
            for (std::size_t v = 0; v < cavity_node.size(); ++v) {
              if (cavity_node[v] != 0) {
                nearest = std::min(
                    nearest, (solid.mesh.points.row(static_cast<Eigen::Index>(v)) - centre).norm());
              }
            }
            worst = std::min(worst, nearest - radius);
          }
          return worst;
        };
        fallbacks.insert(fallbacks.begin(), cycles);
        std::vector<double> clear(fallbacks.size());
        for (std::size_t k = 0; k < fallbacks.size(); ++k) clear[k] = clearance(fallbacks[k]);
        std::vector<std::size_t> order(fallbacks.size());
        for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return clear[a] > clear[b]; });
        std::vector<std::vector<std::vector<NodeId>>> sorted;
        sorted.reserve(order.size());
        for (std::size_t k : order) sorted.push_back(std::move(fallbacks[k]));
        cycles = sorted.front();
        fallbacks.assign(std::make_move_iterator(sorted.begin() + 1),
                         std::make_move_iterator(sorted.end()));
        for (const auto& cycle : cycles)
          for (NodeId v : cycle) used[v.index()] = 1;
      }
      const auto centroid = [&](std::size_t q) {
        Eigen::Vector3d m = Eigen::Vector3d::Zero();
        for (NodeId v : solid.mesh.surface.quads[q])
          m += solid.mesh.points.row(v.value()).transpose();
        return Eigen::Vector3d(m / 4.0);
      };
      const auto free_quad = [&](std::size_t q) {
        return std::none_of(solid.mesh.surface.quads[q].begin(), solid.mesh.surface.quads[q].end(),
                            [&](NodeId v) { return used[v.index()] != 0; });
      };
      for (std::size_t k : cavities[c]) {
        double best = INFINITY;
        std::size_t qi = 0;
        std::size_t qo = 0;
        for (std::size_t a = 0; a < solid_quad_component.size(); ++a) {
          if (solid_quad_component[a] != k || !free_quad(a)) continue;
          const Eigen::Vector3d ca = centroid(a);
          for (std::size_t b = 0; b < solid_quad_component.size(); ++b) {
            if (solid_quad_component[b] != c || !free_quad(b)) continue;
            const double d = (centroid(b) - ca).squaredNorm();
            if (d < best) {
              best = d;
              qi = a;
              qo = b;
            }
          }
        }
        if (!std::isfinite(best)) {
          throw Unsupported(ComponentId(k).str() +
                            ": no quad of the cavity and of the outer shell is free to join them "
                            "(every pair touches a handle cycle or another cavity's join): "
                            "refine the surface");
        }
        const stc::Quad& outer_quad = solid.mesh.surface.quads[qo];
        const stc::Quad& inner_quad = solid.mesh.surface.quads[qi];
        std::vector<NodeId> outer(outer_quad.begin(), outer_quad.end());
        std::vector<NodeId> inner;
        double best_pairing = INFINITY;
        for (int shift = 0; shift < 4; ++shift) {
          for (int dir : {1, -1}) {
            // Only dir = -1 pairs the cycles the way the surface's orientation needs: the
            // annulus of `cut_annulus` then fits both shells, and a column hex (inner then
            // outer, VTK order) is positive. The reflected pairings are skipped.
            if (dir == 1) continue;
            std::vector<NodeId> candidate;
            double cost = 0.0;
            for (int p = 0; p < 4; ++p) {
              const NodeId v =
                  inner_quad[static_cast<std::size_t>(((shift + dir * p) % 4 + 4) % 4)];
              candidate.push_back(v);
              cost += (solid.mesh.points.row(v.value()) -
                       solid.mesh.points.row(outer[static_cast<std::size_t>(p)].value()))
                          .squaredNorm();
            }
            if (cost < best_pairing) {
              best_pairing = cost;
              inner = candidate;
            }
          }
        }
        for (NodeId v : outer) used[v.index()] = rim[v.index()] = 1;
        for (NodeId v : inner) used[v.index()] = rim[v.index()] = 1;
        HandleCut hc;
        for (NodeId v : outer) hc.cycle.push_back(solid.final_id[v.index()]);
        for (NodeId v : inner) hc.cycle.push_back(solid.final_id[v.index()]);
        hc.grid_a = 1;
        hc.grid_b = 4;  // an annulus of 1 x 4 quads
        hc.attempts = 1;
        // With handles the column is not cut off but attached: woven apart, the joined
        // shell's weave may fill the column's place with hexes of its own (its front does
        // not hold the column's quads); attached, the weaver knows the hex behind the
        // annulus and builds none sharing two faces with it. Without handles it is cut off
        // first, and attached when that weave blocks or glues into an invalid complex.
        columns.push_back(
            {inner[0], inner[1], inner[2], inner[3], outer[0], outer[1], outer[2], outer[3]});
        if (genus == 0) {
          current = cut_annulus(current, outer, inner);
          hc.disc = "annulus 1x4";
        } else {
          hc.disc = "column hex";
        }
        rep.cuts.push_back(hc);
      }
      if (genus == 0) {
        const stc::LoopSet loops =
            stc::find_loops(current.mesh.surface, stc::FindLoopsOptions{false});
        if (loops.num_self_intersecting() > 0 &&
            (!cut_options.allow_self_crossing ||
             loops.num_self_crossing_quads() > self_crossing_quads_of(solid))) {
          throw Unsupported(ComponentId(c).str() +
                            ": cutting its cavities off gives a surface with a "
                            "self-intersecting loop: not supported yet");
        }
        rep.cut_seconds += seconds_since(t0);
        // One weave, of the cut-off surface or of the uncut solid with `attached` on its front,
        // glued after what is woven so far: `problem` empty when the result is valid, else why
        // not, to follow "its weave".
        struct Attempt {
          BallWeave w;
          std::string problem;
          bool blocked = false;
        };
        const auto weave_and_glue = [&](const CutSurface& s,
                                        const std::vector<stc::Hex>& attached) {
          Attempt a;
          const auto t1 = std::chrono::steady_clock::now();
          try {
            a.w = weave_ball(s, options, next_final, cut_options, attached);
            rep.weave_seconds += seconds_since(t1);
            a.problem = glue_problem(a.w.hexes, next_final + a.w.interior, rep);
            if (!a.problem.empty())
              a.problem = "glued back breaks an invariant (" + a.problem.substr(0, 200) + ")";
          } catch (const WeaveError& e) {
            rep.weave_seconds += seconds_since(t1);
            a.problem = std::string("blocks (") + std::string(e.what()).substr(0, 200) + ")";
            a.blocked = true;
          } catch (const InvalidInput& e) {
            // (the joined front's loops crossing themselves, say); on the cut-off surface a
            // refusal stays one
            if (attached.empty()) throw;
            rep.weave_seconds += seconds_since(t1);
            a.problem = std::string("is refused (") + std::string(e.what()).substr(0, 200) + ")";
          }
          return a;
        };
        Attempt woven = weave_and_glue(current, {});
        if (!woven.problem.empty()) {
          // The columns attached to the front of the uncut solid instead (as with handles).
          // Measured: the hollow cubes whose cavity is more than one cell wide glued into a
          // face of three hexes when cut off (docs/topology.md "Several shells").
          Attempt joined = weave_and_glue(solid, columns);
          if (!joined.problem.empty()) {
            std::string why = ComponentId(c).str();
            why += ": its cavities cut off along annuli, their weave ";
            why += woven.problem;
            why += "; with the column hexes attached to the front its weave ";
            why += joined.problem;
            if (woven.blocked && joined.blocked) throw WeaveError(why);
            throw Unsupported(why);
          }
          woven = std::move(joined);
          for (std::size_t k = rep.cuts.size() - cavities[c].size(); k < rep.cuts.size(); ++k)
            rep.cuts[k].disc = "column hex";
        }
        next_final += woven.w.interior;
        append_ball(result, woven.w);
        continue;
      }
      // Handles too: the handle route goes on, its balls woven with the column hexes on their
      // fronts. The outer shell's cycles avoid the columns; a fallback through one is dropped.
      if (cut_options.ball_weaver && self_crossing_quads_of(solid) > 0) {
        throw Unsupported(ComponentId(c).str() +
                          ": a solid with handles and cavities whose loops cross themselves is "
                          "not supported yet: re-mesh the surface so that its loops do not cross "
                          "themselves (docs/self-intersecting-loops.md)");
      }
      std::erase_if(fallbacks, [&](const std::vector<std::vector<NodeId>>& set) {
        return std::any_of(set.begin(), set.end(), [&](const std::vector<NodeId>& cycle) {
          return std::any_of(cycle.begin(), cycle.end(),
                             [&](NodeId v) { return rim[v.index()] != 0; });
        });
      });
    }

    if (genus > 0 && cycles.empty()) choose_cycles(solid, genus, cycles, fallbacks);
    // With `allow_self_crossing`, the solid's own count of self-crossing quads bounds its cuts'.
    const std::size_t solid_self_crossing_quads =
        cut_options.allow_self_crossing ? self_crossing_quads_of(solid) : 0;
    rep.cut_seconds += seconds_since(t0);

    // Cut the handles one after the other (the cycles are disjoint, so their node ids stay
    // valid through the earlier cuts): a depth-first search over the disc choices of each
    // cut, pruned by loop cleanliness after every cut, where the last cut is checked by
    // weaving and gluing; within a budget of loop checks and of weaves.
    // Two passes over the disc choices. First the grids, woven with `options` alone (what
    // the cut did before chord discs). Then the loop-following chord discs first, and a
    // blocked weave (or an invalid glue) tried again with the reliable rule set, then each
    // with one-face recovery pillows: the two copies of a disc coincide, and the extended rules
    // often block beside them (docs/topology.md has the figures).
    struct Pass {
      bool follow_first = false;
      std::vector<weave::WeaveOptions> chain;
    };
    std::vector<Pass> passes(2);
    passes[0].chain = {options};
    passes[1].follow_first = true;
    passes[1].chain = {options};
    if (options.rules != weave::RuleSet::Reliable) {
      weave::WeaveOptions o = options;
      o.rules = weave::RuleSet::Reliable;
      passes[1].chain.push_back(o);
    }
    if (cut_options.recovery_pillows > 0 && options.recovery_pillows == 0) {
      const std::size_t plain = passes[1].chain.size();
      for (std::size_t i = 0; i < plain; ++i) {
        weave::WeaveOptions o = passes[1].chain[i];
        o.recovery_pillows = cut_options.recovery_pillows;
        passes[1].chain.push_back(o);
      }
    }
    // The slab route is tried last and weaves at most a few balls: it keeps the recovery.
    const std::vector<weave::WeaveOptions> slab_chain = passes[1].chain;
    if (!cut_options.ball_block_recovery) {
      for (Pass& pass : passes) {
        for (weave::WeaveOptions& o : pass.chain) o.block_recovery = weave::BlockRecovery::Off;
      }
    }
    bool follow_first = false;
    const std::vector<weave::WeaveOptions>* chain = &passes[0].chain;
    std::optional<BallWeave> ball;
    std::vector<BallWeave> slabs;  // the slab route's slabs
    std::string slab_why = columns.empty() ? "" : "not tried: the solid has cavities";
    std::vector<HandleCut> cuts(cycles.size());
    std::size_t loop_checks = 0;
    std::size_t self_intersecting_cuts = 0;
    std::size_t weaves = 0;
    std::string failures;
    const auto note = [&](const DiscChoice& choice, std::size_t k, const std::string& why) {
      if (failures.size() > 600) return;
      failures += "; cut " + std::to_string(k + 1) + ", " + disc_name(choice) +
                  " disc from position " + std::to_string(choice.start) + ": " + why;
    };
    const std::function<bool(const CutSurface&, std::size_t, std::size_t)> search =
        [&](const CutSurface& current, std::size_t k, std::size_t final_start) -> bool {
      if (weaves >= cut_options.max_disc_attempts || loop_checks >= cut_options.max_loop_checks)
        return false;
      auto t1 = std::chrono::steady_clock::now();
      std::vector<DiscChoice> choices = disc_choices(current.mesh.points, cycles[k]);
      {
        // Loop-following chord discs after the plain grids, before the O-grids.
        const stc::LoopSet before =
            stc::find_loops(current.mesh.surface, stc::FindLoopsOptions{false});
        const std::vector<LoopId> crossing =
            crossing_loops(current.mesh.surface, before, cycles[k]);
        std::vector<DiscChoice> follow = loop_following_choices(crossing, before);

        const auto first_ring = std::find_if(choices.begin(), choices.end(),
                                             [](const DiscChoice& d) { return d.ring; });
        if (follow_first)
          choices.insert(choices.begin(), follow.begin(), follow.end());
        else
          choices.insert(first_ring, follow.begin(), follow.end());
      }
      rep.cut_seconds += seconds_since(t1);
      HandleCut& hc = cuts[k];
      hc.cycle.clear();
      for (NodeId v : cycles[k]) hc.cycle.push_back(current.final_id[v.index()]);
      const bool last = k + 1 == cycles.size();
      for (const DiscChoice& choice : choices) {
        if (weaves >= cut_options.max_disc_attempts || loop_checks >= cut_options.max_loop_checks)
          return false;
        ++hc.attempts;
        t1 = std::chrono::steady_clock::now();
        std::size_t trial_final = final_start;
        std::optional<Disc> disc;
        if (choice.partner.empty()) {
          disc = grid_disc(current, cycles[k], choice);
        } else {
          std::vector<Eigen::RowVector3d> points;
          for (NodeId v : cycles[k]) points.emplace_back(current.mesh.points.row(v.value()));
          disc = chord_disc(points, choice.partner);
        }
        if (!disc) {
          rep.cut_seconds += seconds_since(t1);
          note(choice, k, "no disc realises the pairing");
          continue;
        }
        CutSurface cut = cut_along(current, cycles[k], choice.start, *disc, &trial_final);
        const stc::LoopSet loops = stc::find_loops(cut.mesh.surface, stc::FindLoopsOptions{false});
        ++loop_checks;
        rep.cut_seconds += seconds_since(t1);
        if (loops.num_self_intersecting() > 0 &&
            (!cut_options.allow_self_crossing ||
             loops.num_self_crossing_quads() > solid_self_crossing_quads)) {
          ++self_intersecting_cuts;
          continue;
        }
        hc.grid_a = choice.a;
        hc.grid_b = choice.b;
        hc.disc = disc_name(choice);
        if (!last) {
          if (search(cut, k + 1, trial_final)) return true;
          continue;
        }
        ++weaves;
        for (const weave::WeaveOptions& attempt : *chain) {
          t1 = std::chrono::steady_clock::now();
          try {
            BallWeave w = weave_ball(cut, attempt, trial_final, cut_options, columns);
            rep.weave_seconds += seconds_since(t1);
            const std::string problem = glue_problem(w.hexes, trial_final + w.interior, rep);
            if (!problem.empty()) {
              note(choice, k, "glued complex invalid (" + problem.substr(0, 120) + ")");
              continue;
            }
            if (&attempt != &chain->front()) ++rep.relaxed_weaves;
            next_final = trial_final;
            ball = std::move(w);
            return true;
          } catch (const WeaveError& e) {
            rep.weave_seconds += seconds_since(t1);
            note(choice, k, std::string("weave blocked: ") + std::string(e.what()).substr(0, 80));
          } catch (const InvalidInput& e) {
            // The weave refused the cut surface as a front (a bug of the cut, or a pinch):
            // another choice may do.
            rep.weave_seconds += seconds_since(t1);
            note(choice, k, std::string("the weave refused the cut surface: ") + e.what());
          }
        }
      }
      return false;
    };
    // The slab route: the band of quads beside each handle cycle closed by two discs and
    // woven on its own, so that no node is identified at the glue.
    const auto try_slabs = [&](const std::vector<std::vector<NodeId>>& primary) {
      std::vector<std::vector<std::vector<NodeId>>> sets{primary};
      sets.insert(sets.end(), fallbacks.begin(), fallbacks.end());
      std::optional<SlabRoute> slab =
          slab_route(solid, sets, slab_chain, cut_options, next_final, rep, &slab_why);
      if (!slab) return false;
      cuts = std::move(slab->cuts);
      ball = std::move(slab->ball);
      slabs = std::move(slab->slabs);
      next_final = slab->next_final;
      return true;
    };
    if (cycles.empty()) {
      auto t1 = std::chrono::steady_clock::now();
      ball = weave_ball(solid, uncut_options, next_final, cut_options);
      rep.weave_seconds += seconds_since(t1);
    } else if (const auto primary = cycles;
               !(columns.empty() && cut_options.slab_first && try_slabs(primary)) &&
               !std::any_of(passes.begin(), passes.end(),
                            [&](const Pass& pass) {
                              follow_first = pass.follow_first;
                              chain = &pass.chain;
                              loop_checks = 0;
                              weaves = 0;
                              self_intersecting_cuts = 0;
                              failures.clear();
                              cycles = primary;
                              for (HandleCut& hc : cuts) hc.attempts = 0;
                              if (search(solid, 0, next_final)) return true;
                              return std::any_of(fallbacks.begin(), fallbacks.end(),
                                                 [&](const auto& set) {
                                                   cycles = set;
                                                   return search(solid, 0, next_final);
                                                 });
                            }) &&
               !(columns.empty() && !cut_options.slab_first && try_slabs(primary))) {
      cycles = primary;
    }
    if (!ball) {
      std::string names;
      for (std::size_t k = 0; k < cycles.size(); ++k) {
        names += (k > 0 ? ", " : "");
        for (std::size_t i = 0; i < cycles[k].size() && i < 8; ++i)
          names += (i > 0 ? "-" : "") + solid.final_id[cycles[k][i].index()].str();
        names +=
            (cycles[k].size() > 8 ? "-... (" : " (") + std::to_string(cycles[k].size()) + " edges)";
      }
      std::string why = ComponentId(c).str() + ": no choice of discs spanning the handle cycles ";
      why += names;
      why += " could be woven and glued (" + std::to_string(loop_checks) + " cuts tried, ";
      why += std::to_string(self_intersecting_cuts) + " with a self-intersecting loop, ";
      why += std::to_string(weaves) + " woven";
      why += failures.size() > 600 ? failures.substr(0, 600) + "..." : failures;
      why += "; slabs: " + slab_why;
      why += "); docs/topology.md says what the disc choice needs";
      throw Unsupported(why);
    }
    for (HandleCut& hc : cuts) rep.cuts.push_back(std::move(hc));
    next_final += ball->interior;
    append_ball(result, *ball);
    for (const BallWeave& b : slabs) append_ball(result, b);
  }
  const auto t2 = std::chrono::steady_clock::now();
  // Interior nodes were numbered solid by solid (discs first, then the weave's); the weave's
  // own numbering of a solid follows its disc nodes, so the ids are dense.
  result.complex.num_nodes = next_final;
  result.dual = dual_of(result.complex, surface);
  rep.glue_seconds += seconds_since(t2);
  return result;
}

}  // namespace stcweave::primal
