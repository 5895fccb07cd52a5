#include "support/shapes.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "stcweave/primal/generate.hpp"

namespace stcweave::test {

primal::MeshFile file_of(const primal::SurfaceMesh& surface, const std::string& name) {
  primal::MeshFile f;
  f.path = name;
  f.format = "memory";
  f.points = surface.points;
  f.quads = surface.surface.quads;
  return f;
}

primal::HexMesh box_hexes(int a, int b, int c, double sx, double sy, double sz) {
  primal::HexMesh m = primal::box_hexes(a, b, c);  // unit cubes, node (i, j, k) at (i, j, k)
  m.points.col(0) *= sx;
  m.points.col(1) *= sy;
  m.points.col(2) *= sz;
  return m;
}

primal::SurfaceMesh boundary_of(const primal::HexMesh& mesh) {
  std::map<std::array<NodeId, 4>, std::pair<int, stc::Quad>> faces;
  for (const auto& h : mesh.complex.hexes) {
    for (int f = 0; f < 6; ++f) {
      const stc::Quad q = stc::hex_face(h, f);
      auto key = q;
      std::sort(key.begin(), key.end());
      auto& entry = faces[key];
      entry.first += 1;
      entry.second = q;
    }
  }
  std::vector<stc::Quad> quads;
  for (const auto& [key, entry] : faces)
    if (entry.first == 1) quads.push_back(entry.second);
  std::map<NodeId, NodeId> renumber;
  for (const auto& q : quads)
    for (NodeId v : q) renumber.emplace(v, NodeId::invalid());
  int next = 0;
  for (auto& [old, now] : renumber) now = NodeId(next++);
  primal::SurfaceMesh s;
  s.points.resize(next, 3);
  for (const auto& [old, now] : renumber) s.points.row(now.value()) = mesh.points.row(old.value());
  for (auto q : quads) {
    for (auto& v : q) v = renumber.at(v);
    s.surface.quads.push_back(q);
  }
  s.surface.num_nodes = static_cast<std::size_t>(next);
  return s;
}

primal::SurfaceMesh box_surface(int a, int b, int c, double sx, double sy, double sz) {
  return boundary_of(box_hexes(a, b, c, sx, sy, sz));
}

primal::HexMesh voxel_hexes(const std::vector<std::array<int, 3>>& cells) {
  primal::HexMesh m;
  std::map<std::array<int, 3>, NodeId> ids;
  std::vector<std::array<int, 3>> corners;
  const auto node = [&](int i, int j, int k) {
    const auto [it, fresh] = ids.emplace(std::array<int, 3>{i, j, k}, NodeId(corners.size()));
    if (fresh) corners.push_back({i, j, k});
    return it->second;
  };
  for (const auto& [i, j, k] : cells)
    m.complex.hexes.push_back({node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k),
                               node(i, j + 1, k), node(i, j, k + 1), node(i + 1, j, k + 1),
                               node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)});
  m.points.resize(static_cast<Eigen::Index>(corners.size()), 3);
  for (std::size_t n = 0; n < corners.size(); ++n)
    m.points.row(static_cast<Eigen::Index>(n)) << corners[n][0], corners[n][1], corners[n][2];
  m.complex.num_nodes = corners.size();
  return m;
}

primal::SurfaceMesh voxel_surface(const std::vector<std::array<int, 3>>& cells) {
  return boundary_of(voxel_hexes(cells));
}

std::vector<std::array<int, 3>> lblock_cells() {
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        if (i == 0 || j == 0) cells.push_back({i, j, k});
  return cells;
}

std::vector<std::array<int, 3>> ring_cells() {
  std::vector<std::array<int, 3>> cells;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      if (i != 1 || j != 1) cells.push_back({i, j, 0});
  return cells;
}

primal::SurfaceMesh bar_surface(const std::vector<std::array<Eigen::RowVector3d, 4>>& sections) {
  const int n = static_cast<int>(sections.size()) - 1;
  primal::HexMesh column = box_hexes(1, 1, n);
  // box node (i, j, k) has id i + 2 (j + 2 k); corner c of a section is (i, j) below
  constexpr std::array<std::array<int, 2>, 4> kCorner = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
  for (int k = 0; k <= n; ++k)
    for (std::size_t c = 0; c < 4; ++c)
      column.points.row(kCorner[c][0] + 2 * (kCorner[c][1] + 2 * k)) =
          sections[static_cast<std::size_t>(k)][c];
  return boundary_of(column);
}

PlanarQuads ogrid_disk(double s) {
  PlanarQuads d;
  // inner grid: point (i, j) for i, j in {0, 1, 2} has index i + 3 j
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) d.points.emplace_back((i - 1) * s, (j - 1) * s);
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i)
      d.quads.push_back({i + 3 * j, i + 1 + 3 * j, i + 1 + 3 * (j + 1), i + 3 * (j + 1)});
  // the 8 boundary points of the grid counter-clockwise, each joined to a circle point
  const std::array<int, 8> ring = {0, 1, 2, 5, 8, 7, 6, 3};
  for (int k = 0; k < 8; ++k) {
    const Eigen::RowVector2d p =
        d.points[static_cast<std::size_t>(ring[static_cast<std::size_t>(k)])];
    d.points.push_back(p.normalized());
  }
  for (int k = 0; k < 8; ++k) {
    const int next = (k + 1) % 8;
    d.quads.push_back(
        {ring[static_cast<std::size_t>(k)], 9 + k, 9 + next, ring[static_cast<std::size_t>(next)]});
  }
  return d;
}

primal::HexMesh extruded_hexes(const PlanarQuads& section, const std::vector<double>& heights) {
  primal::HexMesh m;
  const auto n = static_cast<int>(section.points.size());
  const auto id = [n](int point, int layer) { return NodeId(point + n * layer); };
  m.points.resize(static_cast<Eigen::Index>(section.points.size() * heights.size()), 3);
  for (std::size_t k = 0; k < heights.size(); ++k)
    for (std::size_t p = 0; p < section.points.size(); ++p)
      m.points.row(id(static_cast<int>(p), static_cast<int>(k)).value()) << section.points[p].x(),
          section.points[p].y(), heights[k];
  m.complex.num_nodes = static_cast<std::size_t>(m.points.rows());
  for (int k = 0; k + 1 < static_cast<int>(heights.size()); ++k)
    for (const auto& q : section.quads)
      m.complex.hexes.push_back({id(q[0], k), id(q[1], k), id(q[2], k), id(q[3], k),
                                 id(q[0], k + 1), id(q[1], k + 1), id(q[2], k + 1),
                                 id(q[3], k + 1)});
  return m;
}

primal::SurfaceMesh rhombic_dodecahedron() {
  primal::SurfaceMesh s;
  // nodes 0..7: cube corners (+-1,+-1,+-1); 8..13: (+-2,0,0), (0,+-2,0), (0,0,+-2)
  s.points.resize(14, 3);
  for (int i = 0; i < 8; ++i)
    s.points.row(i) << ((i & 1) ? 1 : -1), ((i & 2) ? 1 : -1), ((i & 4) ? 1 : -1);
  s.points.row(8) << 2, 0, 0;
  s.points.row(9) << -2, 0, 0;
  s.points.row(10) << 0, 2, 0;
  s.points.row(11) << 0, -2, 0;
  s.points.row(12) << 0, 0, 2;
  s.points.row(13) << 0, 0, -2;
  // one rhombus per cube edge: its two corners and the two axis points adjacent to both
  for (int u = 0; u < 8; ++u) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      const int v = u | bit;
      if (v == u) continue;
      std::vector<int> axis;
      for (int p = 8; p < 14; ++p) {
        const Eigen::RowVector3d ap = s.points.row(p);
        if ((ap - s.points.row(u)).squaredNorm() < 3.5 &&
            (ap - s.points.row(v)).squaredNorm() < 3.5)
          axis.push_back(p);
      }
      stc::Quad q{NodeId(u), NodeId(axis[0]), NodeId(v), NodeId(axis[1])};
      const Eigen::RowVector3d p0 = s.points.row(u), p1 = s.points.row(axis[0]),
                               p2 = s.points.row(v);
      const Eigen::RowVector3d normal = (p1 - p0).cross(p2 - p1);
      if (normal.dot(p0 + p2) < 0) q = stc::reversed(q);
      s.surface.quads.push_back(q);
    }
  }
  s.surface.num_nodes = 14;
  return s;
}

primal::SurfaceMesh reversed_surface(primal::SurfaceMesh mesh) {
  for (auto& q : mesh.surface.quads) q = stc::reversed(q);
  return mesh;
}

primal::SurfaceMesh torus_surface(int around, int along, double big_r, double r) {
  primal::SurfaceMesh m;
  m.points.resize(around * along, 3);
  const double pi = 3.14159265358979323846;
  const auto id = [&](int i, int j) { return NodeId(((j % along) * around) + (i % around)); };
  for (int j = 0; j < along; ++j) {
    const double phi = 2.0 * pi * j / along;
    for (int i = 0; i < around; ++i) {
      const double theta = 2.0 * pi * i / around;
      const double rho = big_r + r * std::cos(theta);
      m.points.row(id(i, j).value()) =
          Eigen::RowVector3d(rho * std::cos(phi), rho * std::sin(phi), r * std::sin(theta));
    }
  }
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i)
      m.surface.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  m.surface.num_nodes = static_cast<std::size_t>(around * along);
  // Outward: positive signed volume.
  double volume = 0.0;
  for (const auto& q : m.surface.quads) {
    const Eigen::Vector3d p0 = m.points.row(q[0].value()), p1 = m.points.row(q[1].value()),
                          p2 = m.points.row(q[2].value()), p3 = m.points.row(q[3].value());
    volume += p0.dot(p1.cross(p2)) + p0.dot(p2.cross(p3));
  }
  if (volume < 0.0)
    for (auto& q : m.surface.quads) q = stc::reversed(q);
  return m;
}

primal::SurfaceMesh merged_surfaces(const std::vector<primal::SurfaceMesh>& surfaces) {
  primal::SurfaceMesh m;
  Eigen::Index rows = 0;
  for (const auto& s : surfaces) rows += s.points.rows();
  m.points.resize(rows, 3);
  std::size_t offset = 0;
  for (const auto& s : surfaces) {
    m.points.middleRows(static_cast<Eigen::Index>(offset), s.points.rows()) = s.points;
    for (stc::Quad q : s.surface.quads) {
      for (NodeId& v : q) v = NodeId(v.index() + offset);
      m.surface.quads.push_back(q);
    }
    offset += static_cast<std::size_t>(s.points.rows());
  }
  m.surface.num_nodes = offset;
  return m;
}

primal::SurfaceMesh translated(primal::SurfaceMesh mesh, const Eigen::RowVector3d& offset) {
  mesh.points.rowwise() += offset;
  return mesh;
}

SplitTriangles split_triangles(const std::vector<std::array<int, 3>>& triangles,
                               const primal::Points& vertices) {
  SplitTriangles b;
  int next = static_cast<int>(vertices.rows());
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> key = std::minmax(t[k], t[(k + 1) % 3]);
      if (b.edge_node.find(key) == b.edge_node.end()) b.edge_node[key] = NodeId(next++);
    }
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) b.centre.push_back(NodeId(next++));
  primal::Points& p = b.mesh.points;
  p.resize(next, 3);
  p.topRows(vertices.rows()) = vertices;
  for (const auto& [key, node] : b.edge_node)
    p.row(node.value()) = 0.5 * (vertices.row(key.first) + vertices.row(key.second));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    p.row(b.centre[t].value()) =
        (vertices.row(tri[0]) + vertices.row(tri[1]) + vertices.row(tri[2])) / 3.0;
    for (int k = 0; k < 3; ++k) {
      const int v = tri[k];
      const int after = tri[(k + 1) % 3];
      const int before = tri[(k + 2) % 3];
      b.mesh.surface.quads.push_back({NodeId(v), b.edge_node.at(std::minmax(v, after)), b.centre[t],
                                      b.edge_node.at(std::minmax(before, v))});
    }
  }
  b.mesh.surface.num_nodes = static_cast<std::size_t>(next);
  return b;
}

primal::SurfaceMesh triangle_split_of(const primal::SurfaceMesh& quads) {
  std::vector<std::array<int, 3>> triangles;
  for (const stc::Quad& q : quads.surface.quads) {
    triangles.push_back({q[0].value(), q[1].value(), q[2].value()});
    triangles.push_back({q[0].value(), q[2].value(), q[3].value()});
  }
  return split_triangles(triangles, quads.points).mesh;
}

}  // namespace stcweave::test
