#include "stcweave/stc/graph_io.hpp"

#include <boost/graph/graphviz.hpp>
#include <boost/property_map/function_property_map.hpp>
#include <fstream>
#include <ostream>
#include <string>
#include <system_error>

#include "stcweave/stc/errors.hpp"

namespace stcweave::stc {
namespace {

std::string dual_vertex_name(const HexStc& stc, std::size_t v) {
  const DualVertex& p = stc.dual_graph[v];
  return p.kind == DualVertexKind::HexVertex ? p.hex.str() : p.quad.str();
}

std::string face_name(const DualEdge& e) {
  return e.hex.str() + ".f" + std::to_string(e.face);
}

const char* bool_str(bool b) {
  return b ? "true" : "false";
}

void write_dual_dot(std::ostream& out, const HexStc& stc) {
  const DualGraph& g = stc.dual_graph;
  const auto vertex_id = boost::make_function_property_map<std::size_t, std::string>(
      [&stc](std::size_t v) { return dual_vertex_name(stc, v); });
  const auto vertex_writer = [&g](std::ostream& os, std::size_t v) {
    const bool hex = g[v].kind == DualVertexKind::HexVertex;
    os << "[kind=" << (hex ? "hex" : "boundary_point") << (hex ? "" : ",shape=point") << "]";
  };
  const auto edge_writer = [&g](std::ostream& os, DualGraph::edge_descriptor e) {
    os << "[label=" << g[e].chord.str() << ",face=\"" << face_name(g[e]) << "\"]";
  };
  const auto graph_writer = [](std::ostream& os) { os << "label=\"dual graph\";\n"; };
  boost::write_graphviz(out, g, vertex_writer, edge_writer, graph_writer, vertex_id);
}

void write_sheet_dot(std::ostream& out, const HexStc& stc) {
  const SheetGraph& g = stc.sheet_graph;
  const auto vertex_id = boost::make_function_property_map<std::size_t, std::string>(
      [&g](std::size_t v) { return g[v].sheet.str(); });
  const auto vertex_writer = [&stc, &g](std::ostream& os, std::size_t v) {
    const Sheet& s = stc.sheet(g[v].sheet);
    os << "[hexes=" << s.hexes.size() << ",loops=" << s.boundary_loops.size()
       << ",chords=" << s.chords.size() << ",self_intersecting=" << bool_str(s.self_intersecting)
       << ",blind=" << bool_str(is_blind(s)) << "]";
  };
  const auto edge_writer = [&stc, &g](std::ostream& os, SheetGraph::edge_descriptor e) {
    const Chord& c = stc.chord(g[e].chord);
    os << "[label=" << g[e].chord.str() << ",hexes=" << c.hexes.size()
       << ",blind=" << bool_str(is_blind(c)) << (is_blind(c) ? ",style=dashed" : "") << "]";
  };
  const auto graph_writer = [](std::ostream& os) { os << "label=\"sheet graph\";\n"; };
  boost::write_graphviz(out, g, vertex_writer, edge_writer, graph_writer, vertex_id);
}

/// One GraphML `<key>` declaration.
void graphml_key(std::ostream& out, const char* id, const char* domain, const char* type) {
  out << "  <key id=\"" << id << "\" for=\"" << domain << "\" attr.name=\"" << id
      << "\" attr.type=\"" << type << "\"/>\n";
}

void graphml_header(std::ostream& out) {
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\"\n"
      << "    xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\"\n"
      << "    xsi:schemaLocation=\"http://graphml.graphdrawing.org/xmlns "
         "http://graphml.graphdrawing.org/xmlns/1.0/graphml.xsd\">\n";
  // Keys of both graphs (a key unused by a graph is harmless).
  graphml_key(out, "label", "all", "string");
  graphml_key(out, "kind", "node", "string");
  graphml_key(out, "face", "edge", "string");
  graphml_key(out, "hexes", "all", "int");
  graphml_key(out, "loops", "node", "int");
  graphml_key(out, "chords", "node", "int");
  graphml_key(out, "self_intersecting", "node", "boolean");
  graphml_key(out, "blind", "all", "boolean");
}

template <class T>
void data(std::ostream& out, const char* key, const T& value) {
  out << "<data key=\"" << key << "\">" << value << "</data>";
}

void write_dual_graphml(std::ostream& out, const HexStc& stc) {
  const DualGraph& g = stc.dual_graph;
  out << "  <graph id=\"dual\" edgedefault=\"undirected\">\n";
  for (std::size_t v = 0; v < boost::num_vertices(g); ++v) {
    const std::string name = dual_vertex_name(stc, v);
    out << "    <node id=\"" << name << "\">";
    data(out, "label", name);
    data(out, "kind", g[v].kind == DualVertexKind::HexVertex ? "hex" : "boundary_point");
    out << "</node>\n";
  }
  std::size_t i = 0;
  for (const auto e : boost::make_iterator_range(boost::edges(g))) {
    out << "    <edge id=\"e" << i++ << "\" source=\"" << dual_vertex_name(stc, boost::source(e, g))
        << "\" target=\"" << dual_vertex_name(stc, boost::target(e, g)) << "\">";
    data(out, "label", g[e].chord.str());
    data(out, "face", face_name(g[e]));
    out << "</edge>\n";
  }
  out << "  </graph>\n";
}

void write_sheet_graphml(std::ostream& out, const HexStc& stc) {
  const SheetGraph& g = stc.sheet_graph;
  out << "  <graph id=\"sheets\" edgedefault=\"undirected\">\n";
  for (std::size_t v = 0; v < boost::num_vertices(g); ++v) {
    const Sheet& s = stc.sheet(g[v].sheet);
    out << "    <node id=\"" << g[v].sheet.str() << "\">";
    data(out, "label", g[v].sheet.str());
    data(out, "hexes", s.hexes.size());
    data(out, "loops", s.boundary_loops.size());
    data(out, "chords", s.chords.size());
    data(out, "self_intersecting", bool_str(s.self_intersecting));
    data(out, "blind", bool_str(is_blind(s)));
    out << "</node>\n";
  }
  for (const auto e : boost::make_iterator_range(boost::edges(g))) {
    const ChordId id = g[e].chord;
    const Chord& c = stc.chord(id);
    out << "    <edge id=\"" << id.str() << "\" source=\"" << g[boost::source(e, g)].sheet.str()
        << "\" target=\"" << g[boost::target(e, g)].sheet.str() << "\">";
    data(out, "label", id.str());
    data(out, "hexes", c.hexes.size());
    data(out, "blind", bool_str(is_blind(c)));
    out << "</edge>\n";
  }
  out << "  </graph>\n";
}

}  // namespace

void write_graphs(std::ostream& out, const HexStc& stc, const std::vector<StcGraph>& graphs,
                  GraphFormat format) {
  if (format == GraphFormat::GraphMl) graphml_header(out);
  for (const StcGraph graph : graphs) {
    if (format == GraphFormat::Dot)
      graph == StcGraph::Dual ? write_dual_dot(out, stc) : write_sheet_dot(out, stc);
    else
      graph == StcGraph::Dual ? write_dual_graphml(out, stc) : write_sheet_graphml(out, stc);
  }
  if (format == GraphFormat::GraphMl) out << "</graphml>\n";
}

void write_graph(std::ostream& out, const HexStc& stc, StcGraph graph, GraphFormat format) {
  write_graphs(out, stc, {graph}, format);
}

void write_graph_file(const std::filesystem::path& path, const HexStc& stc,
                      const std::vector<StcGraph>& graphs, GraphFormat format) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
      throw IoError("cannot write " + path.string() + ": cannot create " + temporary.string() +
                    "; check the folder exists and is writable");
    write_graphs(out, stc, graphs, format);
    out.flush();
    if (!out) {
      out.close();
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw IoError("cannot write " + path.string() + " (disk full?)");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw IoError("cannot write " + path.string() + ": " + error.message());
  }
}

}  // namespace stcweave::stc
