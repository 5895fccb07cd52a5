/// \file
/// Pinched face pairs (docs/geometry.md "Repair"): two distinct quad faces of a hex complex
/// that share two consecutive edges at a node (found by `stc::pinched_faces`). No placement
/// makes every hex around them valid, so the positioning names them as topology, and
/// `unpinch` removes them by pillowing.
#include "position_pinch.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "stcweave/stc/validate.hpp"

namespace stcweave::primal {
namespace {

/// The sorted node quadruple of a face cycle.
std::array<std::int32_t, 4> face_key(const std::array<std::int32_t, 4>& cycle) {
  std::array<std::int32_t, 4> key = cycle;
  std::sort(key.begin(), key.end());
  return key;
}

/// The hexes having the face `key`, in hex order.
std::vector<std::size_t> hexes_on_face(const stc::HexComplex& complex,
                                       const std::array<std::int32_t, 4>& key) {
  std::vector<std::size_t> out;
  for (std::size_t h = 0; h < complex.hexes.size(); ++h) {
    for (int f = 0; f < 6; ++f) {
      const stc::Quad q = stc::hex_face(complex.hexes[h], f);
      std::array<std::int32_t, 4> c{};
      for (std::size_t i = 0; i < 4; ++i) c[i] = q[i].value();
      if (face_key(c) == key) {
        out.push_back(h);
        break;
      }
    }
  }
  return out;
}

/// `mesh` with the hexes `block` pillowed: every node of theirs copied (a third of the way
/// to their centroid), the block moved to the copies, one hex per outer face of the block
/// (faces in one block hex only) between the face and its copy, the face outward as face 0.
HexMesh pillow_block(const HexMesh& mesh, const std::vector<std::size_t>& block) {
  HexMesh out = mesh;
  std::vector<std::int32_t> nodes;
  for (const std::size_t h : block)
    for (const NodeId v : mesh.complex.hexes[h]) nodes.push_back(v.value());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  for (const std::int32_t v : nodes) centre += mesh.points.row(v);
  centre /= static_cast<double>(nodes.size());
  const auto n0 = static_cast<std::int32_t>(mesh.complex.num_nodes);
  const auto copy = [&](NodeId v) {
    const auto it = std::lower_bound(nodes.begin(), nodes.end(), v.value());
    return NodeId(n0 + static_cast<std::int32_t>(it - nodes.begin()));
  };
  out.points.conservativeResize(mesh.points.rows() + static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Eigen::RowVector3d p = mesh.points.row(nodes[i]);
    out.points.row(n0 + static_cast<Eigen::Index>(i)) = p + (centre - p) / 3.0;
  }
  // Outer faces: block faces not shared by two block hexes.
  std::vector<std::pair<std::array<std::int32_t, 4>, stc::Quad>> faces;
  for (const std::size_t h : block) {
    for (int f = 0; f < 6; ++f) {
      const stc::Quad q = stc::hex_face(mesh.complex.hexes[h], f);
      std::array<std::int32_t, 4> c{};
      for (std::size_t i = 0; i < 4; ++i) c[i] = q[i].value();
      faces.emplace_back(face_key(c), q);
    }
  }
  std::sort(faces.begin(), faces.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    if (j - i == 1) {
      const stc::Quad& q = faces[i].second;
      out.complex.hexes.push_back(
          {q[0], q[3], q[2], q[1], copy(q[0]), copy(q[3]), copy(q[2]), copy(q[1])});
    }
    i = j;
  }
  for (const std::size_t h : block)
    for (NodeId& v : out.complex.hexes[h]) v = copy(v);
  out.complex.num_nodes = mesh.complex.num_nodes + nodes.size();
  return out;
}

}  // namespace

UnpinchReport unpinch(HexMesh& mesh, std::size_t num_fixed, const stc::QuadSurface& boundary,
                      std::optional<std::vector<PinchedFaces>> found) {
  UnpinchReport r;
  std::vector<PinchedFaces> pinched = found ? std::move(*found) : pinched_faces(mesh.complex);
  r.pinched_before = pinched.size();
  // Each accepted block lowers the count, so this ends.
  bool progress = true;
  while (!pinched.empty() && progress) {
    progress = false;
    for (const PinchedFaces& p : pinched) {
      for (const auto* face : {&p.second, &p.first}) {
        const std::vector<std::size_t> block = hexes_on_face(mesh.complex, face_key(*face));
        if (block.size() != 2) continue;
        const bool touches_fixed = std::any_of(block.begin(), block.end(), [&](std::size_t h) {
          return std::any_of(mesh.complex.hexes[h].begin(), mesh.complex.hexes[h].end(),
                             [&](NodeId v) { return v.index() < num_fixed; });
        });
        if (touches_fixed) continue;
        HexMesh trial = pillow_block(mesh, block);
        if (!stc::validate_hex_complex(trial.complex, &boundary).valid) continue;
        std::vector<PinchedFaces> left = pinched_faces(trial.complex);
        if (left.size() >= pinched.size()) continue;
        r.nodes_added += trial.complex.num_nodes - mesh.complex.num_nodes;
        r.hexes_added += trial.complex.hexes.size() - mesh.complex.hexes.size();
        ++r.blocks;
        mesh = std::move(trial);
        pinched = std::move(left);
        progress = true;
        break;
      }
      if (progress) break;
    }
  }
  r.pinched_after = pinched.size();
  return r;
}

}  // namespace stcweave::primal
