/// The trace as an observer of the driver: each call becomes one `TraceEvent`, handed to
/// `WeaveOptions::on_trace` as it happens and kept when `WeaveOptions::trace` is set.

#include "trace.hpp"

#include <algorithm>
#include <cstddef>

namespace stcweave::weave {

void TraceRecorder::record(TraceEvent e) {
  if (options_.on_trace) options_.on_trace(e);
  if (options_.trace) events_.push_back(std::move(e));
}

void TraceRecorder::on_selection(std::size_t step, std::int32_t shrink,
                                 std::span<const TraceCandidate> candidates, std::size_t chosen,
                                 const std::string& reason, std::span<const std::string> filters,
                                 const std::string& decided_by) {
  TraceEvent e;
  e.kind = TraceEvent::Kind::Selection;
  e.step = step;
  if (options_.trace_chosen_only) {
    e.candidates.assign(candidates.begin() + static_cast<std::ptrdiff_t>(chosen),
                        candidates.begin() + static_cast<std::ptrdiff_t>(chosen) + 1);
    e.chosen = 0;
  } else {
    e.candidates.assign(candidates.begin(), candidates.end());
    e.chosen = static_cast<std::int32_t>(chosen);
  }
  e.reason = reason;
  e.filters.assign(filters.begin(), filters.end());
  e.decided_by = decided_by;
  e.shrink = shrink;
  record(std::move(e));
}

void TraceRecorder::on_rule(std::size_t step, std::int32_t shrink, const char* rule, NodeId node,
                            std::span<const FaceOwner> faces, HexId hex) {
  TraceEvent e;
  e.kind = TraceEvent::Kind::Rule;
  e.step = step;
  e.rule = rule;
  e.node = node;
  e.faces.reserve(faces.size());
  for (const FaceOwner& f : faces) e.faces.push_back(f.str());
  e.hex = hex;
  e.shrink = shrink;
  record(std::move(e));
}

void TraceRecorder::on_shrink_failed(std::size_t step, std::int32_t shrink,
                                     const std::string& reason) {
  TraceEvent e;
  e.kind = TraceEvent::Kind::ShrinkFailed;
  e.step = step;
  e.reason = reason;
  e.shrink = shrink;
  record(std::move(e));
}

void file_shrink_record(std::vector<ShrinkRecord>& records, ShrinkRecord r) {
  if (records.empty() || records.back().shrink < r.shrink) {
    records.push_back(std::move(r));
    return;
  }
  const auto it =
      std::lower_bound(records.begin(), records.end(), r.shrink,
                       [](const ShrinkRecord& s, std::int32_t i) { return s.shrink < i; });
  if (it != records.end() && it->shrink == r.shrink) {
    *it = std::move(r);
  } else {
    records.insert(it, std::move(r));
  }
}

void mark_shrink_failed(std::vector<ShrinkRecord>& records, std::int32_t shrink) {
  for (auto it = records.rbegin(); it != records.rend(); ++it) {
    if (it->shrink == shrink) {
      it->failed = true;
      return;
    }
  }
}

void ShrinkRecorder::on_selection(std::size_t /*step*/, std::int32_t shrink,
                                  std::span<const TraceCandidate> candidates, std::size_t chosen,
                                  const std::string& /*reason*/,
                                  std::span<const std::string> /*filters*/,
                                  const std::string& decided_by) {
  ShrinkRecord r;
  r.shrink = shrink;
  r.decided_by = decided_by;
  if (chosen < candidates.size()) {
    const TraceCandidate& c = candidates[chosen];
    r.loop = c.loop;
    r.side = c.side;
    r.length = c.length;
    r.depth = c.depth;
  }
  file_shrink_record(records_, std::move(r));
}

void ShrinkRecorder::on_shrink_failed(std::size_t /*step*/, std::int32_t shrink,
                                      const std::string& /*reason*/) {
  mark_shrink_failed(records_, shrink);
}

void ObserverList::on_selection(std::size_t step, std::int32_t shrink,
                                std::span<const TraceCandidate> candidates, std::size_t chosen,
                                const std::string& reason, std::span<const std::string> filters,
                                const std::string& decided_by) {
  for (WeaveObserver* o : observers_)
    o->on_selection(step, shrink, candidates, chosen, reason, filters, decided_by);
}

bool ObserverList::reads_every_candidate() const {
  return std::any_of(observers_.begin(), observers_.end(),
                     [](const WeaveObserver* o) { return o->reads_every_candidate(); });
}

void ObserverList::on_rule(std::size_t step, std::int32_t shrink, const char* rule, NodeId node,
                           std::span<const FaceOwner> faces, HexId hex) {
  for (WeaveObserver* o : observers_) o->on_rule(step, shrink, rule, node, faces, hex);
}

void ObserverList::on_shrink_failed(std::size_t step, std::int32_t shrink,
                                    const std::string& reason) {
  for (WeaveObserver* o : observers_) o->on_shrink_failed(step, shrink, reason);
}

}  // namespace stcweave::weave
