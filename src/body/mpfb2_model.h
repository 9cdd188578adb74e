// The MPFB2 / MakeHuman body source (CC0 data; layout in ../shared/bodymodels/mpfb2/README.md).
//
// loadMpfb2 builds a BodyModel from the folder:
//  - mesh: group `body` of 3dobjs/base.obj (helpers and joint cubes dropped), quads split along
//    the shorter diagonal, boundary loops closed by a centroid fan (hm08 has none: its body
//    group is already a closed genus-0 surface), decimetres → metres, feet on y = 0;
//  - template: the base mesh plus the macrodetail targets weighted as MakeHuman 1.x does at
//    the chosen slider setting (see mpfb2MacroTargetWeights);
//  - shape space: one parameter per macro slider (central difference of the macro combination,
//    1 unit = 0.1 slider units) and one per `measure-*` decr/incr pair;
//  - skeleton: the 53 bones of rigs/standard/rig.game_engine.json, joint = bone head, with
//    helper-defined heads (joint cubes, tights) regressed onto body vertices;
//  - skinning: rigs/standard/weights.game_engine.json restricted to the body, rows normalised.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "body/body_model.h"

namespace s2p {

struct Mpfb2Options {
  // Macro setting around which the linear shape space is built (MakeHuman's slider values,
  // each in [0, 1]; 0.5 everywhere is MakeHuman's default human, gender 0.5 = neutral).
  double gender = 0.5, age = 0.5, muscle = 0.5, weight = 0.5, height = 0.5, proportions = 0.5;
  // "mixed" = African, Asian and Caucasian at 1/3 each (MakeHuman's default human), or one of
  // "african", "asian", "caucasian" at weight 1.
  std::string ethnicity = "mixed";
  bool includeMeasureTargets = true;  // add one shape parameter per measure-* target pair
};

// What the loader found and did, for reports and tests.
struct Mpfb2Report {
  int bodyVertices = 0;        // vertices of group `body` in base.obj
  int holesClosed = 0;         // boundary loops closed by a centroid fan
  int holeVertices = 0;        // vertices on those loops
  int splitVertices = 0;       // non-manifold vertices split into one copy per extra fan
  int unweightedVertices = 0;  // body vertices given their nearest weighted neighbour's weights
  int targetsRead = 0;         // morph target files parsed
  int regressedJoints = 0;     // joints whose definition uses non-body (helper) vertices
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // metres, applied after scaling
  // The joints as the rig file defines them (means of cube / helper / body vertices of the
  // full base mesh, shaped like the body), in the model's frame: what jointRegressor imitates.
  Eigen::MatrixX3d trueJoints;    // #J×3 at β = 0
  Eigen::MatrixXd trueJointDirs;  // (3#J)×#S, row 3j+k: ∂J_jk/∂β_s
};

// Throws IoError naming the file when a required file is missing, FormatError naming the file
// when one is malformed, TopologyError when the body group is not a repairable closed surface,
// InputError when an option is out of range.
BodyModel loadMpfb2(const std::filesystem::path& dir, const Mpfb2Options& options = {},
                    Mpfb2Report* report = nullptr);

// MakeHuman 1.x macro modifier weights at a slider setting: target path relative to
// targets/ without ".target.gz" (e.g. "macrodetails/universal-female-young-averagemuscle-
// averageweight", "macrodetails/height/male-young-averagemuscle-averageweight-maxheight")
// → weight; zero weights left out. Cup size and firmness stay at 0.5 (no target).
std::map<std::string, double> mpfb2MacroTargetWeights(const Mpfb2Options& setting);

// What closeTriangleMesh added: vertex numVertices + e is the mean of extra[e] (a hole's
// centroid, or a copy of a split vertex), so it follows shape, weights and regressors.
struct MeshClosure {
  int holes = 0, holeVertices = 0, splitVertices = 0;
  std::vector<std::vector<int>> extra;
};
// Makes a triangle soup over vertices [0, numVertices) a closed 2-manifold: each boundary
// loop closed by a fan around a new centroid vertex, each vertex whose faces form several fans
// split into one copy per extra fan. Throws TopologyError naming `what` for an edge used by
// more than two faces (or twice in one direction) or when the result has several components.
MeshClosure closeTriangleMesh(std::vector<Eigen::Vector3i>& tris, int numVertices,
                              const std::string& what);

}  // namespace s2p
