#include "weave_options.hpp"

#include "commands.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::cli {

void add_weave_options(CLI::App* sub, WeaveArgs& args) {
  weave::ExtendedParameters& p = args.extended;
  const std::string group = "Weaving";
  sub->add_option("--rules", args.rules,
                  "loop-selection rule set: extended (seed sect. 4-7: geometry-aware filters) or "
                  "reliable (smallest topological weight only)")
      ->capture_default_str()
      ->group(group);
  sub->add_option("--sharp", p.sharp,
                  "extended: dihedral angle (degrees) up to which an edge is sharp convex")
      ->check(kFinite)
      ->capture_default_str()
      ->group(group);
  sub->add_option("--little-sharp", p.little_sharp,
                  "extended: angle up to which an edge is a little sharp convex")
      ->check(kFinite)
      ->capture_default_str()
      ->group(group);
  sub->add_option("--flat", p.flat, "extended: angle up to which an edge is flat")
      ->check(kFinite)
      ->capture_default_str()
      ->group(group);
  sub->add_option("--little-sharp-nonconvex", p.little_sharp_nonconvex,
                  "extended: angle up to which an edge is a little sharp non-convex (above: "
                  "sharp non-convex)")
      ->check(kFinite)
      ->capture_default_str()
      ->group(group);
  const auto off = [&](const std::string& name, bool& flag, const std::string& what) {
    sub->add_flag_function(
           "--no-" + name, [&flag](std::int64_t) { flag = false; }, "extended: " + what)
        ->group(group);
  };
  off("parallel-crossing", p.parallel_crossing,
      "switch off the parallel crossing rule (sect. 4.5)");
  off("parallel-merging", p.parallel_merging,
      "switch off the parallel merging rule (sect. 5.1: closes a layer between two discs)");
  sub->add_flag("--nonconvexity-seam", p.nonconvexity_seam,
                "extended: switch on the non-convexity seam (sect. 5.2: folds a hex face onto an "
                "input quad; off by default, see docs/extended-rules.md)")
      ->group(group);
  off("nonconvex-filter", p.nonconvex_filter, "switch off the non-convex filter (sect. 4.4)");
  off("nonconvex-least", p.nonconvex_least,
      "when every side holds a non-convex edge, relax the non-convex filter entirely (by default "
      "it keeps the sides with the fewest)");
  off("depth-filter", p.depth_filter, "switch off the depth filter (sect. 4.1)");
  off("first-convex-filter", p.first_convex_filter,
      "switch off the first convex filter (sect. 4.2)");
  off("first-convex-rim", p.first_convex_rim,
      "the first convex filter drops a loop that crosses no sharp edge even when its side runs "
      "along a sharp rim (the seed's rule; by default such a side is kept)");
  off("second-convex-filter", p.second_convex_filter,
      "switch off the second convex filter (sect. 4.3)");
  sub->add_option(
         "--second-convex-min-weight", p.second_convex_min_weight,
         "extended: a side elimination weight (sharp side edges / loop length) below this "
         "counts as 0 (0: the seed's rule; 0.1: fewer than one sharp edge in ten is a stray one)")
      ->check(kFinite)
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0))
      ->group(group);
  off("second-convex-smaller-side", p.second_convex_smaller_side,
      "the second convex filter weighs the larger side of a loop too (the seed's rule; by "
      "default a side collapsing more faces than the other side of its loop weighs 0)");
  sub->add_flag_function(
         "--depth-before-convex", [&p](std::int64_t) { p.depth_after_convex = false; },
         "extended: apply the depth filter before the convex filters (the seed's order; by "
         "default it comes after them, see docs/extended-rules.md)")
      ->group(group);
  off("flat-cross-precondition", p.flat_cross_precondition,
      "switch off the geometric precondition of the cross (no cross on a too flat corner)");
  sub->add_option("--max-rules", args.max_rules,
                  "give up weaving after this many rule applications (0: 8 quads^1.5 + 20000)")
      ->check(kCount)
      ->capture_default_str()
      ->group(group);
  sub->add_option("--block-recovery", args.block_recovery,
                  "when every loop is blocked: auto (pillow blocked front faces and weave on, a "
                  "bounded search; then, for mesh, the other ways of the front-move stage; "
                  "docs/weave-recovery.md) or off (the block is an error, exit 3)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "off"}))
      ->group(group);
  sub->add_flag_function(
         "--keep-seam-blocking-shrinks",
         [&args](std::int64_t) { args.undo_seam_blocking_shrinks = false; },
         "never undo a loop shrink that leaves a valence-2 node whose seam is refused (by "
         "default a weave that blocks is woven again undoing such shrinks, and the front-move "
         "stage always undoes them; docs/weave-recovery.md \"Seams left blocked\")")
      ->group(group);
}

void apply_weave_options(const WeaveArgs& args, weave::WeaveOptions& options) {
  options.rules = weave::rule_set_from_name(args.rules);
  options.extended = args.extended;
  options.max_rules = args.max_rules;
  options.block_recovery = weave::block_recovery_from_name(args.block_recovery);
  // The flag switches off every undoing: the retry of a weave that blocked here, and (mesh)
  // the front-move stage's. --block-recovery off asks for the first block alone: no retry
  // either (the library's cut balls, which switch their recovery off, keep theirs).
  options.undo_seam_blocking_on_block =
      args.undo_seam_blocking_shrinks && options.block_recovery != weave::BlockRecovery::Off;
  weave::check_parameters(options.extended);
}

nlohmann::json weave_options_json(const weave::WeaveOptions& options) {
  nlohmann::json j;
  j["rules"] = weave::to_string(options.rules);
  j["block_recovery"] = weave::to_string(options.block_recovery);
  j["undo_seam_blocking_shrinks"] = options.undo_seam_blocking_shrinks;
  j["undo_seam_blocking_on_block"] = options.undo_seam_blocking_on_block;
  // The last ways after that retry (docs/weave-recovery.md "The fill"): only with it and with
  // the block recovery on.
  j["fill_up_to"] = options.fill_up_to;
  j["reliable_from_start"] = options.reliable_from_start;
  if (options.rules == weave::RuleSet::Extended) {
    const weave::ExtendedParameters& p = options.extended;
    j["sharp"] = p.sharp;
    j["little_sharp"] = p.little_sharp;
    j["flat"] = p.flat;
    j["little_sharp_nonconvex"] = p.little_sharp_nonconvex;
    j["parallel_crossing"] = p.parallel_crossing;
    j["parallel_merging"] = p.parallel_merging;
    j["nonconvexity_seam"] = p.nonconvexity_seam;
    j["nonconvex_filter"] = p.nonconvex_filter;
    j["nonconvex_least"] = p.nonconvex_least;
    j["depth_filter"] = p.depth_filter;
    j["first_convex_filter"] = p.first_convex_filter;
    j["first_convex_rim"] = p.first_convex_rim;
    j["second_convex_filter"] = p.second_convex_filter;
    j["second_convex_min_weight"] = p.second_convex_min_weight;
    j["second_convex_smaller_side"] = p.second_convex_smaller_side;
    j["depth_after_convex"] = p.depth_after_convex;
    j["flat_cross_precondition"] = p.flat_cross_precondition;
  }
  return j;
}

}  // namespace stcweave::cli
