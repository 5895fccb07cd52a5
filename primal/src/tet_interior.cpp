#include "stcweave/primal/tet_interior.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "stcweave/stc/errors.hpp"

#if STCWEAVE_HAVE_GMSH
#include "gmsh_session.hpp"
#include "shells.hpp"
#include "tet_flips.hpp"
#endif

namespace stcweave::primal {

std::string_view interior_mode_name(InteriorMode mode) {
  switch (mode) {
    case InteriorMode::Auto:
      return "auto";
    case InteriorMode::Weave:
      return "weave";
    case InteriorMode::Tets:
      return "tets";
  }
  return "auto";
}

InteriorMode interior_mode_from_name(std::string_view name) {
  for (const InteriorMode m : {InteriorMode::Auto, InteriorMode::Weave, InteriorMode::Tets})
    if (name == interior_mode_name(m)) return m;
  throw InvalidInput("unknown interior '" + std::string(name) + "': use auto, weave or tets");
}

#if !STCWEAVE_HAVE_GMSH

bool has_tet_interior_support() {
  return false;
}

weave::WeaveResult tet_interior(const SurfaceMesh& /*surface*/, const stc::TriangleSplit& /*split*/,
                                const TetInteriorOptions& /*options*/, Points& /*positions*/,
                                TetInteriorReport* /*report*/) {
  throw Unsupported(
      "the tetrahedral interior (--interior tets) needs Gmsh, and this stcweave was built "
      "without it (CMake option STCWEAVE_WITH_GMSH is OFF or libgmsh-dev was not found); "
      "install libgmsh-dev and reconfigure, or use --interior weave");
}

#else

bool has_tet_interior_support() {
  return true;
}

namespace {

/// The Gmsh model of one call, cleared on the way out whatever happens.
class GmshModel {
 public:
  GmshModel() : lock_(gmsh_detail::GmshSession::instance().mutex) {
    gmsh::clear();
    gmsh::model::mesh::setSizeCallback({});
  }
  GmshModel(const GmshModel&) = delete;
  GmshModel& operator=(const GmshModel&) = delete;
  GmshModel(GmshModel&&) = delete;
  GmshModel& operator=(GmshModel&&) = delete;
  ~GmshModel() {
    try {
      // Gmsh 4.8 keeps a size callback across clear(): ours must not outlive this call.
      gmsh::model::mesh::setSizeCallback({});
      gmsh::clear();
    } catch (...) {  // NOLINT(bugprone-empty-catch): already failing or done
    }
  }

 private:
  std::lock_guard<std::mutex> lock_;
};

/// Every option the 3D mesh reads, set explicitly: the session is shared with the CAD front
/// end, which sets sizes and algorithms of its own.
void set_tet_options() {
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 2);
  gmsh::option::setNumber("General.NumThreads", 1);  // determinism
  gmsh::option::setNumber("Mesh.MaxNumThreads3D", 1);
  gmsh::option::setNumber("Mesh.RandomFactor", 1e-9);
  gmsh::option::setNumber("Mesh.RandomFactor3D", 1e-12);
  gmsh::option::setNumber("Mesh.Algorithm3D", 1);  // Delaunay
  gmsh::option::setNumber("Mesh.Optimize", 1);
  gmsh::option::setNumber("Mesh.OptimizeNetgen", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 1);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
  gmsh::option::setNumber("Mesh.MeshSizeFactor", 1);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
  gmsh::option::setNumber("Mesh.MeshSizeMax", 1e22);
  gmsh::option::setNumber("Mesh.RecombineAll", 0);
  gmsh::option::setNumber("Mesh.Recombine3DAll", 0);
  gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 0);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
}

/// The nearest boundary vertex by a k-d tree (median splits, deterministic ties by index):
/// the size Gmsh is to aim at anywhere inside is that vertex's edge length, grown with the
/// distance to it.
class BoundarySizes {
 public:
  BoundarySizes(std::vector<Eigen::Vector3d> points, std::vector<double> sizes)
      : points_(std::move(points)), sizes_(std::move(sizes)), order_(points_.size()) {
    for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = i;
    build(0, order_.size(), 0);
  }

  /// min(growth h, h + d / 2) for the nearest vertex (size h) at distance d.
  [[nodiscard]] double size_at(const Eigen::Vector3d& x, double growth) const {
    double best = std::numeric_limits<double>::infinity();
    std::size_t nearest = 0;
    search(0, order_.size(), 0, x, best, nearest);
    const double h = sizes_[nearest];
    return std::min(growth * h, h + 0.5 * std::sqrt(best));
  }

 private:
  // The median of [lo, hi) along axis at `mid`, smaller coordinates before it.
  void build(std::size_t lo, std::size_t hi, int axis) {
    if (hi - lo <= 1) return;
    const std::size_t mid = lo + (hi - lo) / 2;
    const auto before = [&](std::size_t a, std::size_t b) {
      const double ca = points_[a][axis];
      const double cb = points_[b][axis];
      return ca != cb ? ca < cb : a < b;
    };
    std::nth_element(order_.begin() + static_cast<std::ptrdiff_t>(lo),
                     order_.begin() + static_cast<std::ptrdiff_t>(mid),
                     order_.begin() + static_cast<std::ptrdiff_t>(hi), before);
    build(lo, mid, (axis + 1) % 3);
    build(mid + 1, hi, (axis + 1) % 3);
  }

  void search(std::size_t lo, std::size_t hi, int axis, const Eigen::Vector3d& x, double& best,
              std::size_t& nearest) const {
    if (lo >= hi) return;
    const std::size_t mid = lo + (hi - lo) / 2;
    const std::size_t p = order_[mid];
    const double d = (points_[p] - x).squaredNorm();
    if (d < best || (d == best && p < nearest)) {
      best = d;
      nearest = p;
    }
    const double delta = x[axis] - points_[p][axis];
    const int next = (axis + 1) % 3;
    if (delta < 0) {
      search(lo, mid, next, x, best, nearest);
      if (delta * delta <= best) search(mid + 1, hi, next, x, best, nearest);
    } else {
      search(mid + 1, hi, next, x, best, nearest);
      if (delta * delta <= best) search(lo, mid, next, x, best, nearest);
    }
  }

  std::vector<Eigen::Vector3d> points_;
  std::vector<double> sizes_;
  std::vector<std::size_t> order_;  // the tree: each range's median at its middle
};

/// The shells of a triangle split (components joined by shared vertices), each with the
/// Gmsh volume it bounds: a shell of positive signed volume bounds a solid, one of negative
/// volume (oriented into its cavity) is a cavity of the smallest solid around it.
struct Shells {
  std::vector<std::size_t> shell_of_node;  ///< per surface node (SIZE_MAX: none)
  std::vector<std::size_t> shell_of_triangle;
  std::size_t count = 0;
  /// Per solid shell, the cavity shells inside it.
  std::vector<std::pair<std::size_t, std::vector<std::size_t> > > solids;
};

/// How many times the closed triangle shell winds round p: the sum of its triangles' signed
/// solid angles seen from p (Van Oosterom and Strackee), over 4 pi.
double winding(const Points& points, const stc::TriangleSplit& split,
               const std::vector<std::size_t>& triangles, const Eigen::Vector3d& p) {
  double total = 0.0;
  for (const std::size_t t : triangles) {
    const Eigen::Vector3d a = points.row(split.triangles[t][0].value()).transpose() - p;
    const Eigen::Vector3d b = points.row(split.triangles[t][1].value()).transpose() - p;
    const Eigen::Vector3d c = points.row(split.triangles[t][2].value()).transpose() - p;
    const double la = a.norm();
    const double lb = b.norm();
    const double lc = c.norm();
    const double det = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(det, den);
  }
  return total / (4.0 * M_PI);
}

Shells find_shells(const SurfaceMesh& surface, const stc::TriangleSplit& split) {
  const Points& points = surface.points;
  Shells shells;
  const std::vector<int> label = shell_of_nodes(surface.surface, &shells.count);
  shells.shell_of_node.assign(label.size(), SIZE_MAX);
  for (std::size_t v = 0; v < label.size(); ++v)
    if (label[v] >= 0) shells.shell_of_node[v] = static_cast<std::size_t>(label[v]);
  std::vector<std::vector<std::size_t> > triangles(shells.count);
  for (std::size_t t = 0; t < split.triangles.size(); ++t) {
    const std::size_t k = shells.shell_of_node[split.triangles[t][0].index()];
    shells.shell_of_triangle.push_back(k);
    triangles[k].push_back(t);
  }
  std::vector<double> volume(shells.count, 0.0);
  for (std::size_t t = 0; t < split.triangles.size(); ++t) {
    const Eigen::Vector3d a = points.row(split.triangles[t][0].value()).transpose();
    const Eigen::Vector3d b = points.row(split.triangles[t][1].value()).transpose();
    const Eigen::Vector3d c = points.row(split.triangles[t][2].value()).transpose();
    volume[shells.shell_of_triangle[t]] += a.dot(b.cross(c)) / 6.0;
  }
  if (shells.count == 1) {
    shells.solids.push_back({0, {}});
    return shells;
  }
  // Which shells each shell lies inside (one vertex of it tested against every other).
  const auto inside = [&](std::size_t i, std::size_t j) {
    const Eigen::Vector3d p = points.row(split.triangles[triangles[i][0]][0].value()).transpose();
    return std::abs(winding(points, split, triangles[j], p)) > 0.5;
  };
  std::vector<std::size_t> solid_of(shells.count, SIZE_MAX);
  for (std::size_t i = 0; i < shells.count; ++i) {
    if (volume[i] <= 0.0) continue;
    solid_of[i] = shells.solids.size();
    shells.solids.push_back({i, {}});
  }
  for (std::size_t k = 0; k < shells.count; ++k) {
    if (volume[k] > 0.0) continue;
    std::size_t best = SIZE_MAX;
    for (std::size_t i = 0; i < shells.count; ++i)
      if (volume[i] > 0.0 && inside(k, i) && (best == SIZE_MAX || volume[i] < volume[best]))
        best = i;
    if (best == SIZE_MAX) {
      throw InvalidInput("tet interior: shell " + std::to_string(k) +
                         " faces inward (a cavity) but lies inside no solid; orient the "
                         "surface outward");
    }
    shells.solids[solid_of[best]].second.push_back(k);
  }
  return shells;
}

}  // namespace

weave::WeaveResult tet_interior(const SurfaceMesh& surface, const stc::TriangleSplit& split,
                                const TetInteriorOptions& options, Points& positions,
                                TetInteriorReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t num_surface = surface.surface.num_nodes;
  if (static_cast<std::size_t>(surface.points.rows()) != num_surface)
    throw InvalidInput("tet interior: the surface has " + std::to_string(num_surface) +
                       " nodes but " + std::to_string(surface.points.rows()) + " points");

  // Gmsh tags: the split's vertices shell by shell, each shell's in increasing order, from 1
  // (Gmsh renumbers the nodes of each discrete surface to a contiguous range when it meshes;
  // so numbered, that renumbering changes nothing).
  const Shells shells = find_shells(surface, split);
  const std::vector<std::size_t>& shell_of_node = shells.shell_of_node;
  std::vector<std::size_t> vertex_of_tag(split.vertices.size());  // tag - 1 -> split vertex
  for (std::size_t k = 0; k < split.vertices.size(); ++k) vertex_of_tag[k] = k;
  std::stable_sort(vertex_of_tag.begin(), vertex_of_tag.end(), [&](std::size_t a, std::size_t b) {
    return shell_of_node[split.vertices[a].index()] < shell_of_node[split.vertices[b].index()];
  });
  std::vector<std::size_t> node_tags(split.vertices.size());
  std::vector<double> coords(3 * split.vertices.size());
  std::vector<std::size_t> tag_of(num_surface, 0);  // surface node -> tag
  for (std::size_t i = 0; i < split.vertices.size(); ++i) {
    const NodeId v = split.vertices[vertex_of_tag[i]];
    node_tags[i] = i + 1;
    tag_of[v.index()] = i + 1;
    for (int c = 0; c < 3; ++c)
      coords[3 * i + static_cast<std::size_t>(c)] = surface.points(v.value(), c);
  }
  std::vector<std::size_t> triangle_tags;
  triangle_tags.reserve(3 * split.triangles.size());
  for (const auto& tri : split.triangles)
    for (const NodeId v : tri) triangle_tags.push_back(tag_of[v.index()]);

  // With growth, Gmsh's size anywhere is the nearest vertex's mean edge length, grown.
  std::optional<BoundarySizes> sizes;
  if (options.growth > 1.0) {
    std::vector<double> length(split.vertices.size(), 0.0);
    std::vector<int> count(split.vertices.size(), 0);
    for (std::size_t t = 0; t < split.triangles.size(); ++t) {
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t a = triangle_tags[3 * t + k] - 1;
        const std::size_t b = triangle_tags[3 * t + (k + 1) % 3] - 1;
        const double l = (surface.points.row(split.vertices[vertex_of_tag[a]].value()) -
                          surface.points.row(split.vertices[vertex_of_tag[b]].value()))
                             .norm();
        length[a] += l;
        length[b] += l;
        ++count[a];
        ++count[b];
      }
    }
    std::vector<Eigen::Vector3d> at(split.vertices.size());
    for (std::size_t k = 0; k < split.vertices.size(); ++k) {
      length[k] /= std::max(count[k], 1);
      at[k] = surface.points.row(split.vertices[vertex_of_tag[k]].value()).transpose();
    }
    sizes.emplace(std::move(at), std::move(length));
  }

  std::vector<std::size_t> interior_tags;
  std::vector<double> interior_coords;
  std::vector<std::size_t> tet_nodes;
  std::vector<std::size_t> surface_tags;
  std::vector<double> surface_coords;
  try {
    const GmshModel model;
    set_tet_options();
    gmsh::model::add("stcweave_tet_interior");
    // One discrete surface per shell, with its own nodes; one volume per solid shell, its
    // cavities as holes.
    std::vector<int> entity(shells.count);
    std::vector<std::vector<std::size_t> > shell_tags(shells.count);
    std::vector<std::vector<double> > shell_coords(shells.count);
    std::vector<std::vector<std::size_t> > shell_triangles(shells.count);
    for (std::size_t t = 0; t < split.triangles.size(); ++t) {
      const std::size_t k = shells.shell_of_triangle[t];
      for (std::size_t i = 0; i < 3; ++i) shell_triangles[k].push_back(triangle_tags[3 * t + i]);
    }
    // Each shell's nodes in increasing tag order: Gmsh renumbers them in the order added.
    for (std::size_t i = 0; i < node_tags.size(); ++i) {
      const std::size_t k = shell_of_node[split.vertices[vertex_of_tag[i]].index()];
      shell_tags[k].push_back(node_tags[i]);
      for (std::size_t c = 0; c < 3; ++c) shell_coords[k].push_back(coords[3 * i + c]);
    }
    for (std::size_t k = 0; k < shells.count; ++k) {
      entity[k] = gmsh::model::addDiscreteEntity(2);
      gmsh::model::mesh::addNodes(2, entity[k], shell_tags[k], shell_coords[k]);
      gmsh::model::mesh::addElementsByType(entity[k], 2, {}, shell_triangles[k]);
    }
    std::vector<int> volumes;
    for (const auto& [solid, cavities] : shells.solids) {
      std::vector<int> loops{gmsh::model::geo::addSurfaceLoop({entity[solid]})};
      for (const std::size_t k : cavities)
        loops.push_back(gmsh::model::geo::addSurfaceLoop({entity[k]}));
      volumes.push_back(gmsh::model::geo::addVolume(loops));
    }
    gmsh::model::geo::synchronize();
    if (sizes) {
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
      gmsh::model::mesh::setSizeCallback(
          [&](int /*dim*/, int /*tag*/, double x, double y, double z) {
            return sizes->size_at(Eigen::Vector3d(x, y, z), options.growth);
          });
    }
    gmsh::model::mesh::generate(3);
    std::vector<double> parametric;
    const auto append = [](auto& to, const auto& from) {
      to.insert(to.end(), from.begin(), from.end());
    };
    const auto append_nodes = [&](int dim, int tag, std::vector<std::size_t>& tags_to,
                                  std::vector<double>& coords_to) {
      std::vector<std::size_t> tags;
      std::vector<double> xyz;
      gmsh::model::mesh::getNodes(tags, xyz, parametric, dim, tag, false, false);
      append(tags_to, tags);
      append(coords_to, xyz);
    };
    for (const int v : volumes) {
      append_nodes(3, v, interior_tags, interior_coords);
      std::vector<std::size_t> tet_tags;
      std::vector<std::size_t> nodes;
      gmsh::model::mesh::getElementsByType(4, tet_tags, nodes, v);
      append(tet_nodes, nodes);
    }
    for (const int e : entity) append_nodes(2, e, surface_tags, surface_coords);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (...) {
    throw InvalidInput("Gmsh could not tetrahedralise the solid bounded by the surface's " +
                       std::to_string(split.triangles.size()) + " triangles: " +
                       gmsh_detail::gmsh_reason() + " (use --interior weave to weave it instead)");
  }
  // The boundary nodes must come back as they went in: tags 1 .. V at the same places.
  bool kept = surface_tags.size() == node_tags.size();
  for (std::size_t k = 0; kept && k < surface_tags.size(); ++k) {
    const std::size_t tag = surface_tags[k];
    kept = tag >= 1 && tag <= node_tags.size();
    for (int c = 0; kept && c < 3; ++c)
      kept = surface_coords[3 * k + static_cast<std::size_t>(c)] ==
             coords[3 * (tag - 1) + static_cast<std::size_t>(c)];
  }
  if (!kept) {
    throw InvalidInput("Gmsh changed the boundary nodes while tetrahedralising the solid (" +
                       std::to_string(surface_tags.size()) + " nodes on the surface after, " +
                       std::to_string(node_tags.size()) +
                       " before): the surface's triangles could not be kept; use --interior "
                       "weave");
  }
  if (tet_nodes.empty()) {
    throw InvalidInput("Gmsh made no tetrahedron in the solid bounded by the surface's " +
                       std::to_string(split.triangles.size()) +
                       " triangles (is the surface self-intersecting?); use --interior weave");
  }

  // Our numbering: the surface's nodes, then Gmsh's interior vertices in Gmsh's order.
  const std::size_t num_vertices = num_surface + interior_tags.size();
  positions.resize(static_cast<Eigen::Index>(num_vertices), 3);
  positions.topRows(static_cast<Eigen::Index>(num_surface)) = surface.points;
  std::unordered_map<std::size_t, NodeId> node_of;
  for (std::size_t i = 0; i < split.vertices.size(); ++i)
    node_of[i + 1] = split.vertices[vertex_of_tag[i]];
  for (std::size_t k = 0; k < interior_tags.size(); ++k) {
    const NodeId id(num_surface + k);
    if (!node_of.emplace(interior_tags[k], id).second)
      throw InvalidInput("tet interior: Gmsh gave node tag " + std::to_string(interior_tags[k]) +
                         " twice");
    for (int c = 0; c < 3; ++c)
      positions(id.value(), c) = interior_coords[3 * k + static_cast<std::size_t>(c)];
  }
  std::vector<stc::Tet> tets(tet_nodes.size() / 4);
  for (std::size_t t = 0; t < tets.size(); ++t) {
    for (std::size_t i = 0; i < 4; ++i) {
      const auto it = node_of.find(tet_nodes[4 * t + i]);
      if (it == node_of.end()) {
        throw InvalidInput(
            "Gmsh added a node on the boundary while tetrahedralising the solid (tag " +
            std::to_string(tet_nodes[4 * t + i]) +
            "): the surface's triangles could not be kept; use --interior weave");
      }
      tets[t][i] = it->second;
    }
    if (tet_volume6(positions, tets[t]) < 0.0) std::swap(tets[t][2], tets[t][3]);
  }

  TetFlips flips;
  if (options.flips) flips = flip_tets(positions, tets, options.flip_floor);
  stc::TetSplit cut = stc::split_tets(split, static_cast<std::size_t>(positions.rows()), tets);
  positions.conservativeResize(static_cast<Eigen::Index>(cut.complex.num_nodes), 3);
  for (std::size_t i = 0; i < cut.added_parents.size(); ++i) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (const NodeId p : cut.added_parents[i]) sum += positions.row(p.value());
    positions.row(static_cast<Eigen::Index>(cut.first_added + i)) =
        sum / static_cast<double>(cut.added_parents[i].size());
  }

  weave::WeaveResult result;
  result.num_input_nodes = num_surface;
  result.hex_shrink.assign(cut.complex.hexes.size(), -1);
  result.hex_rule.assign(cut.complex.hexes.size(), "tet-split");
  result.complex = std::move(cut.complex);
  if (report != nullptr) {
    report->triangles = split.triangles.size();
    report->tets = tets.size();
    report->flips = flips.flips;
    report->interior_vertices = interior_tags.size();
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return result;
}

#endif

}  // namespace stcweave::primal
