// A solver's failure restated for the user (issue 17: no raw solver message reaches the user):
// which stage, on what, and what to do, with the solver's own diagnosis reduced to its kind.
#pragma once

#include <string>

#include "core/error.h"

namespace s2p {

// e.g. stageSolverError(e, "segmentation, boundary U|S", "the 30214-vertex scan (3 pieces)",
// "clean the scan"): "segmentation, boundary U|S: a linear system on the 30214-vertex scan (3
// pieces) could not be solved (its matrix is not positive definite); clean the scan".
inline SolverError stageSolverError(const SolverError& e, const std::string& stage,
                                    const std::string& on, const std::string& advice) {
  const std::string what = e.what();
  const char* kind = what.find("not positive definite") != std::string::npos
                         ? "its matrix is not positive definite"
                     : what.find("out of memory") != std::string::npos
                         ? "it ran out of memory"
                         : "the factorisation failed";
  return SolverError(stage + ": a linear system on " + on + " could not be solved (" + kind +
                     "); " + advice);
}

}  // namespace s2p
