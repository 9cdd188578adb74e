// Bodies built in code for the fit tests: a small mannequin posed with known parameters,
// "clothed" offsets of it and rotated copies.
#pragma once

#include "body/body_model.h"
#include "body/posing.h"
#include "core/tri_mesh.h"

namespace s2p::test {

// The mannequin with ~4000 template vertices, built once per test program.
const BodyModel& smallMannequin();

enum class TestPose { Rest, APose, TPose, Walking, BentArm };
// Known parameters: the given pose, a shape with a few non-zero measurements when `shaped`,
// translated by `translation`.
BodyParams testParams(const BodyModel& model, TestPose pose, bool shaped = false,
                      const Eigen::Vector3d& translation = Eigen::Vector3d::Zero());

// The mesh displaced along its angle-weighted vertex normals by `distance` metres.
TriMesh offsetAlongNormals(const TriMesh& mesh, double distance);

// Mean and max Euclidean distance between the rows of two canonical-joint matrices, skipping
// surface landmarks (hand and toe tips, heels, head top, nose) when `jointsOnly`.
struct JointError {
  double mean = 0, max = 0;
};
JointError canonicalJointError(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b,
                               bool jointsOnly = true);

}  // namespace s2p::test
