/// Edge classes by dihedral angle (seed sect. 4.2 and 4.4, Fig. 8) and the names of the rule
/// sets.

#include <string>

#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::weave {

std::string to_string(RuleSet rules) {
  switch (rules) {
    case RuleSet::Reliable:
      return "reliable";
    case RuleSet::Extended:
      return "extended";
  }
  return "?";
}

RuleSet rule_set_from_name(const std::string& name) {
  if (name == "reliable") return RuleSet::Reliable;
  if (name == "extended") return RuleSet::Extended;
  throw InvalidInput("unknown rule set '" + name + "': valid names are: reliable, extended");
}

EdgeClass classify_edge(double angle, const ExtendedParameters& p) {
  if (angle <= p.sharp) return EdgeClass::SharpConvex;
  if (angle <= p.little_sharp) return EdgeClass::LittleSharpConvex;
  if (angle <= p.flat) return EdgeClass::Flat;
  if (angle <= p.little_sharp_nonconvex) return EdgeClass::LittleSharpNonConvex;
  return EdgeClass::SharpNonConvex;
}

void check_parameters(const ExtendedParameters& p) {
  const bool ordered = p.sharp > 0.0 && p.sharp <= p.little_sharp && p.little_sharp <= p.flat &&
                       p.flat <= p.little_sharp_nonconvex && p.little_sharp_nonconvex < 360.0;
  if (!ordered) {
    throw InvalidInput("edge class thresholds out of order: need 0 < sharp (" +
                       short_number(p.sharp) + ") <= little_sharp (" +
                       short_number(p.little_sharp) + ") <= flat (" + short_number(p.flat) +
                       ") <= little_sharp_nonconvex (" + short_number(p.little_sharp_nonconvex) +
                       ") < 360 degrees");
  }
  if (!(p.second_convex_min_weight >= 0.0 && p.second_convex_min_weight <= 1.0))
    throw InvalidInput("second_convex_min_weight must be in [0, 1]");
}

std::string to_string(EdgeClass c) {
  switch (c) {
    case EdgeClass::SharpConvex:
      return "sharp convex";
    case EdgeClass::LittleSharpConvex:
      return "a little sharp convex";
    case EdgeClass::Flat:
      return "flat";
    case EdgeClass::LittleSharpNonConvex:
      return "a little sharp non-convex";
    case EdgeClass::SharpNonConvex:
      return "sharp non-convex";
  }
  return "?";
}

}  // namespace stcweave::weave
