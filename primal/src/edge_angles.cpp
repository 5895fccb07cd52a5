#include "stcweave/primal/edge_angles.hpp"

#include <cmath>
#include <numbers>
#include <unordered_map>

namespace stcweave::primal {

std::vector<std::array<double, 4>> dihedral_angles(const SurfaceMesh& mesh) {
  const auto& quads = mesh.surface.quads;
  std::vector<std::array<double, 4>> angles(quads.size(), {180.0, 180.0, 180.0, 180.0});
  std::vector<Eigen::Vector3d> normal(quads.size());
  const auto point = [&](NodeId n) -> Eigen::Vector3d {
    return mesh.points.row(n.value()).transpose();
  };
  for (std::size_t q = 0; q < quads.size(); ++q) {
    const auto& corners = quads[q];
    const Eigen::Vector3d n =
        (point(corners[2]) - point(corners[0])).cross(point(corners[3]) - point(corners[1]));
    const double len = n.norm();
    normal[q] = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
  }
  // directed edge (a, b) -> quad side holding it
  std::unordered_map<std::uint64_t, std::pair<std::size_t, int>> directed;
  directed.reserve(quads.size() * 4);
  const auto key = [](NodeId a, NodeId b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a.value())) << 32) |
           static_cast<std::uint32_t>(b.value());
  };
  for (std::size_t q = 0; q < quads.size(); ++q) {
    for (int i = 0; i < 4; ++i)
      directed[key(quads[q][static_cast<std::size_t>(i)],
                   quads[q][static_cast<std::size_t>((i + 1) % 4)])] = {q, i};
  }
  for (std::size_t q = 0; q < quads.size(); ++q) {
    for (int i = 0; i < 4; ++i) {
      const NodeId a = quads[q][static_cast<std::size_t>(i)];
      const NodeId b = quads[q][static_cast<std::size_t>((i + 1) % 4)];
      const auto it = directed.find(key(b, a));
      if (it == directed.end()) continue;
      const Eigen::Vector3d& na = normal[q];
      const Eigen::Vector3d& nb = normal[it->second.first];
      Eigen::Vector3d e = point(b) - point(a);
      const double len = e.norm();
      if (len == 0.0 || na.isZero() || nb.isZero()) continue;
      e /= len;
      // turning from this quad's normal to the neighbour's about the edge direction (a->b, the
      // quad's own orientation): a positive turn is a convex edge.
      const double turn = std::atan2(na.cross(nb).dot(e), na.dot(nb));
      angles[q][static_cast<std::size_t>(i)] = 180.0 - turn * 180.0 / std::numbers::pi;
    }
  }
  return angles;
}

}  // namespace stcweave::primal
