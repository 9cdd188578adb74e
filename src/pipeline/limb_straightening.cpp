#include "pipeline/limb_straightening.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <string>

#include "body/posing.h"
#include "pipeline/pipeline.h"

namespace s2p {

namespace {

struct StraightJoint {
  Canonical joint;
  const char* name;
};
constexpr StraightJoint kJoints[] = {{Canonical::LeftElbow, "left elbow"},
                                     {Canonical::RightElbow, "right elbow"},
                                     {Canonical::LeftKnee, "left knee"},
                                     {Canonical::RightKnee, "right knee"}};

}  // namespace

std::vector<PanelReshape> straightenLimbs(const PanelsResult& panels, const PosedFeatures& body,
                                          const LimbStraighteningOptions& options) {
  if (!body.model || panels.panels.empty()) return {};
  const BodyModel& model = *body.model;
  const int nj = model.numJoints();
  if (body.params.pose.axisAngle.rows() != nj) return {};

  // The fitted pose with every elbow and knee bent more than minBend at its rest rotation.
  BodyParams straightParams = body.params;
  std::vector<int> owner(nj, -1);  // per joint: the straightened joint it hangs from (kJoints)
  std::vector<double> bend(std::size(kJoints), 0.0);
  bool any = false;
  for (size_t k = 0; k < std::size(kJoints); ++k) {
    const int j = model.canonical[static_cast<int>(kJoints[k].joint)].joint;
    if (j < 0) continue;
    bend[k] = body.params.pose.axisAngle.row(j).norm();
    if (!(bend[k] > options.minBend)) continue;
    straightParams.pose.axisAngle.row(j).setZero();
    owner[j] = static_cast<int>(k);
    any = true;
  }
  if (!any) return {};
  for (int j = 0; j < nj; ++j)  // parents come first: the subtree of a straightened joint
    if (owner[j] < 0 && model.parents[j] >= 0) owner[j] = owner[model.parents[j]];

  const PosedBody fitted = poseBody(model, body.params);
  const PosedBody straight = poseBody(model, straightParams);

  // Every panel's vertices at once, in the parameters' frame where the body is posed.
  int total = 0;
  for (const Panel& p : panels.panels) total += p.mesh.numVertices();
  Eigen::MatrixX3d Q(total, 3);
  const Eigen::Affine3d toParams = body.toGarments.inverse();
  for (int row = 0; const Panel& p : panels.panels)
    for (int v = 0; v < p.mesh.numVertices(); ++v)
      Q.row(row++) = (toParams * p.mesh.V.row(v).transpose()).transpose();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> W = closestPointWeights(model, fitted.mesh, Q);
  const Eigen::MatrixX3d moved = poseSkinned(straight, W, unposeSkinned(fitted, W, Q));

  std::vector<PanelReshape> out(panels.panels.size());
  int row = 0;
  for (size_t pi = 0; pi < panels.panels.size(); ++pi) {
    const Panel& p = panels.panels[pi];
    std::vector<char> carries(std::size(kJoints), 0);  // this panel hangs from kJoints[k]
    Eigen::MatrixX3d V = p.mesh.V;
    bool changed = false;
    for (int v = 0; v < p.mesh.numVertices(); ++v, ++row) {
      bool affected = false;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(W, row); it; ++it)
        if (owner[it.col()] >= 0 && it.value() > 0) {
          affected = true;
          carries[owner[it.col()]] = 1;
        }
      if (!affected) continue;  // exactly as scanned
      V.row(v) = (body.toGarments * moved.row(row).transpose()).transpose();
      changed = true;
    }
    if (!changed) continue;
    PanelReshape& r = out[pi];
    r.V = std::move(V);
    std::string why;
    for (size_t k = 0; k < std::size(kJoints); ++k)
      if (carries[k])
        why += fmt::format("{}{} straightened (bent {:.0f}°)", why.empty() ? "" : ", ",
                           kJoints[k].name, bend[k] * 180 / std::numbers::pi);
    r.why = why;
    // A sleeve's grain: along the straightened arm, shoulder → wrist as panelGrain takes it.
    if (p.name.find("sleeve") != std::string::npos) {
      const bool left = p.name.rfind("left", 0) == 0;
      const auto at = [&](Canonical c) {
        return Eigen::Vector3d(straight.canonical.row(static_cast<int>(c)).transpose());
      };
      const Eigen::Vector3d axis = at(left ? Canonical::LeftShoulder : Canonical::RightShoulder) -
                                   at(left ? Canonical::LeftWrist : Canonical::RightWrist);
      if (axis.norm() > 1e-6) r.grain = (body.toGarments.linear() * axis).normalized();
    }
  }
  return out;
}

}  // namespace s2p
