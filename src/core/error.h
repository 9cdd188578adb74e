// Typed errors of scan2pattern. Stages validate at entry and throw one of these; the CLI maps
// each type to its own exit code (see exitCode). Messages name the input, the element and what
// the user can do.
#pragma once

#include <stdexcept>
#include <string>

namespace s2p {

// === Exit codes of the `scan2pattern` command (documented in the README).
enum class ExitCode : int {
  Ok = 0,
  Internal = 1,       // a bug: an unexpected exception
  Usage = 2,          // bad command-line arguments
  Io = 3,             // a file is missing, unreadable or cannot be written
  Format = 4,         // a file is truncated, garbage or has no mesh in it
  Input = 5,          // the mesh is read but unusable: non-finite, no faces, not a person
  Topology = 6,       // the mesh cannot be repaired into what a stage needs
  Solver = 7,         // a numerical solver failed (matrix not positive definite, no convergence)
};

// Base of every error scan2pattern throws on purpose.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
  virtual ExitCode exitCode() const { return ExitCode::Internal; }
};

// The input is readable but its content is unusable (NaN coordinates, no faces, absurd size).
class InputError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const override { return ExitCode::Input; }
};

// The mesh's connectivity is not what the algorithm needs (non-manifold, wrong genus, ...).
class TopologyError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const override { return ExitCode::Topology; }
};

// A numerical solver failed (factorisation of a non-SPD matrix, no convergence).
class SolverError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const override { return ExitCode::Solver; }
};

// A file cannot be opened, read or written.
class IoError : public Error {
 public:
  using Error::Error;
  ExitCode exitCode() const override { return ExitCode::Io; }
};

// A file was opened but its bytes are not a valid mesh (garbage, truncated, unknown format).
class FormatError : public IoError {
 public:
  using IoError::IoError;
  ExitCode exitCode() const override { return ExitCode::Format; }
};

}  // namespace s2p
