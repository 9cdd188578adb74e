#include "body/smpl_model.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace s2p {

namespace {

using Triplet = Eigen::Triplet<double>;

const std::vector<std::string>& bodyJointNames() {  // the 22 joints shared by the family
  static const std::vector<std::string> names = {
      "pelvis",     "left_hip",    "right_hip",    "spine1",     "left_knee",     "right_knee",
      "spine2",     "left_ankle",  "right_ankle",  "spine3",     "left_foot",     "right_foot",
      "neck",       "left_collar", "right_collar", "head",       "left_shoulder", "right_shoulder",
      "left_elbow", "right_elbow", "left_wrist",   "right_wrist"};
  return names;
}

void appendFingers(std::vector<std::string>& names, const std::string& side) {
  for (const char* finger : {"index", "middle", "pinky", "ring", "thumb"})
    for (int k = 1; k <= 3; ++k) names.push_back(side + "_" + finger + std::to_string(k));
}

const NpyArray& need(const std::map<std::string, NpyArray>& a, const std::string& key,
                     const std::string& src) {
  const auto it = a.find(key);
  if (it == a.end())
    throw FormatError(src + ": missing array '" + key +
                      "' (is this an SMPL / SMPL-H / SMPL-X model .npz?)");
  return it->second;
}

void expectShape(const NpyArray& a, const std::string& key, const std::string& src,
                 const std::vector<long>& shape) {  // −1 = any extent
  bool ok = a.shape.size() == shape.size();
  for (size_t i = 0; ok && i < shape.size(); ++i)
    ok = shape[i] < 0 || a.shape[i] == static_cast<size_t>(shape[i]);
  if (!ok) {
    std::string got = "(", want = "(";
    for (size_t i = 0; i < a.shape.size(); ++i) got += (i ? ", " : "") + std::to_string(a.shape[i]);
    for (size_t i = 0; i < shape.size(); ++i)
      want += (i ? ", " : "") + (shape[i] < 0 ? std::string("*") : std::to_string(shape[i]));
    throw FormatError(src + ": array '" + key + "' has shape " + got + "), expected " + want + ")");
  }
  for (double v : a.data)
    if (!std::isfinite(v)) throw FormatError(src + ": array '" + key + "' has non-finite values");
}

bool inSubtree(const std::vector<int>& parents, int j, int root) {
  for (int k = j; k >= 0; k = parents[k])
    if (k == root) return true;
  return false;
}

// Vertices whose largest skinning weight is on a joint of root's subtree.
std::vector<int> subtreeVertices(const BodyModel& m, const std::vector<int>& dominant, int root) {
  std::vector<int> out;
  for (int v = 0; v < m.numVertices(); ++v)
    if (dominant[v] >= 0 && inSubtree(m.parents, dominant[v], root)) out.push_back(v);
  return out;
}

// The candidate maximising score(v); FormatError when there is none.
template <class Score>
int argmax(const std::vector<int>& candidates, Score score, const std::string& what) {
  int best = -1;
  double bestScore = -std::numeric_limits<double>::infinity();
  for (int v : candidates) {
    const double s = score(v);
    if (s > bestScore) {
      bestScore = s;
      best = v;
    }
  }
  if (best < 0) throw FormatError(what + ": no skinned vertex to place the landmark on");
  return best;
}

// Hand tips, toe tips, heels, head top and nose by rule on the rest template (never by id).
void placeLandmarks(BodyModel& m, const std::string& src) {
  const Eigen::MatrixX3d& V = m.rest.V;
  std::vector<int> dominant(m.numVertices(), -1);
  for (int v = 0; v < m.numVertices(); ++v) {
    double best = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m.weights, v); it; ++it)
      if (it.value() > best) {
        best = it.value();
        dominant[v] = static_cast<int>(it.col());
      }
  }
  const Eigen::MatrixX3d J = m.jointRegressor * V;
  auto joint = [&](Canonical c) { return m.canonical[static_cast<int>(c)].joint; };
  auto set = [&](Canonical c, int v) { m.canonical[static_cast<int>(c)].vertices = {{v, 1.0}}; };
  for (int side = 0; side < 2; ++side) {
    const Canonical wristC = side ? Canonical::RightWrist : Canonical::LeftWrist;
    const Canonical elbowC = side ? Canonical::RightElbow : Canonical::LeftElbow;
    const Canonical ankleC = side ? Canonical::RightAnkle : Canonical::LeftAnkle;
    // Hand tip: farthest along the wrist → hand direction (mean of the wrist's children).
    const int w = joint(wristC);
    Eigen::Vector3d hand = Eigen::Vector3d::Zero();
    int children = 0;
    for (int j = 0; j < m.numJoints(); ++j)
      if (m.parents[j] == w) {
        hand += J.row(j).transpose();
        ++children;
      }
    const Eigen::Vector3d wrist = J.row(w).transpose();
    Eigen::Vector3d dir = children ? Eigen::Vector3d(hand / children - wrist)
                                   : Eigen::Vector3d(wrist - J.row(joint(elbowC)).transpose());
    dir.normalize();
    set(side ? Canonical::RightHandTip : Canonical::LeftHandTip,
        argmax(
            subtreeVertices(m, dominant, w),
            [&](int v) { return (V.row(v).transpose() - wrist).dot(dir); }, src));
    // Toe tip: the frontmost (+Z) foot vertex. Heel: the backmost among the lowest quarter.
    const int a = joint(ankleC);
    const std::vector<int> foot = subtreeVertices(m, dominant, a);
    set(side ? Canonical::RightToeTip : Canonical::LeftToeTip,
        argmax(
            foot, [&](int v) { return V(v, 2); }, src));
    double minY = std::numeric_limits<double>::infinity();
    for (int v : foot) minY = std::min(minY, V(v, 1));
    const double band = minY + 0.25 * (J(a, 1) - minY);
    std::vector<int> sole;
    for (int v : foot)
      if (V(v, 1) <= band) sole.push_back(v);
    set(side ? Canonical::RightHeel : Canonical::LeftHeel,
        argmax(
            sole, [&](int v) { return -V(v, 2); }, src));
  }
  // Head top: highest head vertex; nose: frontmost head vertex.
  const std::vector<int> head = subtreeVertices(m, dominant, joint(Canonical::Head));
  set(Canonical::HeadTop, argmax(
                              head, [&](int v) { return V(v, 1); }, src));
  set(Canonical::Nose, argmax(
                           head, [&](int v) { return V(v, 2); }, src));
}

}  // namespace

std::vector<std::string> smplJointNames(int numJoints) {
  std::vector<std::string> names = bodyJointNames();
  if (numJoints == 24) {
    names.insert(names.end(), {"left_hand", "right_hand"});
  } else if (numJoints == 52) {
    appendFingers(names, "left");
    appendFingers(names, "right");
  } else if (numJoints == 55) {
    names.insert(names.end(), {"jaw", "left_eye_smplhf", "right_eye_smplhf"});
    appendFingers(names, "left");
    appendFingers(names, "right");
  } else {
    throw FormatError("SMPL model with " + std::to_string(numJoints) +
                      " joints: expected 24 (SMPL), 52 (SMPL-H) or 55 (SMPL-X)");
  }
  return names;
}

BodyModel smplModelFromArrays(const std::map<std::string, NpyArray>& arrays,
                              const std::string& source) {
  const std::string src = "SMPL model '" + source + "'";
  const NpyArray& vt = need(arrays, "v_template", src);
  const NpyArray& sd = need(arrays, "shapedirs", src);
  const NpyArray& pd = need(arrays, "posedirs", src);
  const NpyArray& jr = need(arrays, "J_regressor", src);
  const NpyArray& wt = need(arrays, "weights", src);
  const NpyArray& kt = need(arrays, "kintree_table", src);
  const NpyArray& f = need(arrays, "f", src);

  expectShape(vt, "v_template", src, {-1, 3});
  const long nv = static_cast<long>(vt.shape[0]);
  if (nv == 0) throw FormatError(src + ": 'v_template' has no vertices");
  expectShape(kt, "kintree_table", src, {2, -1});
  const long nj = static_cast<long>(kt.shape[1]);
  expectShape(sd, "shapedirs", src, {nv, 3, -1});
  const long ns = static_cast<long>(sd.shape[2]);
  expectShape(pd, "posedirs", src, {nv, 3, 9 * (nj - 1)});
  expectShape(jr, "J_regressor", src, {nj, nv});
  expectShape(wt, "weights", src, {nv, nj});
  expectShape(f, "f", src, {-1, 3});

  BodyModel m;
  m.source = "smpl:" + source;
  m.jointNames = smplJointNames(static_cast<int>(nj));
  m.rest.V.resize(nv, 3);
  for (long v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) m.rest.V(v, k) = vt.data[3 * v + k];
  m.rest.F.resize(static_cast<long>(f.shape[0]), 3);
  for (long i = 0; i < m.rest.F.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double x = f.data[3 * i + k];
      if (!(x >= 0 && x < nv) || x != std::floor(x))
        throw FormatError(src + ": face " + std::to_string(i) + " of 'f' has vertex index " +
                          std::to_string(x) + " outside [0, " + std::to_string(nv) + ")");
      m.rest.F(i, k) = static_cast<int>(x);
    }

  m.parents.resize(nj);
  for (long j = 0; j < nj; ++j) {
    const double p = kt.data[j];  // first row
    if (j == 0) {
      if (p != 4294967295.0 && p != -1.0)
        throw FormatError(src + ": 'kintree_table' root parent is " + std::to_string(p) +
                          ", expected 4294967295 or -1");
      m.parents[0] = -1;
    } else {
      if (!(p >= 0 && p < j))
        throw FormatError(src + ": 'kintree_table' gives joint " + std::to_string(j) +
                          " the parent " + std::to_string(p) +
                          ": parents must precede their children");
      m.parents[j] = static_cast<int>(p);
    }
  }

  // Row 3v+k, column s of shapeDirs is shapedirs[v, k, s] (same layout for posedirs).
  m.shapeDirs =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          sd.data.data(), 3 * nv, ns);
  const long np = 9 * (nj - 1);
  m.poseDirs =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          pd.data.data(), 3 * nv, np);
  const bool extraExpressions = nj == 55 && ns == 400;  // SMPL-X: 300 shape + 100 expression
  for (long s = 0; s < ns; ++s) {
    if (extraExpressions && s >= 300)
      m.shapeParams.push_back({"expression" + std::to_string(s - 300),
                               "SMPL-X expression coefficient (PCA, unit = one standard deviation)",
                               -3, 3});
    else
      m.shapeParams.push_back({"beta" + std::to_string(s),
                               "SMPL shape coefficient (PCA, unit = one standard deviation)", -5,
                               5});
  }

  std::vector<Triplet> t;
  for (long j = 0; j < nj; ++j)
    for (long v = 0; v < nv; ++v)
      if (const double x = jr.data[j * nv + v]; x != 0) t.emplace_back(j, v, x);
  m.jointRegressor.resize(nj, nv);
  m.jointRegressor.setFromTriplets(t.begin(), t.end());

  // Skinning weights: float32 files sum to one only to ~1e-7, so rows are renormalised.
  t.clear();
  for (long v = 0; v < nv; ++v) {
    double sum = 0;
    for (long j = 0; j < nj; ++j) {
      const double x = wt.data[v * nj + j];
      if (x < 0)
        throw FormatError(src + ": 'weights' of vertex " + std::to_string(v) +
                          " has a negative entry");
      sum += x;
    }
    if (!(std::abs(sum - 1.0) < 1e-3))
      throw FormatError(src + ": 'weights' of vertex " + std::to_string(v) + " sum to " +
                        std::to_string(sum) + ", expected 1");
    for (long j = 0; j < nj; ++j)
      if (const double x = wt.data[v * nj + j]; x > 0) t.emplace_back(v, j, x / sum);
  }
  m.weights.resize(nv, nj);
  m.weights.setFromTriplets(t.begin(), t.end());

  // Canonical joints by name.
  const std::pair<Canonical, const char*> byName[] = {{Canonical::Pelvis, "pelvis"},
                                                      {Canonical::Spine, "spine1"},
                                                      {Canonical::Chest, "spine3"},
                                                      {Canonical::Neck, "neck"},
                                                      {Canonical::Head, "head"},
                                                      {Canonical::LeftClavicle, "left_collar"},
                                                      {Canonical::RightClavicle, "right_collar"},
                                                      {Canonical::LeftShoulder, "left_shoulder"},
                                                      {Canonical::RightShoulder, "right_shoulder"},
                                                      {Canonical::LeftElbow, "left_elbow"},
                                                      {Canonical::RightElbow, "right_elbow"},
                                                      {Canonical::LeftWrist, "left_wrist"},
                                                      {Canonical::RightWrist, "right_wrist"},
                                                      {Canonical::LeftHip, "left_hip"},
                                                      {Canonical::RightHip, "right_hip"},
                                                      {Canonical::LeftKnee, "left_knee"},
                                                      {Canonical::RightKnee, "right_knee"},
                                                      {Canonical::LeftAnkle, "left_ankle"},
                                                      {Canonical::RightAnkle, "right_ankle"}};
  for (const auto& [c, name] : byName) m.canonical[static_cast<int>(c)].joint = m.jointIndex(name);
  placeLandmarks(m, src);
  m.validate();
  return m;
}

BodyModel loadSmplNpz(const std::filesystem::path& path) {
  const auto arrays = readNpz(path);
  return smplModelFromArrays(arrays, path.string());
}

}  // namespace s2p
