// Helpers shared by the io tests: exact error-type checks and small meshes built in code.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <functional>
#include <string>
#include <typeinfo>

#include "core/error.h"
#include "core/shapes.h"
#include "core/tri_mesh.h"

namespace s2p::test {

// Passes when `fn` throws exactly E (not a subclass: FormatError derives from IoError).
template <typename E>
::testing::AssertionResult throwsExactly(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    if (typeid(e) == typeid(E)) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "threw " << typeid(e).name() << " instead of "
                                         << typeid(E).name() << ": " << e.what();
  }
  return ::testing::AssertionFailure() << "threw nothing";
}

// Appends b to a (vertex indices of b shifted).
inline TriMesh concat(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return m;
}

// Axis-aligned closed box, outward normals: 8 vertices, 12 faces.
inline TriMesh makeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.V.row(i) << ((i & 1) ? hi.x() : lo.x()), ((i & 2) ? hi.y() : lo.y()),
        ((i & 4) ? hi.z() : lo.z());
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3,  // z = lo
      4, 5, 6, 5, 7, 6,     // z = hi
      0, 1, 4, 1, 5, 4,     // y = lo
      2, 6, 3, 3, 6, 7,     // y = hi
      0, 4, 2, 2, 4, 6,     // x = lo
      1, 3, 5, 3, 7, 5;     // x = hi
  return m;
}

// A person-like stack in metres, +Y up, facing +Z: two feet blocks pointing forward, legs,
// torso, arms and a head sphere. Height 1.69 m; the lowest 5 % (feet and leg ends) spans
// x ∈ [−0.2, 0.2], z ∈ [−0.05, 0.2].
inline TriMesh makePerson() {
  using V3 = Eigen::Vector3d;
  TriMesh m = makeBox(V3(-0.2, 0, -0.05), V3(-0.05, 0.08, 0.2));          // left foot
  m = concat(m, makeBox(V3(0.05, 0, -0.05), V3(0.2, 0.08, 0.2)));         // right foot
  m = concat(m, makeBox(V3(-0.17, 0.08, -0.05), V3(-0.08, 0.85, 0.05)));  // legs
  m = concat(m, makeBox(V3(0.08, 0.08, -0.05), V3(0.17, 0.85, 0.05)));
  m = concat(m, makeBox(V3(-0.2, 0.85, -0.12), V3(0.2, 1.45, 0.12)));  // torso
  m = concat(m, makeBox(V3(-0.3, 0.8, -0.05), V3(-0.2, 1.45, 0.05)));  // arms
  m = concat(m, makeBox(V3(0.2, 0.8, -0.05), V3(0.3, 1.45, 0.05)));
  TriMesh head = makeIcosphere(2, 0.11);
  head.V.col(1).array() += 1.58;
  return concat(m, head);
}

}  // namespace s2p::test
