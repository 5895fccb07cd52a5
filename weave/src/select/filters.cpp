/// The filters of the seed's Fig. 15 as values, the two rule sets as lists of them, and the
/// one ranking function that runs any list.

#include <algorithm>
#include <array>
#include <cstdint>

#include "candidates.hpp"
#include "stcweave/weave/second_convex_threshold.hpp"
#include "stcweave/weave/select.hpp"

namespace stcweave::weave {

namespace {
unsigned reads_nothing(const TraceCandidate& /*c*/) {
  return 0U;
}
}  // namespace

Filter parallel_crossing_filter() {
  Filter f;
  f.name = "parallel_crossing";
  f.kind = Filter::Kind::Decide;
  f.keep = [](const TraceCandidate& c) { return c.parallel_to >= 0; };
  f.reads = reads_nothing;
  f.reason = [](const std::vector<TraceCandidate>& kept) {
    return "parallel crossing: runs along loop " + std::to_string(kept.front().parallel_to) +
           " across sharp convex edges; fewest faces collapsed";
  };
  return f;
}

Filter nonconvex_filter() {
  Filter f;
  f.name = "nonconvex";
  f.keep = [](const TraceCandidate& c) { return c.nonconvex_on_side == 0; };
  f.reads = [](const TraceCandidate& /*c*/) { return side_property::kNonconvex; };
  f.may_relax = true;  // the seed stops here ("not supported"); we go on
  return f;
}

Filter nonconvex_filter(bool least) {
  Filter f = nonconvex_filter();
  if (least) {
    f.relax_cost = [](const TraceCandidate& c) { return static_cast<double>(c.nonconvex_on_side); };
    f.relax_reads = [](const TraceCandidate& /*c*/) {
      return side_property::kNonconvex | side_property::kNonconvexCount;
    };
  }
  return f;
}

Filter depth_filter() {
  Filter f;
  f.name = "depth";
  f.kind = Filter::Kind::Least;
  f.cost = [](const TraceCandidate& c) { return static_cast<double>(c.depth); };
  f.reads = [](const TraceCandidate& /*c*/) { return side_property::kDepth; };
  return f;
}

Filter first_convex_filter() {
  Filter f;
  f.name = "first_convex";
  f.keep = [](const TraceCandidate& c) { return c.crossed_sharp > 0; };
  f.reads = reads_nothing;
  f.may_relax = true;
  return f;
}

Filter first_convex_filter(bool rim) {
  Filter f = first_convex_filter();
  if (rim) {
    f.keep = [](const TraceCandidate& c) {
      return c.crossed_sharp > 0 || (c.length > 0 && c.side_sharp >= c.length);
    };
  }
  return f;
}

Filter second_convex_filter() {
  Filter f;
  f.name = "second_convex";
  f.kind = Filter::Kind::Least;
  // the highest side elimination weight: sharp convex side edges / loop length
  f.cost = [](const TraceCandidate& c) {
    return -(static_cast<double>(c.side_sharp) /
             static_cast<double>(std::max<std::size_t>(1, c.length)));
  };
  f.reads = reads_nothing;
  return f;
}

double side_elimination_weight(const TraceCandidate& c, const TraceCandidate* other,
                               double min_weight, bool smaller_side) {
  if (smaller_side && other != nullptr && c.faces_collapsed > other->faces_collapsed) return 0.0;
  const double w =
      static_cast<double>(c.side_sharp) / static_cast<double>(std::max<std::size_t>(1, c.length));
  return w + 1e-12 >= min_weight ? w : 0.0;
}

Filter second_convex_filter(double min_weight, bool smaller_side) {
  Filter f = second_convex_filter();
  f.cost_with_other = [min_weight, smaller_side](const TraceCandidate& c,
                                                 const TraceCandidate* other) {
    return -side_elimination_weight(c, other, min_weight, smaller_side);
  };
  // The faces of both sides matter only to a weight that is not 0 anyway.
  f.reads = [min_weight, smaller_side](const TraceCandidate& c) {
    if (!smaller_side) return 0U;
    return side_elimination_weight(c, nullptr, min_weight, false) > 0.0 ? side_property::kFaces
                                                                        : 0U;
  };
  return f;
}

Selection reliable_selection() {
  Selection s;
  s.name = "reliable";
  s.order = [](const TraceCandidate& p, const TraceCandidate& q) { return p.weight < q.weight; };
  s.last = "weight";
  s.last_reason = "smallest weight (strictly on side + on strip)";
  return s;
}

Selection extended_selection(const ExtendedParameters& p) {
  Selection s;
  s.name = "extended";
  s.geometric = true;
  s.order = [](const TraceCandidate& a, const TraceCandidate& b) {
    if (a.faces_collapsed != b.faces_collapsed) return a.faces_collapsed < b.faces_collapsed;
    return a.weight < b.weight;
  };
  if (p.parallel_crossing) s.filters.push_back(parallel_crossing_filter());
  if (p.nonconvex_filter) s.filters.push_back(nonconvex_filter(p.nonconvex_least));
  if (p.depth_filter && !p.depth_after_convex) s.filters.push_back(depth_filter());
  if (p.first_convex_filter) s.filters.push_back(first_convex_filter(p.first_convex_rim));
  if (p.second_convex_filter) {
    s.filters.push_back(
        second_convex_filter(p.second_convex_min_weight, p.second_convex_smaller_side));
  }
  if (p.depth_filter && p.depth_after_convex) s.filters.push_back(depth_filter());
  s.last = "topological";
  s.last_reason = "fewest faces collapsed";
  s.list_filters = true;
  s.order_fewest_faces_first = true;
  return s;
}

Selection selection_for(const WeaveOptions& options) {
  if (options.selection) return *options.selection;
  return options.rules == RuleSet::Extended ? extended_selection(options.extended)
                                            : reliable_selection();
}

namespace {

/// What the filters of a selection leave: indices into the candidates, in `selection.order`.
struct Filtered {
  std::vector<std::size_t> set;
  std::vector<std::string> filters;
  std::string reason;
  std::string decided_by;
};

/// The filters of `selection` on `all` (enumeration order), then the kept set ordered.
/// `ready(set, filter)` is called before `filter` reads the candidates of `set` and, with a
/// null filter, before the set left is ordered (it may fill in their side properties).
Filtered filter_candidates(
    const Selection& selection, std::vector<TraceCandidate>& all,
    const std::function<void(const std::vector<std::size_t>&, const Filter*)>& ready) {
  Filtered out;
  // Loops that cross themselves go last (unless there is nothing else).
  std::vector<std::size_t> set;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (!all[i].self_intersecting) set.push_back(i);
  if (set.empty()) {
    set.resize(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) set[i] = i;
  }
  // The other side of each candidate's loop, looked up in every candidate (an earlier filter
  // may have dropped it from `set`): index by loop, then side.
  std::vector<std::array<std::int32_t, 2>> by_loop;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const auto loop = static_cast<std::size_t>(std::max<std::int32_t>(0, all[i].loop));
    if (all[i].loop < 0 || all[i].side < 0 || all[i].side > 1) continue;
    if (by_loop.size() <= loop) by_loop.resize(loop + 1, {-1, -1});
    by_loop[loop][static_cast<std::size_t>(all[i].side)] = static_cast<std::int32_t>(i);
  }
  const auto other_side = [&](const TraceCandidate& c) -> const TraceCandidate* {
    if (c.loop < 0 || c.side < 0 || c.side > 1) return nullptr;
    const auto loop = static_cast<std::size_t>(c.loop);
    if (loop >= by_loop.size()) return nullptr;
    const std::int32_t i = by_loop[loop][static_cast<std::size_t>(1 - c.side)];
    return i < 0 ? nullptr : &all[static_cast<std::size_t>(i)];
  };
  const auto note = [&](const std::string& entry) {
    if (selection.list_filters) out.filters.push_back(entry);
  };
  // The candidates of `set` whose cost is at most the least one plus `slack`.
  const auto least_of = [&](const auto& cost, double slack) {
    std::vector<std::size_t> kept;
    double least = 0.0;
    bool first = true;
    for (const std::size_t i : set) {
      const double x = cost(all[i]);
      if (first || x < least) least = x;
      first = false;
    }
    for (const std::size_t i : set)
      if (cost(all[i]) <= least + slack) kept.push_back(i);
    return kept;
  };
  const Filter* decider = nullptr;
  for (const Filter& filter : selection.filters) {
    if (ready) ready(set, &filter);
    const std::size_t before = set.size();
    std::vector<std::size_t> kept;
    if (filter.kind == Filter::Kind::Least) {
      kept = least_of(
          [&](const TraceCandidate& c) {
            return filter.cost_with_other ? filter.cost_with_other(c, other_side(c))
                                          : filter.cost(c);
          },
          filter.slack);
    } else {
      for (const std::size_t i : set)
        if (filter.keep(all[i])) kept.push_back(i);
      if (kept.empty() && !set.empty() && filter.relax_cost && filter.kind == Filter::Kind::Keep) {
        Filter least;  // what the relaxation reads, for `ready`
        least.name = filter.name;
        least.reads = filter.relax_reads;
        if (ready) ready(set, &least);
        kept = least_of(filter.relax_cost, filter.slack);
        if (!kept.empty()) set = std::move(kept);  // a cost that is NaN everywhere keeps all
        note(filter.name + ":" + std::to_string(before) + "->least:" + std::to_string(set.size()));
        if (set.size() == 1 && out.decided_by.empty()) out.decided_by = filter.name;
        continue;
      }
    }
    if (filter.kind == Filter::Kind::Decide) {
      note(filter.name + ":" + std::to_string(kept.size()));
      if (!kept.empty()) {
        set = std::move(kept);
        out.decided_by = filter.name;
        decider = &filter;
        break;
      }
      continue;
    }
    if (kept.empty() && filter.may_relax) {
      note(filter.name + ":" + std::to_string(before) + "->relaxed");
      continue;
    }
    if (!kept.empty()) set = std::move(kept);
    note(filter.name + ":" + std::to_string(before) + "->" + std::to_string(set.size()));
    if (set.size() == 1 && out.decided_by.empty()) out.decided_by = filter.name;
  }
  if (ready) ready(set, nullptr);
  if (selection.order) {
    std::stable_sort(set.begin(), set.end(),
                     [&](std::size_t p, std::size_t q) { return selection.order(all[p], all[q]); });
  }
  if (decider != nullptr) {
    if (decider->reason) {
      std::vector<TraceCandidate> kept;
      kept.reserve(set.size());
      for (const std::size_t i : set) kept.push_back(all[i]);
      out.reason = decider->reason(kept);
    } else {
      out.reason = decider->name;
    }
  } else {
    note(selection.last + ":" + std::to_string(set.size()));
    if (out.decided_by.empty()) out.decided_by = selection.last;
    if (selection.list_filters) {
      std::string joined;
      for (const auto& f : out.filters) joined += (joined.empty() ? "" : ", ") + f;
      out.reason = "filters " + joined + "; " + selection.last_reason;
    } else {
      out.reason = selection.last_reason;
    }
  }
  out.set = std::move(set);
  return out;
}

}  // namespace

Ranking rank(const Selection& selection, std::vector<TraceCandidate> all) {
  Filtered f = filter_candidates(selection, all, nullptr);
  Ranking out;
  out.filters = std::move(f.filters);
  out.reason = std::move(f.reason);
  out.decided_by = std::move(f.decided_by);
  // The chosen set first (in order), then every other candidate in order.
  std::vector<char> in(all.size(), 0);
  for (const std::size_t i : f.set) in[i] = 1;
  std::vector<std::size_t> rest;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (in[i] == 0) rest.push_back(i);
  if (selection.order) {
    std::stable_sort(rest.begin(), rest.end(),
                     [&](std::size_t p, std::size_t q) { return selection.order(all[p], all[q]); });
  }
  out.order.reserve(all.size());
  for (const std::size_t i : f.set) out.order.push_back(all[i]);
  for (const std::size_t i : rest) out.order.push_back(all[i]);
  return out;
}

Ranking rank_first(const Selection& selection, CandidateSet& candidates) {
  std::vector<TraceCandidate>& all = candidates.all();
  const auto ready = [&](const std::vector<std::size_t>& set, const Filter* filter) {
    if (filter == nullptr && selection.order_fewest_faces_first) {
      candidates.bound_faces(set);  // the order: only the first must be exact
      return;
    }
    for (const std::size_t i : set) {
      const TraceCandidate& c = all[i];
      const unsigned reads = filter == nullptr ? side_property::kAll
                             : filter->reads   ? filter->reads(c)
                                               : side_property::kAll;
      if ((reads & ~candidates.known(c.loop)) != 0U) candidates.complete(c.loop);
    }
  };
  Filtered f = filter_candidates(selection, all, ready);
  Ranking out;
  out.filters = std::move(f.filters);
  out.reason = std::move(f.reason);
  out.decided_by = std::move(f.decided_by);
  if (f.set.empty()) return out;
  const std::size_t first = f.set.front();
  out.order.reserve(all.size());
  out.order.push_back(all[first]);
  for (std::size_t i = 0; i < all.size(); ++i)
    if (i != first) out.order.push_back(all[i]);
  return out;
}

namespace experimental {

Filter depth_within_one_filter() {
  Filter f = depth_filter();
  f.name = "depth_within_one";
  f.slack = 1.0;
  return f;
}

Selection extended_soft_depth_selection(const ExtendedParameters& parameters) {
  Selection s = extended_selection(parameters);
  s.name = "extended-soft-depth";
  for (Filter& f : s.filters)
    if (f.name == "depth") f = depth_within_one_filter();
  return s;
}

}  // namespace experimental

}  // namespace stcweave::weave
