#include "eval/labelling.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/mesh_query.h"
#include "core/surface_point.h"
#include "io/read_ply.h"
#include "synth/truth.h"

namespace s2p {
namespace {

// Centroids (#S×3) and areas (#S) of the 4^levels midpoint sub-triangles of every face, and the
// face each comes from.
struct Samples {
  Eigen::MatrixX3d point;
  Eigen::VectorXd weight;
  std::vector<int> face;
};

void subdivide(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
               int levels, double area, int face, Samples& s, Eigen::Index& row) {
  if (levels == 0) {
    s.point.row(row) = (a + b + c) / 3.0;
    s.weight(row) = area;
    s.face[static_cast<std::size_t>(row)] = face;
    ++row;
    return;
  }
  const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  subdivide(a, ab, ca, levels - 1, area / 4, face, s, row);
  subdivide(ab, b, bc, levels - 1, area / 4, face, s, row);
  subdivide(ca, bc, c, levels - 1, area / 4, face, s, row);
  subdivide(ab, bc, ca, levels - 1, area / 4, face, s, row);
}

Samples sampleFaces(const TriMesh& m, const std::vector<int>& faces, int levels) {
  const Eigen::VectorXd area = faceAreas(m);
  const Eigen::Index per = Eigen::Index{1} << (2 * levels);
  const auto n = static_cast<Eigen::Index>(faces.size()) * per;
  Samples s;
  s.point.resize(n, 3);
  s.weight.resize(n);
  s.face.resize(static_cast<std::size_t>(n));
  Eigen::Index row = 0;
  for (int f : faces)
    subdivide(m.V.row(m.F(f, 0)).transpose(), m.V.row(m.F(f, 1)).transpose(),
              m.V.row(m.F(f, 2)).transpose(), levels, area(f), f, s, row);
  return s;
}

}  // namespace

Eigen::VectorXi faceLabelsFromVertexLabels(const Eigen::MatrixX3i& F,
                                           const Eigen::VectorXi& vertexLabel) {
  Eigen::VectorXi out(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    std::array<int, 3> l{};
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      if (v < 0 || v >= vertexLabel.size())
        throw InputError(fmt::format("face {} refers to vertex {} which has no label ({} labels)",
                                     f, v, vertexLabel.size()));
      l[static_cast<std::size_t>(k)] = vertexLabel(v);
      if (!isValidLabel(l[static_cast<std::size_t>(k)]))
        throw InputError(fmt::format("vertex {} has label {}, not a label code in [0, {})", v,
                                     vertexLabel(v), kNumLabels));
    }
    if (l[0] == l[1] || l[0] == l[2])
      out(f) = l[0];
    else if (l[1] == l[2])
      out(f) = l[1];
    else
      out(f) = std::min({l[0], l[1], l[2]});
  }
  return out;
}

void validateLabelledMesh(const LabelledMesh& m, const std::string& what) {
  validateMesh(m.mesh, what);
  if (m.faceLabel.size() != m.mesh.numFaces())
    throw InputError(fmt::format("{}: {} face labels for {} faces; give one label per face", what,
                                 m.faceLabel.size(), m.mesh.numFaces()));
  for (Eigen::Index f = 0; f < m.faceLabel.size(); ++f)
    if (!isValidLabel(m.faceLabel(f)))
      throw InputError(fmt::format("{}: face {} has label {}, not a label code in [0, {})", what, f,
                                   m.faceLabel(f), kNumLabels));
}

LabelledMesh readLabelledMesh(const std::filesystem::path& path) {
  PlyData ply = readPly(path);
  LabelledMesh out;
  out.mesh = std::move(ply.mesh);
  validateMesh(out.mesh, path.string());
  if (ply.faceLabels.size() == out.mesh.numFaces()) {
    out.faceLabel = std::move(ply.faceLabels);
  } else if (ply.labels.size() == out.mesh.numVertices()) {
    try {
      out.faceLabel = faceLabelsFromVertexLabels(out.mesh.F, ply.labels);
    } catch (const InputError& e) {
      throw FormatError(fmt::format("{}: {}", path.string(), e.what()));
    }
  } else {
    throw FormatError(fmt::format(
        "{} has no face or vertex \"label\" property; write the segmentation with labels "
        "(codes 0 skin, 1 upper, 2 lower, 3 shoes, 4 hair, 5 other, 6 gap)",
        path.string()));
  }
  for (Eigen::Index f = 0; f < out.faceLabel.size(); ++f)
    if (!isValidLabel(out.faceLabel(f)))
      throw FormatError(fmt::format("{}: face {} has label {}, not a label code in [0, {})",
                                    path.string(), f, out.faceLabel(f), kNumLabels));
  return out;
}

LabelTransfer transferLabels(const LabelledMesh& truth, const LabelledMesh& pred,
                             const LabelTransferOptions& opt) {
  validateLabelledMesh(truth, "the truth mesh");
  validateLabelledMesh(pred, "the predicted mesh");
  if (opt.subdivisionLevels < 0 || opt.subdivisionLevels > 5)
    throw InputError(fmt::format("label transfer: subdivisionLevels {} is outside [0, 5]",
                                 opt.subdivisionLevels));
  const int nF = truth.mesh.numFaces();
  const Eigen::VectorXd truthArea = faceAreas(truth.mesh);
  LabelTransfer out;
  out.area = Eigen::MatrixXd::Zero(nF, kNumLabels);

  // Same faces and vertices (up to 1 µm, so a copy stored in single precision counts too).
  if (truth.mesh.V.rows() == pred.mesh.V.rows() && truth.mesh.F.rows() == pred.mesh.F.rows() &&
      truth.mesh.F == pred.mesh.F && (truth.mesh.V - pred.mesh.V).cwiseAbs().maxCoeff() <= 1e-6) {
    out.identity = true;
    for (int f = 0; f < nF; ++f) out.area(f, pred.faceLabel(f)) = truthArea(f);
    return out;
  }

  // Pass 1: one closest-point query per predicted face centroid; a prediction far from the
  // truth is refused here. A face whose corners all project into the truth face under its
  // centroid lies in that face (exact cuts: every cut face lies in one scan face) and gives it
  // its whole area.
  const MeshQuery truthQuery(truth.mesh);
  const Eigen::VectorXd predArea = faceAreas(pred.mesh);
  std::vector<int> all(static_cast<std::size_t>(pred.mesh.numFaces()));
  for (int f = 0; f < pred.mesh.numFaces(); ++f) all[static_cast<std::size_t>(f)] = f;
  const std::vector<ClosestHit> centre =
      truthQuery.closestPoints(sampleFaces(pred.mesh, all, 0).point);
  out.numSamples = static_cast<int>(centre.size());
  double total = 0, off = 0;
  std::vector<int> straddling;
  for (int f = 0; f < pred.mesh.numFaces(); ++f) {
    const ClosestHit& hit = centre[static_cast<std::size_t>(f)];
    total += predArea(f);
    out.maxSampleDistance = std::max(out.maxSampleDistance, hit.distance);
    if (hit.distance > opt.maxDistance) {
      off += predArea(f);
      continue;
    }
    const Eigen::Vector3d a = truth.mesh.V.row(truth.mesh.F(hit.face, 0));
    const Eigen::Vector3d b = truth.mesh.V.row(truth.mesh.F(hit.face, 1));
    const Eigen::Vector3d c = truth.mesh.V.row(truth.mesh.F(hit.face, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    bool inside = n.allFinite();
    for (int k = 0; k < 3 && inside; ++k) {
      const Eigen::Vector3d p = pred.mesh.V.row(pred.mesh.F(f, k));
      inside = planeBarycentric(p, a, b, c).minCoeff() >= -1e-6 &&
               std::abs((p - a).dot(n)) <= opt.maxDistance;
    }
    if (inside || opt.subdivisionLevels == 0)
      out.area(hit.face, pred.faceLabel(f)) += predArea(f);
    else
      straddling.push_back(f);
  }
  out.offFraction = total > 0 ? off / total : 1.0;
  if (out.offFraction > opt.maxOffFraction)
    throw InputError(fmt::format(
        "the prediction does not lie on the truth's surface: {:.1f}% of its area is farther "
        "than {:.1f} mm from it (up to {:.1f} mm); is it a segmentation of another scan, or in "
        "other units or another frame?",
        100 * out.offFraction, 1e3 * opt.maxDistance, 1e3 * out.maxSampleDistance));

  // Pass 2: faces straddling truth faces are split into 4^levels sub-triangles, each located
  // by its centroid and carrying its share of the area.
  constexpr std::size_t kChunk = 1 << 16;  // faces per batch: bounds the samples held at once
  for (std::size_t begin = 0; begin < straddling.size(); begin += kChunk) {
    const std::vector<int> batch(straddling.begin() + static_cast<std::ptrdiff_t>(begin),
                                 straddling.begin() + static_cast<std::ptrdiff_t>(std::min(
                                                          begin + kChunk, straddling.size())));
    const Samples s = sampleFaces(pred.mesh, batch, opt.subdivisionLevels);
    const std::vector<ClosestHit> hits = truthQuery.closestPoints(s.point);
    out.numSamples += static_cast<int>(hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
      out.maxSampleDistance = std::max(out.maxSampleDistance, hits[i].distance);
      if (hits[i].distance <= opt.maxDistance)
        out.area(hits[i].face, pred.faceLabel(s.face[i])) += s.weight(static_cast<Eigen::Index>(i));
    }
  }

  // Rows → fractions of each truth face; faces no sample reached ask the prediction directly.
  std::vector<int> missed;
  for (int f = 0; f < nF; ++f) {
    const double sum = out.area.row(f).sum();
    if (sum > 0)
      out.area.row(f) *= truthArea(f) / sum;
    else if (truthArea(f) > 0)
      missed.push_back(f);
  }
  if (!missed.empty()) {
    const MeshQuery predQuery(pred.mesh);
    Eigen::MatrixX3d centroid(static_cast<Eigen::Index>(missed.size()), 3);
    for (std::size_t i = 0; i < missed.size(); ++i) {
      const int f = missed[i];
      centroid.row(static_cast<Eigen::Index>(i)) =
          (truth.mesh.V.row(truth.mesh.F(f, 0)) + truth.mesh.V.row(truth.mesh.F(f, 1)) +
           truth.mesh.V.row(truth.mesh.F(f, 2))) /
          3.0;
    }
    const std::vector<ClosestHit> back = predQuery.closestPoints(centroid);
    out.numSamples += static_cast<int>(back.size());
    for (std::size_t i = 0; i < missed.size(); ++i) {
      if (back[i].distance > opt.maxDistance) {
        ++out.unlabelledFaces;
        continue;
      }
      out.area(missed[i], pred.faceLabel(back[i].face)) = truthArea(missed[i]);
    }
  }
  return out;
}

}  // namespace s2p
