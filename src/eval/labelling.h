// A labelling of a mesh's faces (ground truth or prediction) and its transfer onto the faces
// of the truth mesh by area, so a segmentation of the scan, of a decimated copy or of the
// exactly cut pieces (DESIGN.md "Exact cuts") can all be compared face by face with the truth.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "core/tri_mesh.h"

namespace s2p {

struct LabelledMesh {
  TriMesh mesh;
  Eigen::VectorXi faceLabel;  // #F label codes (s2p::Label, in [0, kNumLabels))
};

// Face labels from vertex labels: each face takes the label held by at least two of its
// corners; when all three differ, the smallest code. Labels out of range → InputError.
Eigen::VectorXi faceLabelsFromVertexLabels(const Eigen::MatrixX3i& F,
                                           const Eigen::VectorXi& vertexLabel);

// Reads a PLY with a face "label" property; when it has only vertex labels, faces take the
// majority vertex label (faceLabelsFromVertexLabels). Missing file → IoError; no labels at
// all, or a code outside [0, kNumLabels) → FormatError naming the file and the element; no
// faces or non-finite coordinates → InputError.
LabelledMesh readLabelledMesh(const std::filesystem::path& path);

// Throws InputError (naming `what`) unless the mesh is valid and faceLabel has #F entries,
// each a valid label code.
void validateLabelledMesh(const LabelledMesh& m, const std::string& what);

struct LabelTransferOptions {
  int subdivisionLevels = 2;     // midpoint subdivisions of a straddling predicted face: 4^levels
                                 // samples (0: the whole face goes where its centroid lands)
  double maxDistance = 0.01;     // m: a sample farther than this from the truth surface is "off"
  double maxOffFraction = 0.05;  // more predicted area than this fraction off → InputError
};

struct LabelTransfer {
  Eigen::MatrixXd area;     // #F_truth × kNumLabels: predicted area of each label in each face
  bool identity = false;    // same faces and vertices (within 1 µm); no sampling needed
  int numSamples = 0;       // closest-point queries made (centroids, sub-triangles, fallbacks)
  int unlabelledFaces = 0;  // truth faces no sample reached and no predicted face is near
  double offFraction = 0;   // fraction of predicted area whose centroid is beyond maxDistance
  double maxSampleDistance = 0;  // m, largest sample-to-truth distance
};

// The predicted labelling as label areas per truth face. Same F and V (within 1 µm): the
// identity.
// Otherwise each predicted face's centroid is located on the truth mesh by closest point
// (MeshQuery); a face whose corners all project into that truth face (a face of an exact cut,
// or of a finer mesh of the same surface) gives it its whole area; a face straddling truth
// faces is split into 4^levels sub-triangles of equal area located by their centroids. Rows
// are then scaled to the truth face's area (the prediction's label fractions of that face). A
// truth face no predicted area reaches takes the label of the predicted face closest to its
// centroid if within maxDistance, else stays unlabelled (row of zeros). A prediction not on
// the truth surface (offFraction > maxOffFraction, e.g. a segmentation of another scan) →
// InputError saying so.
LabelTransfer transferLabels(const LabelledMesh& truth, const LabelledMesh& prediction,
                             const LabelTransferOptions& options = {});

}  // namespace s2p
