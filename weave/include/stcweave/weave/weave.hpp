#pragma once
/// \file
/// The weaving engine: fills a closed quad surface with hexahedra by shrinking its loops one
/// after the other (Reliable Whisker Weaving, seed sect. 2.2 and 7), working on the front in
/// the dual. `weave` knows no coordinates.
///
/// What it guarantees: on success, every input quad is a face of exactly one hex, every
/// other hex face is shared by exactly two hexes (the front is empty), input nodes keep their
/// ids, and every hex is positively oriented with respect to the outward input orientation
/// (its faces built on front faces are its outward faces). It does not certify the complex:
/// run `stc::validate_hex_complex` on the result (the CLI always does).

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "stcweave/stc/ids.hpp"
#include "stcweave/stc/quad_surface.hpp"

namespace stcweave::weave {

/// Which loop-selection rules run.
enum class RuleSet {
  /// Reliable Whisker Weaving: the (loop, side) with the smallest topological weight.
  Reliable,
};

/// Name of a rule set as used on the command line ("reliable").
[[nodiscard]] std::string to_string(RuleSet rules);
/// \throw InvalidInput for an unknown name.
[[nodiscard]] RuleSet rule_set_from_name(const std::string& name);

/// Progress report, given to `WeaveOptions::progress` now and then.
struct WeaveProgress {
  std::size_t front_faces = 0;  ///< faces still on the front
  std::size_t hexes = 0;        ///< hexes created so far
  std::size_t loops_shrunk = 0;
};

struct WeaveOptions {
  RuleSet rules = RuleSet::Reliable;
  /// Check the front invariants after every rule (slow: for debugging and tests).
  bool check = false;
  /// Record one trace event per loop selection and per rule application.
  bool trace = false;
  /// Give up after this many rule applications; 0 chooses 64 * quads^1.5 + 10^5.
  std::size_t max_rules = 0;
  /// Called every `progress_every` rules when set.
  std::function<void(const WeaveProgress&)> progress;
  std::size_t progress_every = 20000;
};

/// One neighbour of a hex face in the woven STC: another hex, or an input quad (a boundary
/// point of the STC).
struct DualLink {
  bool is_boundary = false;
  std::int32_t id = -1;         ///< HexId value, or QuadId value when `is_boundary`
  std::int8_t local_face = -1;  ///< face index in the neighbouring hex (kHexFaces order)
};

/// A candidate of one loop selection, as the trace reports it.
struct TraceCandidate {
  std::int32_t loop = -1;  ///< index of the loop in this selection's enumeration
  int side = 0;            ///< 0 = side A, 1 = side B (DESIGN.md "Sides of a loop")
  std::size_t length = 0;  ///< number of strip passages
  std::size_t strictly_on_side = 0;
  std::size_t on_strip = 0;
  std::size_t weight = 0;  ///< strictly_on_side + on_strip
  bool self_intersecting = false;
};

/// One line of the trace: a loop selection, a rule application, or a failed shrink.
struct TraceEvent {
  enum class Kind { Selection, Rule, ShrinkFailed };
  Kind kind = Kind::Rule;
  std::size_t step = 0;  ///< rules applied before this event
  // Selection: every candidate, sorted as ranked; `chosen` indexes `candidates`.
  std::vector<TraceCandidate> candidates;
  std::int32_t chosen = -1;
  std::string reason;  ///< why this candidate (or why the shrink failed)
  // Rule: which rule, at which node, on which front faces (their whiskers), which hex.
  std::string rule;  ///< "seam", "seam-coincident", "cross", "blind-chord"
  NodeId node;
  std::vector<std::string> faces;
  HexId hex;
  std::int32_t shrink = -1;  ///< index of the loop shrink in progress (-1: between shrinks)
};

struct WeaveStats {
  std::size_t selections = 0;
  std::size_t shrinks = 0;
  std::size_t failed_shrinks = 0;
  std::size_t seams = 0;
  std::size_t coincident_glues = 0;
  std::size_t crosses = 0;
  std::size_t blind_chords = 0;
  std::size_t blocked_seams = 0;  ///< seam attempts refused by a precondition
};

struct WeaveResult {
  /// The hexes. Input nodes keep their ids 0..num_input_nodes-1; interior nodes follow.
  stc::HexComplex complex;
  std::size_t num_input_nodes = 0;
  /// The woven STC: for each hex and each of its faces (kHexFaces order), what lies behind.
  std::vector<std::array<DualLink, 6>> dual;
  /// For each hex, the index of the loop shrink that created it (its layer).
  std::vector<std::int32_t> hex_shrink;
  /// For each hex, the rule that created it ("cross" or "blind-chord").
  std::vector<std::string> hex_rule;
  WeaveStats stats;
  std::vector<TraceEvent> trace;
};

/// Weaves the hex complex bounded by `surface`.
/// \pre `surface` is closed, edge- and vertex-manifold, consistently oriented outward, every
///      component of genus 0, no self-intersecting loop (`primal::require_weavable` checks
///      this; `weave` re-checks what it relies on).
/// \throw InvalidInput when the surface is not a valid front (open, pinched, degenerate).
/// \throw WeaveError when every (loop, side) is blocked, naming the blocked nodes and why.
/// \throw InternalError when an invariant breaks (with `options.check`).
/// \cite seed sect. 2.2 (loop shrinking, weights), sect. 7 (overall sequence).
WeaveResult weave(const stc::QuadSurface& surface, const WeaveOptions& options = {});

}  // namespace stcweave::weave
