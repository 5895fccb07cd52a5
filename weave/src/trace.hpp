#pragma once
/// \file
/// Observers of the driver kept private to the library: the trace recorder and a fan-out.

#include <vector>

#include "stcweave/weave/kernel.hpp"

namespace stcweave::weave {

/// Turns the driver's calls into `TraceEvent`s (`WeaveOptions::trace`, `on_trace`).
class TraceRecorder final : public WeaveObserver {
 public:
  explicit TraceRecorder(const WeaveOptions& options) : options_(options) {}
  void on_selection(std::size_t step, std::int32_t shrink,
                    std::span<const TraceCandidate> candidates, std::size_t chosen,
                    const std::string& reason, std::span<const std::string> filters,
                    const std::string& decided_by) override;
  void on_rule(std::size_t step, std::int32_t shrink, const char* rule, NodeId node,
               std::span<const FaceOwner> faces, HexId hex) override;
  void on_shrink_failed(std::size_t step, std::int32_t shrink, const std::string& reason) override;
  [[nodiscard]] bool reads_every_candidate() const override { return !options_.trace_chosen_only; }
  /// The events kept (with `WeaveOptions::trace`).
  std::vector<TraceEvent> take() { return std::move(events_); }

 private:
  void record(TraceEvent e);
  const WeaveOptions& options_;
  std::vector<TraceEvent> events_;
};

/// Keeps one `ShrinkRecord` per shrink (`WeaveResult::shrinks`): always on, it reads only the
/// chosen candidate and nothing per rule.
class ShrinkRecorder final : public WeaveObserver {
 public:
  void on_selection(std::size_t step, std::int32_t shrink,
                    std::span<const TraceCandidate> candidates, std::size_t chosen,
                    const std::string& reason, std::span<const std::string> filters,
                    const std::string& decided_by) override;
  void on_rule(std::size_t /*step*/, std::int32_t /*shrink*/, const char* /*rule*/, NodeId /*node*/,
               std::span<const FaceOwner> /*faces*/, HexId /*hex*/) override {}
  void on_shrink_failed(std::size_t step, std::int32_t shrink, const std::string& reason) override;
  [[nodiscard]] bool reads_every_candidate() const override { return false; }
  std::vector<ShrinkRecord> take() { return std::move(records_); }

 private:
  std::vector<ShrinkRecord> records_;
};

/// Hands every call to each observer in turn.
class ObserverList final : public WeaveObserver {
 public:
  void add(WeaveObserver* o) { observers_.push_back(o); }
  [[nodiscard]] bool empty() const { return observers_.empty(); }
  [[nodiscard]] std::size_t size() const { return observers_.size(); }
  [[nodiscard]] WeaveObserver* front() const { return observers_.front(); }
  void on_selection(std::size_t step, std::int32_t shrink,
                    std::span<const TraceCandidate> candidates, std::size_t chosen,
                    const std::string& reason, std::span<const std::string> filters,
                    const std::string& decided_by) override;
  void on_rule(std::size_t step, std::int32_t shrink, const char* rule, NodeId node,
               std::span<const FaceOwner> faces, HexId hex) override;
  void on_shrink_failed(std::size_t step, std::int32_t shrink, const std::string& reason) override;
  [[nodiscard]] bool reads_every_candidate() const override;

 private:
  std::vector<WeaveObserver*> observers_;
};

}  // namespace stcweave::weave
