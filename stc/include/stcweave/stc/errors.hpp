#pragma once
/// \file
/// The exception hierarchy at the library boundary. Library code never prints and never
/// exits: it throws one of these, with a message that says what is wrong, where (file,
/// line, element id) and what the user can do. The CLI maps them to exit codes:
///
/// | exception        | meaning                                            | exit code |
/// |------------------|----------------------------------------------------|-----------|
/// | `InvalidInput`   | the input cannot be used (format, topology, ...)   | 2         |
/// | `TopologyError`  | an `InvalidInput` about the surface's topology     | 2         |
/// | `Unsupported`    | a valid input outside what is supported yet        | 2         |
/// | `IoError`        | a file cannot be opened, read or written           | 2         |
/// | `WeaveError`     | the weave could not complete                       | 3         |
/// | `SolverError`    | a numerical solve failed                           | 3         |
/// | `InternalError`  | a broken invariant: a bug, please report it        | 3         |

#include <array>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace stcweave {

/// Base of every exception thrown by stcweave.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input (a file, a mesh, an option) cannot be used as it is.
class InvalidInput : public Error {
 public:
  using Error::Error;
};

/// The input surface has a topological defect (open, non-manifold, non-orientable, odd
/// number of quads, self-intersecting loop, ...).
class TopologyError : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

/// A valid input that stcweave does not handle yet (for example genus > 0).
class Unsupported : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

/// A file cannot be opened, read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

/// The weave could not complete (every rule blocked, step limit reached).
class WeaveError : public Error {
 public:
  using Error::Error;
};

/// A numerical solve failed (factorisation, non-convergence).
class SolverError : public Error {
 public:
  using Error::Error;
};

/// A broken internal invariant: always a bug in stcweave.
class InternalError : public Error {
 public:
  using Error::Error;
};

/// A number for a message: six significant digits, exponent form where it is large or small
/// (std::to_string writes 1e308 with 309 digits and 1e-9 as 0.000000).
inline std::string short_number(double v) {
  std::array<char, 32> buf{};
  std::snprintf(buf.data(), buf.size(), "%.6g", v);
  return buf.data();
}

}  // namespace stcweave
