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

double signed_volume(const Points& p, const stc::Tet& t) {
  const Eigen::Vector3d a = p.row(t[0].index());
  const Eigen::Vector3d e1 = p.row(t[1].index()).transpose() - a;
  const Eigen::Vector3d e2 = p.row(t[2].index()).transpose() - a;
  const Eigen::Vector3d e3 = p.row(t[3].index()).transpose() - a;
  return e1.dot(e2.cross(e3));
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

}  // namespace

weave::WeaveResult tet_interior(const SurfaceMesh& surface, const stc::TriangleSplit& split,
                                const TetInteriorOptions& options, Points& positions,
                                TetInteriorReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t num_surface = surface.surface.num_nodes;
  if (static_cast<std::size_t>(surface.points.rows()) != num_surface)
    throw InvalidInput("tet interior: the surface has " + std::to_string(num_surface) +
                       " nodes but " + std::to_string(surface.points.rows()) + " points");

  // Gmsh tags: vertex k of the split is tag k + 1.
  std::vector<std::size_t> node_tags(split.vertices.size());
  std::vector<double> coords(3 * split.vertices.size());
  std::vector<std::size_t> tag_of(num_surface, 0);  // surface node -> tag
  for (std::size_t k = 0; k < split.vertices.size(); ++k) {
    node_tags[k] = k + 1;
    tag_of[split.vertices[k].index()] = k + 1;
    for (int c = 0; c < 3; ++c)
      coords[3 * k + static_cast<std::size_t>(c)] = surface.points(split.vertices[k].value(), c);
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
        const double l = (surface.points.row(split.vertices[a].value()) -
                          surface.points.row(split.vertices[b].value()))
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
      at[k] = surface.points.row(split.vertices[k].value()).transpose();
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
    const int s = gmsh::model::addDiscreteEntity(2);
    gmsh::model::mesh::addNodes(2, s, node_tags, coords);
    gmsh::model::mesh::addElementsByType(s, 2, {}, triangle_tags);
    const int loop = gmsh::model::geo::addSurfaceLoop({s});
    const int v = gmsh::model::geo::addVolume({loop});
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
    gmsh::model::mesh::getNodes(interior_tags, interior_coords, parametric, 3, v, false, false);
    gmsh::model::mesh::getNodes(surface_tags, surface_coords, parametric, 2, s, false, false);
    std::vector<std::size_t> tet_tags;
    gmsh::model::mesh::getElementsByType(4, tet_tags, tet_nodes, v);
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
  for (std::size_t k = 0; k < split.vertices.size(); ++k) node_of[k + 1] = split.vertices[k];
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
    if (signed_volume(positions, tets[t]) < 0.0) std::swap(tets[t][2], tets[t][3]);
  }

  TetFlips flips;
  if (options.flips) flips = flip_tets(positions, tets, options.flip_floor);
  stc::TetSplit cut = stc::split_tets(split, num_vertices, tets);
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
