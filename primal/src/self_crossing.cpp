#include "stcweave/primal/self_crossing.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <unordered_map>

#include "stcweave/primal/edge_angles.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/validate.hpp"
#include "stcweave/weave/attached.hpp"

namespace stcweave::primal {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// Positions for every node of the moves' result, for looking at the front: input nodes at
/// their points, each node an attached hex made first at the centroid of that hex's other
/// nodes, then 50 Jacobi sweeps of the average of its hex-edge neighbours.
Points front_points(const Points& input, const stc::LoopMoveResult& moves) {
  const std::size_t n = moves.hexes.num_nodes;
  Points p = Points::Zero(static_cast<Eigen::Index>(n), 3);
  const auto fixed = static_cast<Eigen::Index>(moves.num_input_nodes);
  p.topRows(fixed) = input.topRows(fixed);
  std::vector<bool> placed(n, false);
  for (std::size_t v = 0; v < moves.num_input_nodes; ++v) placed[v] = true;
  std::vector<std::vector<std::size_t>> adj(n);
  for (const stc::Hex& h : moves.hexes.hexes) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    int count = 0;
    for (const NodeId v : h) {
      if (placed[v.index()]) {
        sum += p.row(static_cast<Eigen::Index>(v.index()));
        ++count;
      }
    }
    for (const NodeId v : h) {
      if (!placed[v.index()]) {
        p.row(static_cast<Eigen::Index>(v.index())) =
            count > 0 ? Eigen::RowVector3d(sum / count) : Eigen::RowVector3d::Zero();
        placed[v.index()] = true;
      }
    }
    for (const auto& e : stc::kHexEdges) {
      adj[h[static_cast<std::size_t>(e[0])].index()].push_back(
          h[static_cast<std::size_t>(e[1])].index());
      adj[h[static_cast<std::size_t>(e[1])].index()].push_back(
          h[static_cast<std::size_t>(e[0])].index());
    }
  }
  for (int sweep = 0; sweep < 50; ++sweep) {
    Points next = p;
    for (std::size_t v = moves.num_input_nodes; v < n; ++v) {
      if (adj[v].empty()) continue;
      Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
      for (const std::size_t u : adj[v]) sum += p.row(static_cast<Eigen::Index>(u));
      next.row(static_cast<Eigen::Index>(v)) = sum / static_cast<double>(adj[v].size());
    }
    p = next;
  }
  return p;
}

using FaceKey = std::array<std::int32_t, 4>;
FaceKey face_key(const stc::Quad& q) {
  FaceKey k{q[0].value(), q[1].value(), q[2].value(), q[3].value()};
  std::sort(k.begin(), k.end());
  return k;
}

/// The woven STC of a joined complex: per hex face, the hex across it or the input quad.
std::vector<std::array<weave::DualLink, 6>> rebuild_dual(const stc::HexComplex& complex,
                                                         const stc::QuadSurface& input) {
  std::map<FaceKey, std::vector<std::pair<std::int32_t, std::int8_t>>> faces;
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (int f = 0; f < 6; ++f) {
      faces[face_key(stc::hex_face(complex.hexes[h], f))].emplace_back(static_cast<std::int32_t>(h),
                                                                       static_cast<std::int8_t>(f));
    }
  }
  std::map<FaceKey, std::int32_t> quads;
  for (std::size_t q = 0; q < input.quads.size(); ++q)
    quads.emplace(face_key(input.quads[q]), static_cast<std::int32_t>(q));
  std::vector<std::array<weave::DualLink, 6>> dual(complex.hexes.size());
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (int f = 0; f < 6; ++f) {
      const FaceKey k = face_key(stc::hex_face(complex.hexes[h], f));
      weave::DualLink& link = dual[h][static_cast<std::size_t>(f)];
      for (const auto& [other, of] : faces[k]) {
        if (other != static_cast<std::int32_t>(h)) {
          link.id = other;
          link.local_face = of;
        }
      }
      if (link.id < 0) {
        const auto it = quads.find(k);
        link.is_boundary = true;
        link.id = it == quads.end() ? -1 : it->second;
      }
    }
  }
  return dual;
}

}  // namespace

weave::WeaveResult weave_self_crossing(const SurfaceMesh& surface,
                                       const weave::WeaveOptions& caller_weave_options,
                                       const std::vector<std::array<double, 4>>& side_angles,
                                       const SelfCrossingOptions& options,
                                       SelfCrossingReport& report) {
  report = SelfCrossingReport{};
  report.used = true;
  // The ways below read these; the reliable fallback changes the rules and runs them again.
  // The caller's weave options as this stage runs them.
  const auto stage_weave_options = [&] {
    weave::WeaveOptions o = caller_weave_options;
    if (options.undo_seam_blocking_shrinks) o.undo_seam_blocking_shrinks = true;
    return o;
  };
  weave::WeaveOptions weave_options = stage_weave_options();
  auto t = std::chrono::steady_clock::now();
  report.moves = stc::untangle_loops(surface.surface, options.search);
  const stc::LoopMoveResult moves = report.moves;  // a copy: a fill replaces report.moves
  report.attached_hexes = moves.hexes.hexes.size();
  report.search_seconds = seconds_since(t);
  const auto give_up = [&](const stc::LoopMoveResult& at, const std::string& why) -> WeaveError {
    std::string where;
    if (!options.front_on_failure.empty()) {
      SurfaceMesh front{front_points(surface.points, at), at.front};
      write_surface(front, options.front_on_failure);
      where = "; the front at that point (" + std::to_string(at.front.quads.size()) +
              " quads) is written to " + options.front_on_failure;
    }
    std::string woven;
    if (!report.weave_failure.empty()) {
      woven = "; the weave of that front blocked too (" + report.weave_failure.substr(0, 600) +
              (report.weave_failure.size() > 600 ? " ..." : "") + ")";
    }
    return WeaveError("self-intersecting loops: " + why + woven + " with " +
                      std::to_string(at.self_crossing_quads_after) + " of " +
                      std::to_string(at.self_crossing_quads_before) +
                      " self-crossing quads left after " + std::to_string(at.moves.size()) +
                      " attached hexes" + where +
                      "; raise the search bounds (--loop-moves-*) or re-mesh the surface so that "
                      "fewer loops cross themselves");
  };
  // The weave of the front with the attached hexes known to the weaver: their nodes are free
  // (mergeable) interior nodes, and its seams see the hexes behind every front face.
  const auto weave_free = [&](std::size_t pillows) -> std::optional<weave::WeaveResult> {
    if (!options.free_nodes) return std::nullopt;
    const auto t_free = std::chrono::steady_clock::now();
    try {
      weave::WeaveOptions free_options = weave_options;
      free_options.recovery_pillows = pillows;
      weave::AttachedWeaveOptions more;
      more.untangle_rounds = options.untangle_rounds;
      more.search = options.search;
      weave::AttachedWeaveReport rounds;
      weave::WeaveResult r = weave::weave_attached(surface.surface, moves.hexes, free_options,
                                                   side_angles, more, &rounds);
      report.weave_seconds += seconds_since(t_free);
      const stc::ValidationReport check = stc::validate_hex_complex(r.complex, &surface.surface);
      if (!check.valid) {
        // Not an output: the next way is tried, and the violation is reported.
        report.free_weave_violation = check.summary();
        report.weave_failure += (report.weave_failure.empty() ? "" : "; ") +
                                std::string("the free weave gave an invalid complex (") +
                                check.summary() + ")";
        return std::nullopt;
      }
      report.untangle_rounds = rounds.rounds;
      report.round_hexes = rounds.hexes;
      report.woven_hexes = r.complex.hexes.size() - report.attached_hexes;
      report.free_nodes = true;
      report.front_pillows = r.stats.front_pillows;
      return r;
    } catch (const WeaveError& e) {
      report.weave_seconds += seconds_since(t_free);
      report.weave_failure += (report.weave_failure.empty() ? "" : "; ") + std::string("with ") +
                              std::to_string(pillows) + " recovery pillows: " + e.what();
      return std::nullopt;
    } catch (const InvalidInput& e) {
      throw InternalError(std::string("self-intersecting loops: the attached hexes are not a valid "
                                      "start for the weave (") +
                          e.what() + "); please report this surface");
    }
  };
  // The weave of the front with every front node fixed (the attached hexes unknown to the
  // weaver), joined directly or through a pillow layer.
  const auto weave_fixed_on = [&](const stc::LoopMoveResult& base_moves,
                                  bool residual) -> std::optional<weave::WeaveResult> {
    // The front with compact node ids (all of them "input" nodes for the weaver).
    t = std::chrono::steady_clock::now();
    std::vector<NodeId> front_nodes;
    for (const stc::Quad& q : base_moves.front.quads)
      front_nodes.insert(front_nodes.end(), q.begin(), q.end());
    std::sort(front_nodes.begin(), front_nodes.end());
    front_nodes.erase(std::unique(front_nodes.begin(), front_nodes.end()), front_nodes.end());
    std::unordered_map<std::int32_t, NodeId> compact;
    for (std::size_t i = 0; i < front_nodes.size(); ++i)
      compact.emplace(front_nodes[i].value(), NodeId(i));
    stc::QuadSurface front;
    front.num_nodes = front_nodes.size();
    for (const stc::Quad& q : base_moves.front.quads) {
      stc::Quad c{};
      for (std::size_t i = 0; i < 4; ++i) c[i] = compact.at(q[i].value());
      front.quads.push_back(c);
    }
    std::vector<std::array<double, 4>> angles;
    if (!side_angles.empty() && !residual && surface.points.rows() > 0) {
      // The extended rules read the front's own dihedral angles, its attached hexes' nodes
      // placed as for viewing (`front_points`). Measured on gmsh-quad/cylinder2_c3: with the
      // angles guessed from the input and the attached hexes (below), every weave of its
      // loop-clean front after 50 attached hexes blocked or ran out of rules; with these the
      // weave with recovery pillows completes (docs/self-intersecting-loops.md).
      const Points all = front_points(surface.points, base_moves);
      SurfaceMesh placed;
      placed.points.resize(static_cast<Eigen::Index>(front.num_nodes), 3);
      for (std::size_t i = 0; i < front_nodes.size(); ++i)
        placed.points.row(static_cast<Eigen::Index>(i)) = all.row(front_nodes[i].value());
      placed.surface = front;
      angles = dihedral_angles(placed);
    } else if (!side_angles.empty()) {
      // (A residual front has no positions: angles from the input's and the attached hexes'.)
      std::unordered_map<std::uint64_t, std::size_t> directed;
      const auto key = [](NodeId a, NodeId b) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a.value())) << 32U) |
               static_cast<std::uint32_t>(b.value());
      };
      for (std::size_t q = 0; q < front.quads.size(); ++q)
        for (std::size_t i = 0; i < 4; ++i)
          directed.emplace(key(front.quads[q][i], front.quads[q][(i + 1) % 4]), q);
      angles.resize(front.quads.size());
      for (std::size_t q = 0; q < front.quads.size(); ++q) {
        for (std::size_t i = 0; i < 4; ++i) {
          const auto it = directed.find(key(front.quads[q][(i + 1) % 4], front.quads[q][i]));
          const std::size_t o = it == directed.end() ? q : it->second;
          double a = 180.0;
          if (base_moves.front_input[q] >= 0 && base_moves.front_input[o] >= 0) {
            // An untouched input quad keeps its node order, so its side i is the input's.
            a = side_angles[static_cast<std::size_t>(base_moves.front_input[q])][i];
          } else if (base_moves.front_hex[q] >= 0 &&
                     base_moves.front_hex[q] == base_moves.front_hex[o]) {
            a = 270.0;  // two faces of one attached hex: the hex fills a right angle there
          }
          angles[q][i] = a;
        }
      }
    }
    weave::WeaveResult woven;
    try {
      weave::WeaveOptions fixed_options = weave_options;
      fixed_options.recovery_pillows =
          std::max(fixed_options.recovery_pillows, options.recovery_pillows);
      if (residual) {
        // The front a stalled fill left: meshed by this stage as a surface of its own.
        SelfCrossingOptions inner = options;
        inner.plain_weave_blocked = false;
        inner.fill_residual_depth = options.fill_residual_depth - 1;
        inner.front_on_failure.clear();
        SelfCrossingReport inner_report;
        const SurfaceMesh residual_mesh{Points::Zero(static_cast<Eigen::Index>(front.num_nodes), 3),
                                        front};
        woven = weave_self_crossing(residual_mesh, fixed_options, angles, inner, inner_report);
      } else {
        woven = weave::weave(front, fixed_options, angles);
      }
    } catch (const WeaveError& e) {
      report.weave_failure +=
          (report.weave_failure.empty() ? "" : "; with every front node fixed: ") +
          std::string(e.what());
      report.weave_seconds += seconds_since(t);
      return std::nullopt;
    }
    report.woven_hexes = woven.complex.hexes.size();
    report.weave_seconds += seconds_since(t);

    // Join: attached hexes + woven hexes, woven nodes mapped back.
    t = std::chrono::steady_clock::now();
    const std::size_t m = front_nodes.size();
    const std::size_t base = base_moves.hexes.num_nodes;
    const auto join = [&](bool pillow) {
      weave::WeaveResult r;
      r.num_input_nodes = base_moves.num_input_nodes;
      r.complex.hexes = base_moves.hexes.hexes;
      r.hex_rule.assign(r.complex.hexes.size(), "attached");
      r.hex_shrink.assign(r.complex.hexes.size(), -1);
      const auto woven_node = [&](NodeId v) {
        if (pillow) return NodeId(base + v.index());
        return v.index() < m ? front_nodes[v.index()] : NodeId(base + (v.index() - m));
      };
      if (pillow) {
        for (const stc::Quad& q : base_moves.front.quads) {
          const auto star = [&](NodeId v) { return NodeId(base + compact.at(v.value()).index()); };
          r.complex.hexes.push_back(
              {q[0], q[3], q[2], q[1], star(q[0]), star(q[3]), star(q[2]), star(q[1])});
          r.hex_rule.emplace_back("pillow");
          r.hex_shrink.push_back(-1);
        }
      }
      // Rule nodes: none for the attached and pillow hexes, the weave's (in its numbering) for
      // the woven ones.
      r.hex_node.assign(r.complex.hexes.size(), NodeId::invalid());
      for (std::size_t h = 0; h < woven.complex.hexes.size(); ++h) {
        stc::Hex x{};
        for (std::size_t i = 0; i < 8; ++i) x[i] = woven_node(woven.complex.hexes[h][i]);
        r.complex.hexes.push_back(x);
        r.hex_rule.push_back(h < woven.hex_rule.size() ? woven.hex_rule[h] : "woven");
        r.hex_shrink.push_back(h < woven.hex_shrink.size() ? woven.hex_shrink[h] : -1);
        r.hex_node.push_back(h < woven.hex_node.size() ? woven.hex_node[h] : NodeId::invalid());
      }
      r.shrinks = woven.shrinks;
      r.complex.num_nodes =
          pillow ? base + woven.complex.num_nodes : base + (woven.complex.num_nodes - m);
      r.stats = woven.stats;
      r.trace = woven.trace;
      return r;
    };
    weave::WeaveResult result = join(options.always_pillow);
    stc::ValidationReport check = stc::validate_hex_complex(result.complex, &surface.surface);
    if (options.always_pillow && check.valid) {
      report.pillowed = true;
      report.pillow_hexes = base_moves.front.quads.size();
    }
    if (!check.valid) {
      report.direct_join_violation = check.summary();
      result = join(true);
      check = stc::validate_hex_complex(result.complex, &surface.surface);
      if (!check.valid) {
        // Not an output: the next way is tried. The pillow layer itself can hold two hexes
        // sharing four nodes off a face (two front faces on two opposite nodes of both), and
        // the fixed weave does not see the attached hexes' contacts.
        report.join_seconds += seconds_since(t);
        report.weave_failure +=
            (report.weave_failure.empty() ? "" : "; ") + std::string("neither joining the ") +
            std::to_string(report.attached_hexes) + " attached hexes to the " +
            std::to_string(report.woven_hexes) +
            " woven ones directly nor through a pillow layer gives a valid complex (direct: " +
            report.direct_join_violation + "; pillowed: " + check.summary() + ")";
        return std::nullopt;
      }
      report.pillowed = true;
      report.pillow_hexes = base_moves.front.quads.size();
    }
    result.dual = rebuild_dual(result.complex, surface.surface);
    report.join_seconds += seconds_since(t);
    return result;
  };
  const auto weave_fixed = [&] { return weave_fixed_on(moves, false); };
  // Fills the front by moves alone: the whole complex is the attached hexes.
  bool fill_tried = false;
  // A fill that stalled on a small even front, kept for the last way (below).
  std::optional<stc::LoopMoveResult> stalled;
  const auto fill = [&]() -> std::optional<weave::WeaveResult> {
    if (fill_tried || moves.front.quads.size() > options.fill_up_to) return std::nullopt;
    fill_tried = true;
    const auto t_fill = std::chrono::steady_clock::now();
    stc::LoopMoveResult filled = stc::fill_front(moves, options.search);
    report.search_seconds += seconds_since(t_fill);
    if (!filled.simple) {
      const std::size_t left = filled.front.quads.size();
      if (left <= options.fill_residual_up_to && left < moves.front.quads.size() && left % 2 == 0)
        stalled = std::move(filled);
      return std::nullopt;
    }
    weave::WeaveResult r;
    r.num_input_nodes = filled.num_input_nodes;
    r.complex = filled.hexes;
    r.hex_rule.assign(r.complex.hexes.size(), "attached");
    r.hex_shrink.assign(r.complex.hexes.size(), -1);
    const stc::ValidationReport check = stc::validate_hex_complex(r.complex, &surface.surface);
    if (!check.valid) {
      throw InternalError("self-intersecting loops: the " + std::to_string(r.complex.hexes.size()) +
                          " hexes that fill the front are not a valid complex (" + check.summary() +
                          "); please report this surface");
    }
    r.dual = rebuild_dual(r.complex, surface.surface);
    report.moves = std::move(filled);
    report.attached_hexes = r.complex.hexes.size();
    report.filled = true;
    return r;
  };

  // The ways, in order: the free weave without recovery pillows, the fill by moves (small
  // fronts), the free weave with recovery pillows, the weave with every front node fixed. On a
  // small front (at most `fill_up_to` faces) every way runs and the fewest hexes win (ties: the
  // earlier way); otherwise the first way that succeeds.
  const std::size_t first_pillows = weave_options.recovery_pillows;
  const std::size_t most = std::max(first_pillows, options.recovery_pillows);
  // With no hex attached, the first way is the plain weave of the surface: not run again
  // under the caller's rules when the caller has seen it block.
  const bool plain_seen = options.plain_weave_blocked && moves.moves.empty();
  std::vector<std::function<std::optional<weave::WeaveResult>()>> ways;
  const auto list_ways = [&](bool skip_plain) {
    ways.clear();
    const bool free_weaves = options.free_nodes && (moves.simple || options.weave_unsimple);
    if (free_weaves && !skip_plain) ways.emplace_back([&] { return weave_free(first_pillows); });
    ways.emplace_back(fill);
    if (free_weaves && most > first_pillows) ways.emplace_back([&] { return weave_free(most); });
    // With no hex attached, the weave of the fixed front is a free weave with `most` pillows.
    const bool fixed_is_free =
        moves.moves.empty() && free_weaves && (most > first_pillows || !skip_plain);
    if (moves.simple && !fixed_is_free) ways.emplace_back(weave_fixed);
    if (moves.simple && options.always_pillow) ways = {weave_fixed};
  };
  list_ways(plain_seen);
  const bool best_of = moves.front.quads.size() <= options.fill_up_to;
  const SelfCrossingReport base = report;
  const auto keep_totals = [&](SelfCrossingReport& into) {
    into.search_seconds = report.search_seconds;
    into.weave_seconds = report.weave_seconds;
    into.join_seconds = report.join_seconds;
    into.weave_failure = report.weave_failure;
    into.free_weave_violation = report.free_weave_violation;
    into.direct_join_violation = report.direct_join_violation;
  };
  std::optional<std::pair<weave::WeaveResult, SelfCrossingReport>> best;
  // Every way in turn (all of them with `best_of`), keeping the fewest hexes.
  const auto run_ways = [&](bool reliable_fallback) {
    for (const auto& way : ways) {
      SelfCrossingReport fresh = base;
      keep_totals(fresh);
      report = std::move(fresh);
      std::optional<weave::WeaveResult> r = way();
      if (!r) continue;
      report.reliable_fallback = reliable_fallback;
      if (!best || r->complex.hexes.size() < best->first.complex.hexes.size())
        best.emplace(std::move(*r), report);
      if (!best_of) break;
    }
  };
  run_ways(false);
  if (!best && options.reliable_fallback && moves.simple && !caller_weave_options.selection &&
      weave_options.rules == weave::RuleSet::Extended) {
    weave_options.rules = weave::RuleSet::Reliable;
    weave_options.selection = nullptr;
    report.weave_failure += "; then with the reliable rules: ";
    list_ways(false);
    run_ways(true);
  }
  if (!best && stalled && options.fill_residual_depth > 0) {
    // Last, when every way failed: the front a stalled fill left, meshed by this stage as a
    // surface of its own (its nodes fixed) and joined to the fill's hexes.
    weave_options = stage_weave_options();
    SelfCrossingReport fresh = base;
    keep_totals(fresh);
    report = std::move(fresh);
    std::optional<weave::WeaveResult> r;
    try {
      r = weave_fixed_on(*stalled, true);
    } catch (const InvalidInput& e) {
      report.weave_failure += std::string("; the front the fill left: ") + e.what();
    }
    if (r) {
      report.attached_hexes = stalled->hexes.hexes.size();
      report.fill_residual = stalled->front.quads.size();
      report.moves = std::move(*stalled);
      best.emplace(std::move(*r), report);
    }
  }
  if (best) {
    keep_totals(best->second);
    report = std::move(best->second);
    return std::move(best->first);
  }
  if (!moves.simple)
    throw give_up(moves, "the search for front moves gave up (" + moves.stop_reason + ")");
  if (moves.self_crossing_quads_before == 0 && moves.moves.empty()) {
    // A loop-clean surface (the rescue of a blocked weave): no move was needed or made.
    throw WeaveError(
        "the loops are simple, and every other way to weave the surface blocked "
        "too (" +
        report.weave_failure.substr(0, 900) + (report.weave_failure.size() > 900 ? " ..." : "") +
        "): a defect of the weaver, please report the input");
  }
  throw give_up(moves, "the loops are simple after " + std::to_string(moves.moves.size()) +
                           " attached hexes, but every weave of the front blocked");
}

}  // namespace stcweave::primal
