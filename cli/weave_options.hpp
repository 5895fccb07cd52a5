#pragma once
/// \file
/// The weaving options shared by the commands that weave (`mesh`, `bench` through `mesh`):
/// the rule set, the extended rule set's thresholds and switches, the rule budget.

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "stcweave/weave/weave.hpp"

namespace stcweave::cli {

struct WeaveArgs {
  std::string rules = "extended";
  weave::ExtendedParameters extended;
  std::size_t max_rules = 0;
  std::string block_recovery = "auto";
  bool undo_seam_blocking_shrinks = true;
};

/// Adds --rules, the four angle thresholds, one --no-<switch> flag per filter or rule of the
/// extended set, --max-rules, --block-recovery and --keep-seam-blocking-shrinks to `sub`, in
/// an option group "Weaving".
void add_weave_options(CLI::App* sub, WeaveArgs& args);

/// Copies the parsed arguments into `options`. \throw InvalidInput for an unknown rule set or
/// thresholds out of order.
void apply_weave_options(const WeaveArgs& args, weave::WeaveOptions& options);

/// The parameters as recorded in a report.
[[nodiscard]] nlohmann::json weave_options_json(const weave::WeaveOptions& options);

}  // namespace stcweave::cli
