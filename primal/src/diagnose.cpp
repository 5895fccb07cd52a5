#include "stcweave/primal/diagnose.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>

#include "stcweave/stc/errors.hpp"
#include "stcweave/stc/loops.hpp"
#include "surface_crossings.hpp"

namespace stcweave::primal {
namespace {

/// How many elements a message names before saying how many there are in all.
constexpr std::size_t kNamed = 5;

std::string prefix(const SurfaceDiagnosis& d) {
  return d.path.empty() ? "" : d.path + ": ";
}

std::string edge_name(const NodePair& e) {
  return e[0].str() + "-" + e[1].str();
}

/// `q12 (face 2 of h7)` for a hex boundary, `q12 (line 40)` when the line is known.
std::string quad_name(const SurfaceDiagnosis& d, QuadId q) {
  std::string s = q.str();
  if (q.index() < d.quad_origins.size()) {
    const stc::HexFaceRef& o = d.quad_origins[q.index()];
    s += " (face " + std::to_string(o.face) + " of " + o.hex.str() + ")";
  } else if (q.index() < d.quad_lines.size() && d.quad_lines[q.index()] > 0) {
    s += " (line " + std::to_string(d.quad_lines[q.index()]) + ")";
  }
  return s;
}

/// The first `kNamed` names, then "... (N in all)".
template <class T, class Name>
std::string name_list(const std::vector<T>& items, Name name) {
  std::string s;
  for (std::size_t i = 0; i < items.size() && i < kNamed; ++i) {
    if (i > 0) s += ", ";
    s += name(i, items[i]);
  }
  if (items.size() > kNamed) s += ", ... (" + std::to_string(items.size()) + " in all)";
  return s;
}

/// Checks every node index of the file's cells against its points.
void check_node_indices(const MeshFile& file) {
  const auto rows = static_cast<std::size_t>(file.points.rows());
  const auto fail = [&](const std::string& cell, NodeId v) {
    std::string msg = file.path;
    msg += ": ";
    msg += cell;
    msg += " refers to node ";
    msg += v.str();
    msg += " but the file has ";
    msg += std::to_string(rows);
    msg += " nodes: fix the connectivity of the file";
    throw InvalidInput(msg);
  };
  const auto bad = [&](NodeId v) { return !v.is_valid() || v.index() >= rows; };
  for (std::size_t h = 0; h < file.hexes.size(); ++h)
    for (NodeId v : file.hexes[h])
      if (bad(v)) fail("hex " + HexId(h).str(), v);
  if (file.hexes.empty()) {
    for (std::size_t q = 0; q < file.quads.size(); ++q)
      for (NodeId v : file.quads[q])
        if (bad(v)) fail("quad " + QuadId(q).str(), v);
  }
}

/// The surface to diagnose, in file node numbering.
stc::QuadSurface file_surface(const MeshFile& file, std::vector<stc::HexFaceRef>* origins,
                              std::vector<stc::HexFaceRef>* nonmanifold_faces) {
  check_node_indices(file);
  if (!file.hexes.empty()) {
    stc::HexComplex complex;
    complex.hexes = file.hexes;
    complex.num_nodes = static_cast<std::size_t>(file.points.rows());
    return stc::boundary_surface(complex, origins, nonmanifold_faces);
  }
  stc::QuadSurface surface;
  surface.quads = file.quads;
  surface.num_nodes = static_cast<std::size_t>(file.points.rows());
  return surface;
}

bool is_finite_row(const Points& p, Eigen::Index r) {
  return std::isfinite(p(r, 0)) && std::isfinite(p(r, 1)) && std::isfinite(p(r, 2));
}

/// Surface nodes sharing a cell of the grid of step 1e-9 x `span`, their largest
/// bounding-box extent.
std::size_t count_coincident(const Points& points, const std::vector<NodeId>& nodes, double span) {
  if (nodes.empty()) return 0;
  if (span == 0.0) span = 1.0;
  const double step = span * 1e-9;
  std::vector<std::array<double, 3>> cells;
  cells.reserve(nodes.size());
  for (NodeId v : nodes) {
    // nearbyint rounds half to even in the default rounding mode, like Python's round().
    cells.push_back({std::nearbyint(points(v.value(), 0) / step),
                     std::nearbyint(points(v.value(), 1) / step),
                     std::nearbyint(points(v.value(), 2) / step)});
  }
  std::sort(cells.begin(), cells.end());
  std::size_t coincident = 0;
  for (std::size_t i = 1; i < cells.size(); ++i)
    if (cells[i] == cells[i - 1]) ++coincident;
  return coincident;
}

template <class T>
nlohmann::json optional_json(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

/// Whether the ray from `o` along `dir` crosses triangle (a, b, c) at t > 0
/// (Moeller-Trumbore).
bool ray_hits_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& dir,
                       const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a;
  const Eigen::Vector3d e2 = c - a;
  const Eigen::Vector3d p = dir.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return false;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = dir.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  return e2.dot(q) * inv > 0.0;
}

}  // namespace

SurfaceMesh surface_of(const MeshFile& file, std::vector<NodeId>* file_nodes) {
  SurfaceMesh mesh;
  stc::QuadSurface surface = file_surface(file, nullptr, nullptr);
  if (file.hexes.empty()) {
    if (file_nodes != nullptr) {
      file_nodes->clear();
      for (std::size_t v = 0; v < surface.num_nodes; ++v) file_nodes->push_back(NodeId(v));
    }
    mesh.points = file.points;
    mesh.surface = std::move(surface);
    return mesh;
  }
  // Compact the boundary's nodes, keeping their relative order.
  std::vector<NodeId> renumber(surface.num_nodes, NodeId::invalid());
  for (const stc::Quad& q : surface.quads)
    for (NodeId v : q) renumber[v.index()] = NodeId(0);
  std::vector<NodeId> old_ids;
  for (std::size_t v = 0; v < renumber.size(); ++v) {
    if (!renumber[v].is_valid()) continue;
    renumber[v] = NodeId(old_ids.size());
    old_ids.push_back(NodeId(v));
  }
  mesh.points.resize(static_cast<Eigen::Index>(old_ids.size()), 3);
  for (std::size_t i = 0; i < old_ids.size(); ++i)
    mesh.points.row(static_cast<Eigen::Index>(i)) = file.points.row(old_ids[i].value());
  for (stc::Quad& q : surface.quads)
    for (NodeId& v : q) v = renumber[v.index()];
  surface.num_nodes = old_ids.size();
  mesh.surface = std::move(surface);
  if (file_nodes != nullptr) *file_nodes = std::move(old_ids);
  return mesh;
}

SurfaceDiagnosis diagnose(const MeshFile& file) {
  SurfaceDiagnosis d;
  d.path = file.path;
  d.format = file.format;
  d.hexes = file.hexes.size();
  d.from_hexes = !file.hexes.empty();
  d.triangles = file.triangles;
  d.tetrahedra = file.tetrahedra;
  d.other_cells = file.other_cells;
  d.first_other_cell = file.first_other_cell;

  std::vector<stc::HexFaceRef> nonmanifold_faces;
  const stc::QuadSurface surface = file_surface(file, &d.quad_origins, &nonmanifold_faces);
  d.nonmanifold_hex_faces = nonmanifold_faces.size();
  if (!d.from_hexes) d.quad_lines = file.quad_lines;

  const stc::SurfaceTopology topo = stc::surface_topology(surface);
  d.quads = surface.num_quads();
  d.nodes = topo.num_nodes_used;
  d.components = topo.components.size();
  d.closed = topo.is_closed();
  d.manifold = topo.is_manifold();
  d.consistently_oriented = topo.is_consistently_oriented();
  if (!d.from_hexes) d.orientable = topo.is_orientable();
  d.euler_characteristic = topo.euler_characteristic();
  d.genus = topo.genus();
  for (const stc::ComponentTopology& c : topo.components) d.genus_per_component.push_back(c.genus);
  d.open_edges = topo.open_edges.size();
  d.nonmanifold_edges = topo.nonmanifold_edges.size();
  d.nonmanifold_nodes = topo.nonmanifold_nodes.size();
  d.inconsistent_edges = topo.inconsistent_edges.size();
  d.degenerate_quads = topo.degenerate_quads.size();

  // Where the defects are.
  const auto pair_of = [&](stc::EdgeId e) { return NodePair{topo.edge(e).a, topo.edge(e).b}; };
  for (stc::EdgeId e : topo.open_edges) {
    d.sites.open_edges.push_back(pair_of(e));
    d.sites.open_edge_quads.push_back(topo.uses(e)[0].quad);
  }
  for (stc::EdgeId e : topo.nonmanifold_edges) {
    d.sites.nonmanifold_edges.push_back(pair_of(e));
    d.sites.nonmanifold_edge_uses.push_back(topo.uses(e).size());
  }
  d.sites.nonmanifold_nodes = topo.nonmanifold_nodes;
  d.sites.degenerate_quads = topo.degenerate_quads;
  {
    std::map<std::array<std::int32_t, 4>, QuadId> first;
    for (std::size_t q = 0; q < surface.quads.size(); ++q) {
      std::array<std::int32_t, 4> key{};
      for (std::size_t i = 0; i < 4; ++i) key[i] = surface.quads[q][i].value();
      std::sort(key.begin(), key.end());
      if (std::adjacent_find(key.begin(), key.end()) != key.end()) continue;  // degenerate
      const auto [it, fresh] = first.emplace(key, QuadId(q));
      if (!fresh) d.sites.duplicate_quads.push_back({it->second, QuadId(q)});
    }
  }
  d.duplicate_quads = d.sites.duplicate_quads.size();
  if (!topo.orientation_conflicts.empty()) {
    const stc::EdgeId e = topo.orientation_conflicts.front();
    d.sites.orientation_conflict = pair_of(e);
    d.sites.orientation_conflict_quads = {topo.uses(e)[0].quad, topo.uses(e)[1].quad};
  }

  // Loops (null figures when an edge is non-manifold: loops are not defined there).
  const stc::LoopSet loops = stc::find_loops(surface, topo, stc::FindLoopsOptions{false});
  if (topo.nonmanifold_edges.empty()) {
    d.loops = loops.size();
    d.self_intersecting_loops = loops.num_self_intersecting();
    d.self_crossing_quads = loops.num_self_crossing_quads();
    d.longest_loop = loops.longest_length();
    d.open_loops = loops.num_open();
  }
  for (const stc::Loop& l : loops.loops)
    if (l.is_self_intersecting())
      d.sites.self_intersecting_loops.push_back({l.id, l.length(), l.self_crossing_quads});

  // Geometry of the surface nodes.
  std::vector<NodeId> finite;
  {
    std::vector<char> used(surface.num_nodes, 0);
    for (const stc::Quad& q : surface.quads)
      for (NodeId v : q) used[v.index()] = 1;
    for (std::size_t v = 0; v < used.size(); ++v) {
      if (used[v] == 0) continue;
      if (is_finite_row(file.points, static_cast<Eigen::Index>(v))) {
        finite.push_back(NodeId(v));
      } else {
        d.sites.nonfinite_nodes.push_back(NodeId(v));
      }
    }
  }
  d.nonfinite_nodes = d.sites.nonfinite_nodes.size();
  if (!finite.empty()) {
    Eigen::RowVector3d lo = file.points.row(finite.front().value());
    Eigen::RowVector3d hi = lo;
    for (NodeId v : finite) {
      lo = lo.cwiseMin(file.points.row(v.value()));
      hi = hi.cwiseMax(file.points.row(v.value()));
    }
    d.coordinate_magnitude = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
    d.extent = (hi - lo).maxCoeff();
  }
  d.coincident_nodes = count_coincident(file.points, finite, d.extent);
  if (d.nonfinite_nodes == 0) {
    d.sites.crossing_quads = crossing_quads(file.points, surface);
    d.crossing_quad_pairs = d.sites.crossing_quads.size();
  }

  // Handles: which cycles bound inside the solid (needs the embedding, oriented outward).
  if (d.genus && *d.genus > 0 && d.closed && d.manifold && topo.is_orientable() &&
      d.nonfinite_nodes == 0 && d.degenerate_quads == 0) {
    std::vector<NodeId> file_nodes;
    SurfaceMesh oriented = surface_of(file, &file_nodes);
    orient_outward(oriented);
    HandleDiagnosis h = diagnose_handles(oriented);
    for (HandleCycle& c : h.handles)
      for (NodeId& v : c.nodes) v = file_nodes[v.index()];
    for (auto& list : h.alternatives)
      for (HandleCycle& c : list)
        for (NodeId& v : c.nodes) v = file_nodes[v.index()];
    d.handles = std::move(h);
  }
  return d;
}

nlohmann::json to_json(const SurfaceDiagnosis& d) {
  nlohmann::json j;
  j["path"] = d.path;
  j["format"] = d.format;
  j["source"] = d.from_hexes ? "hex boundary" : "file quads";
  j["hexes"] = d.hexes;
  j["triangles"] = d.triangles;
  j["tetrahedra"] = d.tetrahedra;
  j["other_cells"] = d.other_cells;
  j["quads"] = d.quads;
  j["quad_parity"] = d.has_even_quads() ? "even" : "odd";
  j["nodes"] = d.nodes;
  j["components"] = d.components;
  j["closed"] = d.closed;
  j["manifold"] = d.manifold;
  j["consistently_oriented"] = d.consistently_oriented;
  j["orientable"] = optional_json(d.orientable);
  j["euler_characteristic"] = d.euler_characteristic;
  j["genus"] = optional_json(d.genus);
  nlohmann::json per_component = nlohmann::json::array();
  for (const auto& g : d.genus_per_component) per_component.push_back(optional_json(g));
  j["genus_per_component"] = per_component;
  j["loops"] = optional_json(d.loops);
  j["self_intersecting_loops"] = optional_json(d.self_intersecting_loops);
  j["self_crossing_quads"] = optional_json(d.self_crossing_quads);
  j["longest_loop"] = optional_json(d.longest_loop);
  j["open_loops"] = optional_json(d.open_loops);
  j["open_edges"] = d.open_edges;
  j["nonmanifold_edges"] = d.nonmanifold_edges;
  j["nonmanifold_nodes"] = d.nonmanifold_nodes;
  j["inconsistent_edges"] = d.inconsistent_edges;
  j["coincident_nodes"] = d.coincident_nodes;
  j["degenerate_quads"] = d.degenerate_quads;
  j["duplicate_quads"] = d.duplicate_quads;
  j["nonfinite_nodes"] = d.nonfinite_nodes;
  j["crossing_quad_pairs"] = optional_json(d.crossing_quad_pairs);
  j["coordinate_magnitude"] = d.coordinate_magnitude;
  j["extent"] = d.extent;
  j["nonmanifold_hex_faces"] = d.nonmanifold_hex_faces;
  nlohmann::json self = nlohmann::json::array();
  for (const SelfIntersection& s : d.sites.self_intersecting_loops) {
    nlohmann::json quads = nlohmann::json::array();
    for (QuadId q : s.quads) quads.push_back(q.value());
    self.push_back({{"loop", s.loop.value()}, {"length", s.length}, {"quads", quads}});
  }
  j["self_intersections"] = self;
  if (d.handles) {
    nlohmann::json handles = nlohmann::json::array();
    for (const HandleCycle& c : d.handles->handles) {
      nlohmann::json nodes = nlohmann::json::array();
      for (NodeId v : c.nodes) nodes.push_back(v.value());
      handles.push_back({{"component", c.component.value()},
                         {"length", c.length()},
                         {"even", c.is_even()},
                         {"nodes", nodes}});
    }
    j["handles"] = {{"decided", d.handles->decided},
                    {"undecided_reason", d.handles->undecided_reason},
                    {"cycles", handles},
                    {"combined_lengths", d.handles->combined_lengths},
                    {"projections_tried", d.handles->projections_tried},
                    {"all_even", d.handles->all_even()}};
  } else {
    j["handles"] = nullptr;
  }
  try {
    require_weavable(d);
    j["weavable"] = true;
    j["defect"] = nullptr;
  } catch (const TopologyError& e) {
    j["weavable"] = false;
    j["defect"] = e.what();
  }
  return j;
}

void require_finite_hex_nodes(const MeshFile& file) {
  std::vector<char> used(static_cast<std::size_t>(file.points.rows()), 0);
  for (const stc::Hex& h : file.hexes)
    for (NodeId v : h)
      if (v.is_valid() && v.index() < used.size()) used[v.index()] = 1;
  std::vector<NodeId> bad;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v] != 0 && !is_finite_row(file.points, static_cast<Eigen::Index>(v)))
      bad.push_back(NodeId(v));
  if (bad.empty()) return;
  throw InvalidInput(file.path + ": " + std::to_string(bad.size()) +
                     " hex node(s) have non-finite coordinates (NaN or infinite): " +
                     name_list(bad, [](std::size_t, NodeId v) { return v.str(); }) +
                     "; fix or remove those nodes in the file");
}

std::string crossing_warning(const SurfaceDiagnosis& d) {
  if (d.sites.crossing_quads.empty()) return "";
  return prefix(d) +
         "the surface passes through itself: " + std::to_string(d.sites.crossing_quads.size()) +
         " pair(s) of quads cross: " +
         name_list(d.sites.crossing_quads,
                   [&](std::size_t, const std::array<QuadId, 2>& pair) {
                     return quad_name(d, pair[0]) + " crosses " + quad_name(d, pair[1]);
                   }) +
         "; no solid has such a boundary, so hexes there stay inverted whatever their "
         "positions: move the nodes so that the surface no longer cuts through itself (a node "
         "dragged too far, two solids overlapping, a fold in a surface mesh)";
}

void require_weavable(const SurfaceDiagnosis& d, bool allow_self_intersecting_loops) {
  const std::string at = prefix(d);
  const auto quad = [&](std::size_t, QuadId q) { return quad_name(d, q); };
  const auto node = [](std::size_t, NodeId v) { return v.str(); };

  if (d.triangles + d.tetrahedra + d.other_cells > 0) {
    std::string cells;
    const auto add = [&](std::size_t n, const char* what) {
      if (n == 0) return;
      if (!cells.empty()) cells += ", ";
      cells += std::to_string(n) + " " + what;
    };
    add(d.triangles, "triangles");
    add(d.tetrahedra, "tetrahedra");
    add(d.other_cells, "other cells (prisms, pyramids, polygons)");
    if (!d.first_other_cell.empty()) cells += " (the first other cell: " + d.first_other_cell + ")";
    throw TopologyError(at + "the file holds " + cells + " besides " +
                        (d.from_hexes ? "hexahedra" : "quads") +
                        ": stcweave needs a pure quad surface (or hex mesh); convert the other "
                        "cells to quads (e.g. split each triangle into three quads) and retry");
  }
  if (d.quads == 0 && d.from_hexes) {
    throw TopologyError(at + "the file's " + std::to_string(d.hexes) +
                        " hexahedra have no boundary face (every face is shared by two or more "
                        "of them: duplicated hexes?); `stcweave check` on the file lists the "
                        "defects");
  }
  if (d.quads == 0) {
    throw TopologyError(at +
                        "no quads and no hexahedra found: nothing to mesh; is this the right "
                        "file and format? (" +
                        (d.format == "obj" ? "OBJ quads are `f` lines with four nodes; " : "") +
                        "name the format explicitly when the extension is wrong)");
  }
  if (d.nonfinite_nodes > 0) {
    throw TopologyError(at + std::to_string(d.nonfinite_nodes) +
                        " surface node(s) have non-finite coordinates (NaN or infinite): " +
                        name_list(d.sites.nonfinite_nodes, node) +
                        "; fix or remove those nodes in the file");
  }
  if (d.quads > 0 && d.coordinate_magnitude > kLargestCoordinate) {
    throw TopologyError(
        at + "coordinates up to " + short_number(d.coordinate_magnitude) +
        " lie beyond the range the geometry works in (|x| <= " + short_number(kLargestCoordinate) +
        "): rescale the model (e.g. change its length unit) and retry");
  }
  if (d.quads > 0 && d.extent < kSmallestExtent) {
    throw TopologyError(
        at + (d.extent == 0.0
                  ? std::string("the surface has no extent: all its nodes coincide; give the "
                                "nodes their coordinates")
                  : "the surface's bounding box is only " + short_number(d.extent) +
                        " across, below the range the geometry works in (" +
                        short_number(kSmallestExtent) +
                        "); rescale the model (e.g. change its length unit) and retry"));
  }
  if (d.degenerate_quads > 0) {
    throw TopologyError(
        at + std::to_string(d.degenerate_quads) +
        " degenerate quad(s) repeat a node: " + name_list(d.sites.degenerate_quads, quad) +
        "; collapse or re-mesh them so every quad has four distinct nodes");
  }
  if (d.duplicate_quads > 0) {
    throw TopologyError(
        at + std::to_string(d.duplicate_quads) +
        " quad(s) have the same four nodes as another quad: " +
        name_list(d.sites.duplicate_quads,
                  [&](std::size_t, const std::array<QuadId, 2>& pair) {
                    return quad_name(d, pair[1]) + " repeats " + quad_name(d, pair[0]);
                  }) +
        "; two such quads enclose no volume: remove the repeated quads or re-mesh the surface");
  }
  if (d.open_edges > 0) {
    throw TopologyError(
        at + "the surface is open: " + std::to_string(d.open_edges) +
        " edge(s) belong to a single quad: " +
        name_list(d.sites.open_edges,
                  [&](std::size_t i, const NodePair& e) {
                    return edge_name(e) + " of " + quad_name(d, d.sites.open_edge_quads[i]);
                  }) +
        "; close the surface (every edge must be shared by exactly two quads), e.g. merge "
        "duplicated nodes or add the missing quads");
  }
  if (d.nonmanifold_edges > 0) {
    throw TopologyError(
        at + "the surface is non-manifold: " + std::to_string(d.nonmanifold_edges) +
        " edge(s) are shared by more than two quads: " +
        name_list(d.sites.nonmanifold_edges,
                  [&](std::size_t i, const NodePair& e) {
                    return edge_name(e) + " (" + std::to_string(d.sites.nonmanifold_edge_uses[i]) +
                           " quads)";
                  }) +
        "; separate the solids touching along these edges (duplicate their nodes) or re-mesh");
  }
  if (d.nonmanifold_nodes > 0) {
    throw TopologyError(at + "the surface is non-manifold at " +
                        std::to_string(d.nonmanifold_nodes) +
                        " node(s) where separate fans of quads meet: " +
                        name_list(d.sites.nonmanifold_nodes, node) +
                        "; separate the pieces touching at these nodes (duplicate the nodes) or "
                        "re-mesh");
  }
  if (d.sites.orientation_conflict) {
    const auto& e = *d.sites.orientation_conflict;
    throw TopologyError(at +
                        "the surface is not orientable (like a Moebius strip or a Klein "
                        "bottle): no orientation of the quads agrees across edge " +
                        edge_name(e) + " between " +
                        quad_name(d, d.sites.orientation_conflict_quads[0]) + " and " +
                        quad_name(d, d.sites.orientation_conflict_quads[1]) +
                        "; a solid's boundary is always orientable: check the input");
  }
  if (!d.has_even_quads()) {
    throw TopologyError(at + "the surface has " + std::to_string(d.quads) +
                        " quads, an odd number: no hex mesh can have that boundary (6 x hexes "
                        "= 2 x inner faces + boundary quads); re-mesh the surface with an even "
                        "number of quads (e.g. split every quad into four)");
  }
  if (d.handles && d.handles->decided && !d.handles->all_even()) {
    const HandleDiagnosis& h = *d.handles;
    if (h.odd_handle >= 0) {
      const HandleCycle& c = h.handles[static_cast<std::size_t>(h.odd_handle)];
      throw TopologyError(at + "no hex mesh with this boundary exists: the cycle " + cycle_name(c) +
                          " has " + std::to_string(c.length()) +
                          " edges and bounds a surface inside the solid (it goes round a "
                          "handle of " +
                          c.component.str() +
                          "), and every cycle bounding inside a hex mesh has an even length "
                          "(Erickson 2014); re-mesh the surface so that the cycles around "
                          "each handle have an even number of edges");
    }
    throw TopologyError(at +
                        "no hex mesh with this boundary exists: a cycle of odd length, spread "
                        "over several shells, bounds a surface inside the solid (Erickson "
                        "2014); re-mesh the surface so that such cycles are even");
  }
  if (!allow_self_intersecting_loops && !d.sites.self_intersecting_loops.empty()) {
    const SelfIntersection& first = d.sites.self_intersecting_loops.front();
    std::string others;
    if (d.sites.self_intersecting_loops.size() > 1) {
      others = "; " + std::to_string(d.sites.self_intersecting_loops.size()) +
               " loops are self-intersecting: " +
               name_list(d.sites.self_intersecting_loops,
                         [](std::size_t, const SelfIntersection& s) { return s.loop.str(); });
    }
    throw TopologyError(at + "loop " + first.loop.str() + " (" + std::to_string(first.length) +
                        " quads) crosses itself in " + name_list(first.quads, quad) + others +
                        "; whisker weaving needs loops that never cross themselves: re-mesh the "
                        "surface (e.g. split each triangle of a triangle mesh into three quads)");
  }
}

OrientationReport orient_outward(SurfaceMesh& mesh) {
  stc::QuadSurface& surface = mesh.surface;
  if (static_cast<std::size_t>(mesh.points.rows()) < surface.num_nodes) {
    throw InvalidInput("orient_outward: the surface has " + std::to_string(surface.num_nodes) +
                       " nodes but only " + std::to_string(mesh.points.rows()) +
                       " points: give every node a position");
  }
  const stc::SurfaceTopology topo = stc::surface_topology(surface);
  if (!topo.is_orientable()) {
    const stc::EdgeId e = topo.orientation_conflicts.front();
    const ComponentId c = topo.quad_components[topo.uses(e)[0].quad.index()];
    throw TopologyError(c.str() +
                        " is not orientable: no orientation of its quads agrees across "
                        "edge " +
                        edge_name({topo.edge(e).a, topo.edge(e).b}) + " between " +
                        topo.uses(e)[0].quad.str() + " and " + topo.uses(e)[1].quad.str() +
                        "; a solid's boundary is always orientable: check the input");
  }
  std::vector<bool> flipped = topo.orientation_flips;
  surface = stc::consistently_oriented(surface, topo);

  const std::size_t num_components = topo.components.size();
  OrientationReport report;
  report.components = num_components;
  report.nesting_depth.assign(num_components, 0);

  // Signed volume per component (about the centre of the bounding box, for accuracy) and
  // bounding boxes for the enclosure test.
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  if (mesh.points.rows() > 0)
    centre = 0.5 * (mesh.points.colwise().minCoeff() + mesh.points.colwise().maxCoeff());
  std::vector<double> volume(num_components, 0.0);
  std::vector<Eigen::Vector3d> lo(num_components, Eigen::Vector3d::Constant(INFINITY));
  std::vector<Eigen::Vector3d> hi(num_components, Eigen::Vector3d::Constant(-INFINITY));
  std::vector<std::vector<std::size_t>> quads_of(num_components);
  const auto point = [&](NodeId v) -> Eigen::Vector3d {
    return (mesh.points.row(v.value()) - centre).transpose();
  };
  for (std::size_t q = 0; q < surface.num_quads(); ++q) {
    const std::size_t c = topo.quad_components[q].index();
    quads_of[c].push_back(q);
    const stc::Quad& quad = surface.quads[q];
    const Eigen::Vector3d p0 = point(quad[0]), p1 = point(quad[1]), p2 = point(quad[2]),
                          p3 = point(quad[3]);
    volume[c] += (p0.dot(p1.cross(p2)) + p0.dot(p2.cross(p3))) / 6.0;
    for (NodeId v : quad) {
      lo[c] = lo[c].cwiseMin(point(v));
      hi[c] = hi[c].cwiseMax(point(v));
    }
  }
  // Enclosure: ray parity from one node of each closed component against the others.
  const Eigen::Vector3d dir = Eigen::Vector3d(0.5390117, 0.6421423, 0.5449871).normalized();
  for (std::size_t c = 0; c < num_components; ++c) {
    if (!topo.components[c].closed || quads_of[c].empty()) continue;
    const Eigen::Vector3d o = point(surface.quads[quads_of[c].front()][0]);
    for (std::size_t other = 0; other < num_components; ++other) {
      if (other == c || !topo.components[other].closed) continue;
      if ((o.array() < lo[other].array()).any() || (o.array() > hi[other].array()).any()) continue;
      std::size_t hits = 0;
      for (std::size_t q : quads_of[other]) {
        const stc::Quad& quad = surface.quads[q];
        const Eigen::Vector3d p0 = point(quad[0]), p1 = point(quad[1]), p2 = point(quad[2]),
                              p3 = point(quad[3]);
        hits += ray_hits_triangle(o, dir, p0, p1, p2) ? 1 : 0;
        hits += ray_hits_triangle(o, dir, p0, p2, p3) ? 1 : 0;
      }
      if (hits % 2 == 1) ++report.nesting_depth[c];
    }
  }
  for (std::size_t c = 0; c < num_components; ++c) {
    const bool want_positive = report.nesting_depth[c] % 2 == 0;
    const bool reverse = want_positive ? volume[c] < 0.0 : volume[c] > 0.0;
    if (!reverse) continue;
    for (std::size_t q : quads_of[c]) {
      surface.quads[q] = stc::reversed(surface.quads[q]);
      flipped[q] = !flipped[q];
    }
  }
  report.flipped_quads = static_cast<std::size_t>(std::count(flipped.begin(), flipped.end(), true));
  return report;
}

}  // namespace stcweave::primal
