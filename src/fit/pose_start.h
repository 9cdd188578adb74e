// Several starts for the body fit (issue 17): a relaxed stance (arms hanging against the thighs)
// defeats the geometric pose initialisation, whose five extremities then merge or land on the
// wrong limb. gatedFit runs a short fit from each start — the geometric initialisation, the arms
// down, the rest pose — scores each by the two-sided distance between the fitted body and the
// scan, and finishes the best with the full fit.
#pragma once

#include <string>
#include <vector>

#include "body/body_model.h"
#include "core/tri_mesh.h"
#include "fit/body_fit.h"
#include "fit/pose_init.h"

namespace s2p {

// Metres: the mean of the scan → body and body → scan closest-point distances (each the mean
// over the vertices of one mesh of the distance to the other's surface).
double twoSidedDistance(const TriMesh& body, const TriMesh& scan);

struct GatedFitOptions {
  // The short fit run from every start (BodyFitOptions' cycles, finalSteps, maxIterations and
  // maxFitVertices): one translation → shape → pose cycle on 1000 vertices, about 0.5 s a start
  // on the mannequin, enough to tell an arm drawn into the torso from one on the scan's arm.
  int shortCycles = 1;
  int shortFinalSteps = 0;
  int shortMaxIterations = 10;
  int shortFitVertices = 1000;
  // Metres: another start replaces the geometric one only when its score is lower by more than
  // this, so that a scan the geometric initialisation reads well keeps its fit.
  double geometryMargin = 0.002;
};

struct StartScore {
  std::string name;  // "geometry", "arms down", "rest"
  double score = 0;  // twoSidedDistance after the short fit, metres
};

struct GatedFitResult {
  BodyFitResult fit;                  // the full fit from the chosen start
  std::string start;                  // the chosen start's name
  double score = 0;                   // its score, metres
  std::vector<StartScore> scores;     // every start tried, in order
  std::vector<std::string> warnings;  // e.g. why the geometric initialisation was not tried
};

// input.initial is ignored: the starts are made from input.scan. Throws as runBodyFit.
GatedFitResult gatedFit(const BodyFitInput& input, const PoseInitOptions& poseInit = {},
                        const BodyFitOptions& fit = {}, const GatedFitOptions& options = {});

}  // namespace s2p
