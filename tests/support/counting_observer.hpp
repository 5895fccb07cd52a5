#pragma once
/// A weave observer that counts selections and failed shrinks. It reads every candidate (the
/// default `reads_every_candidate`), so attaching it makes the driver compute every candidate
/// of every selection: tests compare such a weave with the one that computes them in part.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "stcweave/weave/kernel.hpp"

namespace stcweave::test {

class CountingObserver final : public weave::WeaveObserver {
 public:
  std::size_t selections = 0;
  std::size_t failed = 0;
  void on_selection(std::size_t, std::int32_t, std::span<const weave::TraceCandidate>, std::size_t,
                    const std::string&, std::span<const std::string>, const std::string&) override {
    ++selections;
  }
  void on_rule(std::size_t, std::int32_t, const char*, NodeId, std::span<const weave::FaceOwner>,
               HexId) override {}
  void on_shrink_failed(std::size_t, std::int32_t, const std::string&) override { ++failed; }
};

}  // namespace stcweave::test
