#pragma once
/// \file
/// Typed ids for every entity of the project: a `QuadId` cannot be passed where a `NodeId`
/// is expected. Each id is a 32-bit index with an explicit invalid value and a printable
/// prefix (`q12`, `n3`, `l0`, `s4`, `c7`, `h9`).

#include <compare>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace stcweave {

/// A typed index. `Tag::kPrefix` names the entity in messages.
template <class Tag>
class Id {
 public:
  using value_type = std::int32_t;

  constexpr Id() = default;
  constexpr explicit Id(value_type value) : value_(value) {}
  /// Convenience for indices coming from containers.
  constexpr explicit Id(std::size_t value) : value_(static_cast<value_type>(value)) {}

  [[nodiscard]] static constexpr Id invalid() { return Id(); }
  [[nodiscard]] constexpr bool is_valid() const { return value_ >= 0; }
  [[nodiscard]] constexpr value_type value() const { return value_; }
  /// The id as a container index. \pre is_valid().
  [[nodiscard]] constexpr std::size_t index() const { return static_cast<std::size_t>(value_); }

  // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 misreads a defaulted <=>
  friend constexpr auto operator<=>(Id, Id) = default;

  /// `q12`, or `q?` for the invalid id.
  [[nodiscard]] std::string str() const {
    return std::string(Tag::kPrefix) + (is_valid() ? std::to_string(value_) : std::string("?"));
  }
  friend std::ostream& operator<<(std::ostream& os, Id id) { return os << id.str(); }

 private:
  value_type value_ = -1;
};

struct NodeTag {
  static constexpr const char* kPrefix = "n";
};
struct QuadTag {
  static constexpr const char* kPrefix = "q";
};
struct LoopTag {
  static constexpr const char* kPrefix = "l";
};
struct SheetTag {
  static constexpr const char* kPrefix = "s";
};
struct ChordTag {
  static constexpr const char* kPrefix = "c";
};
struct HexTag {
  static constexpr const char* kPrefix = "h";
};
struct ComponentTag {
  static constexpr const char* kPrefix = "component ";
};

using NodeId = Id<NodeTag>;            ///< a mesh vertex (primal)
using QuadId = Id<QuadTag>;            ///< a quad of a surface (input quad or front face)
using LoopId = Id<LoopTag>;            ///< a loop (closed dual curve) of a quad surface
using SheetId = Id<SheetTag>;          ///< a sheet (dual surface of a layer of hexes)
using ChordId = Id<ChordTag>;          ///< a chord (dual curve of a column of hexes)
using HexId = Id<HexTag>;              ///< a hexahedron = an STC vertex
using ComponentId = Id<ComponentTag>;  ///< a connected component of a surface

}  // namespace stcweave

template <class Tag>
struct std::hash<stcweave::Id<Tag>> {
  std::size_t operator()(stcweave::Id<Tag> id) const noexcept {
    return std::hash<std::int32_t>()(id.value());
  }
};
