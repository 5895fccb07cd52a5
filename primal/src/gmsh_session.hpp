#pragma once
// Private to primal, compiled with Gmsh only (STCWEAVE_HAVE_GMSH): the one Gmsh session of
// the process, shared by the CAD front end (cad.cpp, cad_split.cpp) and the tetrahedral interior
// (tet_interior.cpp).
#include <gmsh.h>

#include <exception>
#include <mutex>
#include <string>

namespace stcweave::primal::gmsh_detail {

/// Gmsh's one global state: initialised on first use, finalised when the program ends.
/// Every use holds `mutex`.
class GmshSession {
 public:
  static GmshSession& instance() {
    static GmshSession session;
    return session;
  }
  std::mutex mutex;

  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
  GmshSession(GmshSession&&) = delete;
  GmshSession& operator=(GmshSession&&) = delete;

 private:
  GmshSession() {
    // No configuration files: the result must not depend on the user's gmshrc.
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
  }
  ~GmshSession() {
    try {
      gmsh::finalize();
    } catch (...) {  // NOLINT(bugprone-empty-catch): nothing to report at program end
    }
  }
};

/// What a Gmsh call threw, as text (Gmsh 4.8 throws std::string, later versions
/// std::exception).
inline std::string gmsh_reason() {
  try {
    throw;
  } catch (const std::string& s) {
    return s;
  } catch (const std::exception& e) {
    return e.what();
  } catch (const char* s) {
    return s;
  } catch (...) {
    return "unknown Gmsh error";
  }
}

}  // namespace stcweave::primal::gmsh_detail
