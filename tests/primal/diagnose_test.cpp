/// Tests of primal/diagnose.hpp: figures, JSON, re-orientation, and one test per rejection
/// reason of require_weavable (each checks that the message names the elements).

#include "stcweave/primal/diagnose.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>

#include "stcweave/stc/errors.hpp"
#include "support/shapes.hpp"

namespace stcweave::primal {
namespace {

using ::testing::HasSubstr;

MeshFile file_of(const SurfaceMesh& mesh, const std::string& path = "test.obj") {
  MeshFile f;
  f.path = path;
  f.format = "obj";
  f.points = mesh.points;
  f.quads = mesh.surface.quads;
  return f;
}

MeshFile file_of(const HexMesh& mesh, const std::string& path = "test.vtk") {
  MeshFile f;
  f.path = path;
  f.format = "vtk";
  f.points = mesh.points;
  f.hexes = mesh.complex.hexes;
  return f;
}

/// Several meshes as one, nodes at the same position merged.
SurfaceMesh merged(const std::vector<SurfaceMesh>& parts) {
  SurfaceMesh out;
  std::map<std::tuple<double, double, double>, NodeId> ids;
  std::vector<Eigen::RowVector3d> rows;
  for (const auto& part : parts) {
    for (stc::Quad q : part.surface.quads) {
      for (NodeId& v : q) {
        const Eigen::RowVector3d p = part.points.row(v.value());
        auto [it, inserted] = ids.emplace(std::make_tuple(p(0), p(1), p(2)), NodeId(rows.size()));
        if (inserted) rows.push_back(p);
        v = it->second;
      }
      out.surface.quads.push_back(q);
    }
  }
  out.points.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i)
    out.points.row(static_cast<Eigen::Index>(i)) = rows[i];
  out.surface.num_nodes = rows.size();
  return out;
}

SurfaceMesh transformed(SurfaceMesh m, double scale, double x, double y, double z) {
  for (Eigen::Index r = 0; r < m.points.rows(); ++r)
    m.points.row(r) = scale * m.points.row(r) + Eigen::RowVector3d(x, y, z);
  return m;
}

/// k lunes (N, x_i, S, x_{i+1}) around the poles (0,0,+-1): k quads, an odd number for odd k.
SurfaceMesh pillow(int k) {
  SurfaceMesh m;
  m.points.resize(k + 2, 3);
  for (int i = 0; i < k; ++i)
    m.points.row(i) << std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0.0;
  m.points.row(k) << 0, 0, 1;
  m.points.row(k + 1) << 0, 0, -1;
  for (int i = 0; i < k; ++i)
    m.surface.quads.push_back({NodeId(k), NodeId((i + 1) % k), NodeId(k + 1), NodeId(i)});
  m.surface.num_nodes = static_cast<std::size_t>(k + 2);
  return m;
}

/// Every quad split into 2 x 2, new nodes at edge midpoints and quad centres.
SurfaceMesh refined(const SurfaceMesh& s) {
  SurfaceMesh out;
  std::map<std::pair<NodeId, NodeId>, NodeId> mid;
  std::vector<Eigen::RowVector3d> rows;
  for (Eigen::Index r = 0; r < s.points.rows(); ++r) rows.push_back(s.points.row(r));
  const auto midpoint = [&](NodeId a, NodeId b) {
    const auto key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
    auto [it, inserted] = mid.emplace(key, NodeId(rows.size()));
    if (inserted) rows.push_back((s.points.row(a.value()) + s.points.row(b.value())) / 2);
    return it->second;
  };
  for (const stc::Quad& q : s.surface.quads) {
    const NodeId m01 = midpoint(q[0], q[1]), m12 = midpoint(q[1], q[2]), m23 = midpoint(q[2], q[3]),
                 m30 = midpoint(q[3], q[0]);
    const NodeId c(rows.size());
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (NodeId v : q) centre += s.points.row(v.value()) / 4;
    rows.push_back(centre);
    out.surface.quads.push_back({q[0], m01, c, m30});
    out.surface.quads.push_back({m01, q[1], m12, c});
    out.surface.quads.push_back({c, m12, q[2], m23});
    out.surface.quads.push_back({m30, c, m23, q[3]});
  }
  out.points.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i)
    out.points.row(static_cast<Eigen::Index>(i)) = rows[i];
  out.surface.num_nodes = rows.size();
  return out;
}

/// An n x m Klein bottle (a torus grid whose seam is glued mirrored), placed on a circle.
SurfaceMesh klein_bottle(int n, int m) {
  SurfaceMesh s;
  s.points.resize(n * m, 3);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) s.points.row(i + n * j) << i, j, (i * 7 + j * 3) % 5;
  const auto node = [&](int i, int j) {
    if (j == m) {
      j = 0;
      i = n - i;
    }
    return NodeId(((i % n) + n) % n + n * j);
  };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i)
      s.surface.quads.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)});
  s.surface.num_nodes = static_cast<std::size_t>(n * m);
  return s;
}

double signed_volume(const SurfaceMesh& m) {
  double v = 0;
  for (const stc::Quad& q : m.surface.quads) {
    const Eigen::Vector3d p0 = m.points.row(q[0].value()), p1 = m.points.row(q[1].value()),
                          p2 = m.points.row(q[2].value()), p3 = m.points.row(q[3].value());
    v += (p0.dot(p1.cross(p2)) + p0.dot(p2.cross(p3))) / 6;
  }
  return v;
}

/// The message of require_weavable, or "" when it does not throw.
std::string rejection(const MeshFile& file) {
  try {
    require_weavable(diagnose(file));
  } catch (const TopologyError& e) {
    return e.what();
  }
  return "";
}

TEST(Diagnose, BoxSurface) {
  const SurfaceDiagnosis d = diagnose(file_of(test::box_surface(2, 3, 4)));
  EXPECT_FALSE(d.from_hexes);
  EXPECT_EQ(d.quads, 52u);
  EXPECT_EQ(d.nodes, 54u);
  EXPECT_EQ(d.components, 1u);
  EXPECT_TRUE(d.closed);
  EXPECT_TRUE(d.manifold);
  EXPECT_TRUE(d.consistently_oriented);
  EXPECT_EQ(d.orientable, true);
  EXPECT_EQ(d.euler_characteristic, 2);
  EXPECT_EQ(d.genus, 0);
  EXPECT_EQ(d.loops, 9u);
  EXPECT_EQ(d.longest_loop, 14u);
  EXPECT_EQ(d.self_intersecting_loops, 0u);
  EXPECT_EQ(d.self_crossing_quads, 0u);
  EXPECT_EQ(d.open_edges, 0u);
  EXPECT_EQ(d.nonmanifold_edges, 0u);
  EXPECT_EQ(d.coincident_nodes, 0u);
  EXPECT_TRUE(d.has_even_quads());
  EXPECT_NO_THROW(require_weavable(d));
}

TEST(Diagnose, HexMeshIsDiagnosedByItsBoundary) {
  const MeshFile file = file_of(test::box_hexes(2, 2, 3));
  const SurfaceDiagnosis d = diagnose(file);
  EXPECT_TRUE(d.from_hexes);
  EXPECT_EQ(d.hexes, 12u);
  EXPECT_EQ(d.quads, 32u);
  EXPECT_EQ(d.nodes, 34u);  // 36 nodes in the mesh, 2 of them inside
  EXPECT_EQ(d.orientable, std::nullopt);
  EXPECT_TRUE(d.consistently_oriented);
  EXPECT_EQ(d.genus, 0);
  EXPECT_EQ(d.loops, 7u);
  ASSERT_EQ(d.quad_origins.size(), 32u);
  EXPECT_NO_THROW(require_weavable(d));
  const nlohmann::json j = to_json(d);
  EXPECT_TRUE(j["orientable"].is_null());
  EXPECT_EQ(j["source"], "hex boundary");
  EXPECT_EQ(j["hexes"], 12);
}

TEST(Diagnose, SurfaceOfAHexMeshCompactsItsNodes) {
  const HexMesh hexes = test::box_hexes(2, 2, 2);
  std::vector<NodeId> file_nodes;
  const SurfaceMesh s = surface_of(file_of(hexes), &file_nodes);
  EXPECT_EQ(s.surface.num_quads(), 24u);
  EXPECT_EQ(s.surface.num_nodes, 26u);
  EXPECT_EQ(s.points.rows(), 26);
  ASSERT_EQ(file_nodes.size(), 26u);
  EXPECT_TRUE(std::is_sorted(file_nodes.begin(), file_nodes.end()));
  EXPECT_EQ(std::find(file_nodes.begin(), file_nodes.end(), NodeId(13)),
            file_nodes.end());  // centre
  for (std::size_t v = 0; v < file_nodes.size(); ++v)
    EXPECT_EQ(s.points.row(static_cast<Eigen::Index>(v)), hexes.points.row(file_nodes[v].value()));
  EXPECT_GT(signed_volume(s), 0.0);
}

TEST(Diagnose, JsonHasTheKeysOfExpectedJson) {
  const nlohmann::json j = to_json(diagnose(file_of(test::box_surface(1, 1, 1))));
  for (const char* key :
       {"quads", "nodes", "components", "closed", "manifold", "consistently_oriented", "orientable",
        "euler_characteristic", "genus", "loops", "self_intersecting_loops", "self_crossing_quads",
        "longest_loop", "open_edges", "nonmanifold_edges", "coincident_nodes"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["quads"], 6);
  EXPECT_EQ(j["loops"], 3);
  EXPECT_EQ(j["weavable"], true);
  EXPECT_EQ(j["quad_parity"], "even");
}

TEST(Diagnose, ReversedBoxIsReorientedWithAllQuadsFlipped) {
  SurfaceMesh m = test::reversed_surface(test::box_surface(2, 2, 3));
  ASSERT_LT(signed_volume(m), 0.0);
  const OrientationReport r = orient_outward(m);
  EXPECT_EQ(r.flipped_quads, 32u);
  EXPECT_GT(signed_volume(m), 0.0);
  EXPECT_EQ(m.surface.quads, test::box_surface(2, 2, 3).surface.quads);
}

TEST(Diagnose, OneMirroredQuadIsFlippedBack) {
  SurfaceMesh m = test::box_surface(2, 2, 2);
  const auto original = m.surface.quads;
  m.surface.quads[5] = stc::reversed(m.surface.quads[5]);
  EXPECT_FALSE(diagnose(file_of(m)).consistently_oriented);
  EXPECT_EQ(diagnose(file_of(m)).orientable, true);
  EXPECT_EQ(rejection(file_of(m)), "");  // orientation is fixed, not rejected
  const OrientationReport r = orient_outward(m);
  EXPECT_EQ(r.flipped_quads, 1u);
  EXPECT_EQ(m.surface.quads, original);
}

TEST(Diagnose, CavityIsOrientedTowardsTheHole) {
  // A 3x3x3 box with a cube-shaped cavity in the middle: the cavity's quads face inward.
  const SurfaceMesh outer = test::box_surface(3, 3, 3);
  const SurfaceMesh cavity =
      transformed(test::reversed_surface(test::box_surface(1, 1, 1)), 1, 1, 1, 1);
  SurfaceMesh hollow = merged({outer, cavity});
  const auto expected = hollow.surface.quads;
  OrientationReport r = orient_outward(hollow);
  EXPECT_EQ(r.flipped_quads, 0u);
  EXPECT_EQ(r.nesting_depth, (std::vector<int>{0, 1}));
  EXPECT_EQ(hollow.surface.quads, expected);
  // Both reversed: everything is flipped back.
  SurfaceMesh inside_out = test::reversed_surface(merged({outer, cavity}));
  r = orient_outward(inside_out);
  EXPECT_EQ(r.flipped_quads, 60u);
  EXPECT_EQ(inside_out.surface.quads, expected);
  // Two separate boxes are both outward.
  SurfaceMesh two =
      merged({test::box_surface(1, 1, 1),
              transformed(test::reversed_surface(test::box_surface(1, 1, 1)), 1, 3, 0, 0)});
  r = orient_outward(two);
  EXPECT_EQ(r.flipped_quads, 6u);
  EXPECT_EQ(r.nesting_depth, (std::vector<int>{0, 0}));
}

TEST(Diagnose, OrientOutwardRejectsANonOrientableSurface) {
  SurfaceMesh k = klein_bottle(5, 4);
  try {
    orient_outward(k);
    FAIL() << "expected TopologyError";
  } catch (const TopologyError& e) {
    EXPECT_THAT(e.what(), HasSubstr("not orientable"));
    EXPECT_THAT(e.what(), HasSubstr("component 0"));
    EXPECT_THAT(e.what(),
                testing::ContainsRegex("edge n[0-9]+-n[0-9]+ between q[0-9]+ and q[0-9]+"));
  }
}

TEST(Diagnose, TorusAndTwoComponentsAreWeavable) {
  // A box with a square hole through it: genus 1 is for the weaver to decide, not an error.
  SurfaceMesh frame;
  {
    std::vector<SurfaceMesh> parts;
    const HexMesh ring = [] {
      HexMesh h = test::box_hexes(3, 3, 1);
      h.complex.hexes.erase(h.complex.hexes.begin() + 4);  // the middle hex
      return h;
    }();
    frame = surface_of(file_of(ring));
  }
  MeshFile f = file_of(frame);
  const SurfaceDiagnosis d = diagnose(f);
  EXPECT_EQ(d.genus, 1);
  EXPECT_EQ(d.euler_characteristic, 0);
  EXPECT_NO_THROW(require_weavable(d));

  const SurfaceDiagnosis two = diagnose(file_of(
      merged({test::box_surface(1, 1, 1), transformed(test::box_surface(1, 1, 1), 1, 5, 0, 0)})));
  EXPECT_EQ(two.components, 2u);
  EXPECT_EQ(two.genus, 0);
  EXPECT_EQ(two.genus_per_component, (std::vector<std::optional<int>>{0, 0}));
  EXPECT_NO_THROW(require_weavable(two));
}

TEST(RequireWeavable, OpenSurfaceNamesItsEdgesAndQuads) {
  SurfaceMesh m = test::box_surface(1, 1, 1);
  const stc::Quad removed = m.surface.quads.back();
  m.surface.quads.pop_back();
  MeshFile f = file_of(m, "open.obj");
  f.quad_lines = {11, 12, 13, 14, 15};
  const SurfaceDiagnosis d = diagnose(f);
  EXPECT_FALSE(d.closed);
  EXPECT_EQ(d.open_edges, 4u);
  EXPECT_EQ(d.genus, std::nullopt);
  const std::string msg = rejection(f);
  EXPECT_THAT(msg, HasSubstr("open.obj: the surface is open: 4 edge(s)"));
  EXPECT_THAT(msg, HasSubstr(std::min(removed[0], removed[1]).str()));
  EXPECT_THAT(msg, testing::ContainsRegex("n[0-9]+-n[0-9]+ of q[0-9] \\(line 1[1-5]\\)"));
  EXPECT_THAT(msg, HasSubstr("close the surface"));
}

TEST(RequireWeavable, NonManifoldEdgeIsNamed) {
  const SurfaceMesh cube = test::box_surface(1, 1, 1);
  const MeshFile f = file_of(merged({cube, transformed(cube, 1, 1, 1, 0)}));
  const SurfaceDiagnosis d = diagnose(f);
  EXPECT_EQ(d.nonmanifold_edges, 1u);
  EXPECT_FALSE(d.manifold);
  EXPECT_EQ(d.loops, std::nullopt);
  const NodePair e = d.sites.nonmanifold_edges.at(0);
  // The shared edge is x = y = 1: both ends there.
  EXPECT_EQ(f.points(e[0].value(), 0), 1.0);
  EXPECT_EQ(f.points(e[1].value(), 1), 1.0);
  const std::string msg = rejection(f);
  EXPECT_THAT(msg, HasSubstr("shared by more than two quads: " + e[0].str() + "-" + e[1].str() +
                             " (4 quads)"));
}

TEST(RequireWeavable, NonManifoldNodeIsNamed) {
  const SurfaceMesh cube = test::box_surface(1, 1, 1);
  const MeshFile f = file_of(merged({cube, transformed(cube, 1, 1, 1, 1)}));
  const SurfaceDiagnosis d = diagnose(f);
  EXPECT_TRUE(d.closed);
  EXPECT_FALSE(d.manifold);
  ASSERT_EQ(d.sites.nonmanifold_nodes.size(), 1u);
  const NodeId v = d.sites.nonmanifold_nodes[0];
  EXPECT_EQ(f.points.row(v.value()), Eigen::RowVector3d(1, 1, 1));
  EXPECT_THAT(
      rejection(f),
      HasSubstr("non-manifold at 1 node(s) where separate fans of quads meet: " + v.str() + ";"));
}

TEST(RequireWeavable, NonOrientableSurfaceNamesAnEdge) {
  const MeshFile f = file_of(klein_bottle(5, 4), "klein.obj");
  const SurfaceDiagnosis d = diagnose(f);
  EXPECT_TRUE(d.closed);
  EXPECT_TRUE(d.manifold);
  EXPECT_EQ(d.orientable, false);
  EXPECT_FALSE(d.consistently_oriented);
  EXPECT_EQ(d.genus, std::nullopt);
  const std::string msg = rejection(f);
  EXPECT_THAT(msg, HasSubstr("klein.obj: the surface is not orientable"));
  EXPECT_THAT(msg,
              testing::ContainsRegex("across edge n[0-9]+-n[0-9]+ between q[0-9]+ and q[0-9]+"));
}

TEST(RequireWeavable, OddNumberOfQuadsSaysNoHexMeshHasThatBoundary) {
  const MeshFile f = file_of(pillow(3));
  const SurfaceDiagnosis d = diagnose(f);
  EXPECT_TRUE(d.closed);
  EXPECT_TRUE(d.manifold);
  EXPECT_EQ(d.genus, 0);
  EXPECT_FALSE(d.has_even_quads());
  EXPECT_EQ(to_json(d)["quad_parity"], "odd");
  EXPECT_THAT(
      rejection(f),
      HasSubstr("the surface has 3 quads, an odd number: no hex mesh can have that boundary"));
}

TEST(RequireWeavable, SelfIntersectingLoopNamesTheLoopAndItsQuads) {
  const MeshFile f = file_of(refined(pillow(3)));
  const SurfaceDiagnosis d = diagnose(f);
  EXPECT_EQ(d.quads, 12u);
  EXPECT_EQ(d.loops, 2u);
  EXPECT_EQ(d.self_intersecting_loops, 2u);
  EXPECT_EQ(d.self_crossing_quads, 6u);
  ASSERT_EQ(d.sites.self_intersecting_loops.size(), 2u);
  const SelfIntersection& s = d.sites.self_intersecting_loops[0];
  std::string quads;
  for (QuadId q : s.quads) quads += (quads.empty() ? "" : ", ") + q.str();
  EXPECT_THAT(rejection(f), HasSubstr("loop l0 (12 quads) crosses itself in " + quads +
                                      "; 2 loops are self-intersecting: l0, l1"));
}

TEST(RequireWeavable, NonFiniteCoordinateNamesTheNode) {
  SurfaceMesh m = test::box_surface(1, 1, 1);
  m.points(5, 1) = std::numeric_limits<double>::quiet_NaN();
  const SurfaceDiagnosis d = diagnose(file_of(m));
  EXPECT_EQ(d.nonfinite_nodes, 1u);
  EXPECT_THAT(rejection(file_of(m)), HasSubstr("non-finite coordinates (NaN or infinite): n5;"));
}

TEST(RequireWeavable, DegenerateQuadIsNamed) {
  SurfaceMesh m = test::box_surface(1, 1, 1);
  m.surface.quads[2][3] = m.surface.quads[2][1];
  const SurfaceDiagnosis d = diagnose(file_of(m));
  EXPECT_EQ(d.degenerate_quads, 1u);
  EXPECT_THAT(rejection(file_of(m)), HasSubstr("1 degenerate quad(s) repeat a node: q2;"));
}

TEST(RequireWeavable, QuadsOnTheSameFourNodesAreNamed) {
  // Found by fuzzing: two quads on four nodes glued along all their edges (a closed surface
  // that encloses nothing) sent the weave into minutes of recovery; so did a quad given twice.
  SurfaceMesh two;
  two.points.resize(4, 3);
  two.points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  two.surface.num_nodes = 4;
  two.surface.quads = {{NodeId(0), NodeId(1), NodeId(3), NodeId(2)},
                       {NodeId(0), NodeId(2), NodeId(3), NodeId(1)}};
  const SurfaceDiagnosis d = diagnose(file_of(two));
  EXPECT_EQ(d.duplicate_quads, 1u);
  EXPECT_THAT(rejection(file_of(two)),
              HasSubstr("1 quad(s) have the same four nodes as another quad: q1 repeats q0;"));
  SurfaceMesh cube = test::box_surface(1, 1, 1);
  cube.surface.quads.push_back(cube.surface.quads[3]);
  EXPECT_EQ(diagnose(file_of(cube)).duplicate_quads, 1u);
  EXPECT_THAT(rejection(file_of(cube)), HasSubstr("q6 repeats q3"));
  EXPECT_EQ(diagnose(file_of(test::box_surface(2, 3, 1))).duplicate_quads, 0u);
}

TEST(Diagnose, ASurfaceThatPassesThroughItselfIsNamedInAWarning) {
  // The 2x2x2 box with the centre of its x = 0 face dragged to x = 10: the quads around that
  // node now pass through the x = 2 face (quads they share no node with). The warning names a
  // pair; it is not a refusal (generated test spheres and a CAD face split from triangles
  // have such folds, docs/topology.md). The box as it was has no crossing.
  SurfaceMesh box = test::box_surface(2, 2, 2);
  EXPECT_EQ(diagnose(file_of(box)).crossing_quad_pairs, std::optional<std::size_t>(0));
  int dragged = 0;
  for (Eigen::Index v = 0; v < box.points.rows(); ++v) {
    if (box.points.row(v) == Eigen::RowVector3d(0, 1, 1)) {
      box.points(v, 0) = 10.0;
      ++dragged;
    }
  }
  ASSERT_EQ(dragged, 1);
  const SurfaceDiagnosis d = diagnose(file_of(box));
  ASSERT_TRUE(d.crossing_quad_pairs.has_value());
  EXPECT_GT(*d.crossing_quad_pairs, 0u);
  ASSERT_EQ(d.sites.crossing_quads.size(), *d.crossing_quad_pairs);
  for (const auto& [a, b] : d.sites.crossing_quads) {
    EXPECT_LT(a, b);
    for (const NodeId u : box.surface.quads[a.index()])
      for (const NodeId v : box.surface.quads[b.index()]) EXPECT_NE(u, v);
  }
  EXPECT_THAT(crossing_warning(d), HasSubstr("test.obj: the surface passes through itself: "));
  EXPECT_THAT(crossing_warning(d), HasSubstr(" crosses q"));
  EXPECT_EQ(rejection(file_of(box)), "");
  EXPECT_EQ(crossing_warning(diagnose(file_of(test::box_surface(2, 2, 2)))), "");
  EXPECT_EQ(to_json(d).at("crossing_quad_pairs"), *d.crossing_quad_pairs);
  // Not measured where a coordinate is not finite (that is refused first, by name).
  box.points(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(diagnose(file_of(box)).crossing_quad_pairs.has_value());
}

TEST(Diagnose, SolidsThatTouchOrNestDoNotCrossAndOverlappingOnesDo) {
  const SurfaceMesh box = test::box_surface(2, 2, 2);
  const auto pairs = [](const SurfaceMesh& m) {
    return diagnose(file_of(m)).crossing_quad_pairs.value_or(99999);
  };
  // Two boxes side by side, their faces at x = 2 coincident (nodes apart): a contact.
  EXPECT_EQ(pairs(test::merged_surfaces({box, test::translated(box, {2, 0, 0})})), 0u);
  // A box in a box, the inner one reversed (a cavity), and an edge-to-edge contact.
  EXPECT_EQ(
      pairs(test::merged_surfaces({transformed(box, 2.0, 0, 0, 0),
                                   test::reversed_surface(transformed(box, 0.5, 1.5, 1.5, 1.5))})),
      0u);
  EXPECT_EQ(pairs(test::merged_surfaces({box, test::translated(box, {2, 2, 0})})), 0u);
  // Curved and warped quads: a torus, and a 4x4x4 box whose nodes are moved by up to 0.3 of a
  // cell (a fixed pattern) so that no quad is planar.
  EXPECT_EQ(pairs(test::torus_surface(8, 12)), 0u);
  SurfaceMesh warped = test::box_surface(4, 4, 4);
  for (Eigen::Index v = 0; v < warped.points.rows(); ++v)
    for (Eigen::Index k = 0; k < 3; ++k)
      warped.points(v, k) +=
          0.3 * std::sin(1.7 * static_cast<double>(v) + 2.3 * static_cast<double>(k));
  EXPECT_EQ(pairs(warped), 0u);
  // Overlapping: the faces cross where they pass through each other, at a generic offset and
  // at half a cell, where the crossings run through quad diagonals and along shared edges.
  EXPECT_GT(pairs(test::merged_surfaces({box, test::translated(box, {1.3, 0.4, 0.45})})), 0u);
  EXPECT_GT(pairs(test::merged_surfaces({box, test::translated(box, {1.5, 0.5, 0.5})})), 0u);
  // Scale does not matter: the same overlap at 1e-6 and 1e6.
  for (const double scale : {1e-6, 1e6}) {
    const SurfaceMesh small = transformed(box, scale, 0, 0, 0);
    EXPECT_EQ(pairs(test::merged_surfaces({small, transformed(box, scale, 2 * scale, 0, 0)})), 0u)
        << scale;
    EXPECT_GT(pairs(test::merged_surfaces(
                  {small, transformed(box, scale, 1.5 * scale, 0.5 * scale, 0.5 * scale)})),
              0u)
        << scale;
  }
}

TEST(RequireWeavable, TrianglesAndOtherCellsAreRejected) {
  MeshFile f = file_of(test::box_surface(1, 1, 1));
  f.triangles = 4;
  EXPECT_THAT(rejection(f), HasSubstr("the file holds 4 triangles besides quads"));
  f.triangles = 0;
  f.other_cells = 2;
  EXPECT_THAT(rejection(f), HasSubstr("2 other cells"));
}

TEST(RequireWeavable, ManyElementsAreCountedNotAllListed) {
  SurfaceMesh m = test::box_surface(3, 3, 3);
  m.surface.quads.erase(m.surface.quads.begin(), m.surface.quads.begin() + 9);
  const std::string msg = rejection(file_of(m));
  EXPECT_THAT(msg, HasSubstr("in all)"));
  EXPECT_EQ(msg.find('\n'), std::string::npos);
}

TEST(Diagnose, CoincidentNodesAreCounted) {
  // Two cubes whose touching faces are not merged: the four nodes of the face coincide.
  SurfaceMesh a = test::box_surface(1, 1, 1);
  SurfaceMesh b = transformed(test::box_surface(1, 1, 1), 1, 1, 0, 0);
  SurfaceMesh both;
  both.points.resize(16, 3);
  both.points << a.points, b.points;
  both.surface.quads = a.surface.quads;
  for (stc::Quad q : b.surface.quads) {
    for (NodeId& v : q) v = NodeId(v.value() + 8);
    both.surface.quads.push_back(q);
  }
  both.surface.num_nodes = 16;
  EXPECT_EQ(diagnose(file_of(both)).coincident_nodes, 4u);
}

TEST(Diagnose, NodeOutOfRangeIsInvalidInput) {
  MeshFile f = file_of(test::box_surface(1, 1, 1), "bad.obj");
  f.quads[3][2] = NodeId(99);
  try {
    (void)diagnose(f);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.obj: quad q3 refers to node n99"));
  }
}

}  // namespace
}  // namespace stcweave::primal
