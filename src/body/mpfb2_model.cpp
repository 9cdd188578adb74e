#include "body/mpfb2_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <unordered_map>

#include "body/mpfb2_files.h"
#include "core/error.h"

namespace s2p {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kFileUnit = 0.1;         // MakeHuman decimetres → metres
constexpr double kSliderStep = 0.1;       // one macro shape unit = 0.1 slider units
constexpr int kRegressorNeighbours = 4;   // nearest body vertices per cone around a joint
constexpr double kRegressorRidge = 1e-4;  // pull towards uniform weights, relative

// === MakeHuman 1.x macro factors (apps/humanmodifier.py + human.py _set*Vals)

using Factors = std::vector<std::pair<std::string, double>>;

Factors genderFactors(double g) {
  return {{"female", 1.0 - g}, {"male", g}};
}

// Age slider → baby (1 yr) at 0, child (11 yr) at 0.1875, young (25 yr) at 0.5, old (90) at 1.
Factors ageFactors(double a) {
  if (a < 0.5) {
    const double young = std::max(0.0, (a - 0.1875) / (0.5 - 0.1875));
    const double baby = std::max(0.0, 1.0 - a / 0.1875);
    const double child = std::max(0.0, std::min(1.0, a / 0.1875) - young);
    return {{"baby", baby}, {"child", child}, {"young", young}};
  }
  const double old = 2.0 * a - 1.0;
  return {{"young", 1.0 - old}, {"old", old}};
}

// min / average / max, piecewise linear with the average at 0.5 (muscle, weight).
Factors threeLevel(double x, const std::string& what) {
  if (x < 0.5) return {{"min" + what, 1.0 - 2.0 * x}, {"average" + what, 2.0 * x}};
  return {{"average" + what, 2.0 - 2.0 * x}, {"max" + what, 2.0 * x - 1.0}};
}

// Two-sided slider whose middle has no target (height, proportions).
Factors twoSided(double x, const std::string& low, const std::string& high) {
  if (x < 0.5) return {{low, 1.0 - 2.0 * x}};
  return {{high, 2.0 * x - 1.0}};
}

Factors raceFactors(const std::string& ethnicity) {
  if (ethnicity == "mixed")
    return {{"african", 1.0 / 3}, {"asian", 1.0 / 3}, {"caucasian", 1.0 / 3}};
  return {{ethnicity, 1.0}};
}

// All products of factors, names joined by '-', zero weights dropped.
void expand(const std::vector<const Factors*>& parts, const std::string& prefix,
            const std::string& suffix, std::map<std::string, double>& out) {
  std::function<void(size_t, std::string, double)> rec = [&](size_t i, std::string name, double w) {
    if (w == 0.0) return;
    if (i == parts.size()) {
      out[prefix + name + suffix] += w;
      return;
    }
    for (const auto& [n, fw] : *parts[i]) rec(i + 1, name.empty() ? n : name + "-" + n, w * fw);
  };
  rec(0, "", 1.0);
}

// Height and proportion targets MakeHuman does not ship for every combination (no baby
// proportions): a missing one counts as zero, as in MakeHuman. Others must exist.
bool optionalTarget(const std::string& name) {
  return name.rfind("macrodetails/height/", 0) == 0 ||
         name.rfind("macrodetails/proportions/", 0) == 0;
}

void checkOptions(const Mpfb2Options& o) {
  const std::pair<const char*, double> sliders[] = {
      {"gender", o.gender}, {"age", o.age},       {"muscle", o.muscle},
      {"weight", o.weight}, {"height", o.height}, {"proportions", o.proportions}};
  for (const auto& [name, v] : sliders)
    if (!(v >= 0.0 && v <= 1.0))
      throw InputError(std::string("MPFB2 options: ") + name + " = " + std::to_string(v) +
                       " is outside MakeHuman's slider range [0, 1]");
  if (o.ethnicity != "mixed" && o.ethnicity != "african" && o.ethnicity != "asian" &&
      o.ethnicity != "caucasian")
    throw InputError("MPFB2 options: ethnicity '" + o.ethnicity +
                     "' unknown (use mixed, african, asian or caucasian)");
}

double sliderValue(const Mpfb2Options& o, int s) {
  const double v[] = {o.gender, o.age, o.muscle, o.weight, o.height, o.proportions};
  return v[s];
}
double& slider(Mpfb2Options& o, int s) {
  switch (s) {
    case 0:
      return o.gender;
    case 1:
      return o.age;
    case 2:
      return o.muscle;
    case 3:
      return o.weight;
    case 4:
      return o.height;
    default:
      return o.proportions;
  }
}
const char* kSliderNames[] = {"gender", "age", "muscle", "weight", "height", "proportions"};
const char* kSliderDescriptions[] = {
    "MakeHuman gender slider, +1 = +0.1 towards male",
    "MakeHuman age slider, +1 = +0.1 (0 = 1 yr, 0.1875 = 11, 0.5 = 25, 1 = 90 yr)",
    "MakeHuman muscle slider, +1 = +0.1 towards max muscle",
    "MakeHuman weight slider, +1 = +0.1 towards max weight",
    "MakeHuman height slider, +1 = +0.1 towards max height",
    "MakeHuman proportions slider, +1 = +0.1 towards ideal proportions"};

// Checks macro.json names the sliders and levels this loader combines.
void checkMacroJson(const json& macro, const fs::path& file) {
  const std::map<std::string, std::set<std::string>> expected = {
      {"gender", {"female", "male"}},
      {"age", {"baby", "child", "young", "old"}},
      {"muscle", {"minmuscle", "averagemuscle", "maxmuscle"}},
      {"weight", {"minweight", "averageweight", "maxweight"}},
      {"height", {"minheight", "maxheight"}},
      {"proportions", {"uncommonproportions", "idealproportions"}}};
  try {
    const json& mt = macro.at("macrotargets");
    for (const auto& [name, levels] : expected) {
      std::set<std::string> found;
      for (const json& part : mt.at(name).at("parts")) {
        for (const char* k : {"low", "high"}) {
          const std::string s = part.at(k).get<std::string>();
          if (!s.empty()) found.insert(s);
        }
      }
      if (found != levels)
        throw FormatError("MPFB2 folder: " + file.string() + ": macro '" + name +
                          "' has levels this loader does not know (MakeHuman 1.x expected)");
    }
  } catch (const json::exception& e) {
    throw FormatError("MPFB2 folder: " + file.string() + " lacks the MakeHuman macro entries (" +
                      e.what() + ")");
  }
}

// Splits each polygon into triangles; quads along the shorter diagonal.
std::vector<Eigen::Vector3i> triangulate(const std::vector<const std::vector<int>*>& polys,
                                         const Eigen::MatrixX3d& V) {
  std::vector<Eigen::Vector3i> tris;
  tris.reserve(polys.size() * 2);
  for (const auto* pp : polys) {
    const auto& p = *pp;
    if (p.size() == 4) {
      const double d02 = (V.row(p[0]) - V.row(p[2])).squaredNorm();
      const double d13 = (V.row(p[1]) - V.row(p[3])).squaredNorm();
      if (d02 <= d13) {
        tris.emplace_back(p[0], p[1], p[2]);
        tris.emplace_back(p[0], p[2], p[3]);
      } else {
        tris.emplace_back(p[0], p[1], p[3]);
        tris.emplace_back(p[1], p[2], p[3]);
      }
    } else {
      for (size_t i = 1; i + 1 < p.size(); ++i) tris.emplace_back(p[0], p[i], p[i + 1]);
    }
  }
  return tris;
}

// Weights over body vertices around `p` reproducing it exactly at rest (affine constraints)
// and following its displacements `dp` (3×T, one column per training displacement field in
// `dirs`, (3#V)×T) as closely as the vertices' displacements allow (least squares, ridge
// towards uniform weights).
std::vector<std::pair<int, double>> regressPoint(const Eigen::Vector3d& p,
                                                 const Eigen::MatrixXd& dp,
                                                 const Eigen::MatrixX3d& V,
                                                 const Eigen::MatrixXd& dirs, int numBody) {
  // Vertices surrounding p: the nearest few inside each of 26 cones around p, so the
  // weights interpolate rather than extrapolate (a joint cube sits inside the body).
  const int perCone = kRegressorNeighbours;
  std::vector<Eigen::Vector3d> coneDirs;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c)
        if (a || b || c) coneDirs.push_back(Eigen::Vector3d(a, b, c).normalized());
  std::vector<std::vector<std::pair<double, int>>> inCone(coneDirs.size());
  for (int v = 0; v < numBody; ++v) {
    const Eigen::Vector3d d = V.row(v).transpose() - p;
    const double r = d.norm();
    for (size_t c = 0; c < coneDirs.size(); ++c)
      if (d.dot(coneDirs[c]) > 0.85 * r) inCone[c].emplace_back(r, v);
  }
  std::set<int> chosen;
  for (auto& cone : inCone) {
    const size_t m = std::min<size_t>(perCone, cone.size());
    std::partial_sort(cone.begin(), cone.begin() + m, cone.end());
    for (size_t i = 0; i < m; ++i) chosen.insert(cone[i].second);
  }
  std::vector<std::pair<double, int>> dist;
  for (int v : chosen) dist.emplace_back(0.0, v);
  const int k = static_cast<int>(dist.size());
  const int S = static_cast<int>(dirs.cols());
  Eigen::MatrixXd M(3 * S, k);  // column i: vec of vertex i's shape derivatives
  Eigen::VectorXd y(3 * S);
  Eigen::MatrixXd C(4, k);
  for (int i = 0; i < k; ++i) {
    const int v = dist[i].second;
    for (int s = 0; s < S; ++s)
      for (int c = 0; c < 3; ++c) M(3 * s + c, i) = dirs(3 * v + c, s);
    C.block<3, 1>(0, i) = V.row(v).transpose();
    C(3, i) = 1.0;
  }
  for (int s = 0; s < S; ++s) y.segment<3>(3 * s) = dp.col(s);
  const Eigen::MatrixXd H0 = M.transpose() * M;
  const double lambda = kRegressorRidge * H0.trace() / k + 1e-12;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(k + 4, k + 4);
  K.topLeftCorner(k, k) = H0 + lambda * Eigen::MatrixXd::Identity(k, k);
  K.topRightCorner(k, 4) = C.transpose();
  K.bottomLeftCorner(4, k) = C;
  Eigen::VectorXd rhs(k + 4);
  rhs.head(k) = M.transpose() * y + lambda * Eigen::VectorXd::Constant(k, 1.0 / k);
  rhs.tail<4>() << p, 1.0;
  const Eigen::VectorXd sol = K.fullPivLu().solve(rhs);
  std::vector<std::pair<int, double>> w;
  for (int i = 0; i < k; ++i) w.emplace_back(dist[i].second, sol[i]);
  std::sort(w.begin(), w.end());
  return w;
}

}  // namespace

namespace {
inline uint64_t edgeKey(int a, int b) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

}  // namespace

MeshClosure closeTriangleMesh(std::vector<Eigen::Vector3i>& tris, int numVertices,
                              const std::string& what) {
  MeshClosure out;
  auto& extra = out.extra;
  std::unordered_map<uint64_t, int> half;  // directed edge → count
  half.reserve(tris.size() * 4);
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) ++half[edgeKey(t[k], t[(k + 1) % 3])];
  for (const auto& [key, count] : half) {
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    if (count > 1 || (half.count(edgeKey(b, a)) && half.at(edgeKey(b, a)) > 1))
      throw TopologyError(what + ": edge (" + std::to_string(a) + ", " + std::to_string(b) +
                          ") is used by more than two faces or inconsistently oriented; the body "
                          "group cannot be closed (use the unmodified hm08 base mesh)");
  }
  // Boundary half-edges (no twin) form the holes; walk them into loops.
  std::multimap<int, int> next;
  for (const auto& [key, count] : half) {
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    if (!half.count(edgeKey(b, a))) next.emplace(a, b);
  }
  int nv = numVertices + static_cast<int>(extra.size());
  while (!next.empty()) {
    std::vector<int> loop;
    int start = next.begin()->first, cur = start;
    do {
      auto it = next.find(cur);
      if (it == next.end())
        throw TopologyError(what + ": open boundary at vertex " + std::to_string(cur) +
                            " does not form a loop");
      loop.push_back(cur);
      cur = it->second;
      next.erase(it);
    } while (cur != start);
    const int c = nv++;
    extra.push_back(loop);
    // The hole's half-edges run a→b on the boundary; the fan faces use b→a.
    for (size_t i = 0; i < loop.size(); ++i)
      tris.emplace_back(loop[(i + 1) % loop.size()], loop[i], c);
    ++out.holes;
    out.holeVertices += static_cast<int>(loop.size());
  }
  // Non-manifold vertices: more than one fan of corners around a vertex; split extra fans.
  std::unordered_map<uint64_t, int> faceOfHalf;  // directed edge → face
  faceOfHalf.reserve(tris.size() * 4);
  for (int f = 0; f < static_cast<int>(tris.size()); ++f)
    for (int k = 0; k < 3; ++k) faceOfHalf[edgeKey(tris[f][k], tris[f][(k + 1) % 3])] = f;
  std::vector<std::vector<int>> cornersOf(nv);
  for (int f = 0; f < static_cast<int>(tris.size()); ++f)
    for (int k = 0; k < 3; ++k) cornersOf[tris[f][k]].push_back(f);
  std::vector<std::pair<std::vector<int>, int>> splits;  // (faces of a fan, vertex), applied after
  for (int v = 0; v < static_cast<int>(cornersOf.size()); ++v) {
    std::set<int> remaining(cornersOf[v].begin(), cornersOf[v].end());
    bool first = true;
    while (!remaining.empty()) {
      std::vector<int> fan;
      int f = *remaining.begin();
      while (remaining.erase(f)) {  // rotate: the face across the edge (prev → v)
        fan.push_back(f);
        const auto& t = tris[f];
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        const int prev = t[(k + 2) % 3];
        f = faceOfHalf.at(edgeKey(v, prev));
      }
      if (!first) splits.emplace_back(std::move(fan), v);
      first = false;
    }
  }
  for (const auto& [fan, v] : splits) {
    const int copy = nv++;
    extra.push_back({v});
    ++out.splitVertices;
    for (int g : fan)
      for (int k = 0; k < 3; ++k)
        if (tris[g][k] == v) tris[g][k] = copy;
  }
  // One component.
  std::vector<int> parent(nv);
  for (int i = 0; i < nv; ++i) parent[i] = i;
  std::function<int(int)> find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : tris)
    for (int k = 1; k < 3; ++k) parent[find(t[k])] = find(t[0]);
  std::set<int> roots;
  for (int v = 0; v < nv; ++v) roots.insert(find(v));
  if (roots.size() != 1)
    throw TopologyError(what + ": the body group has " + std::to_string(roots.size()) +
                        " connected components (or unused vertices); one is needed");
  return out;
}

std::map<std::string, double> mpfb2MacroTargetWeights(const Mpfb2Options& o) {
  std::map<std::string, double> out;
  const Factors g = genderFactors(o.gender), a = ageFactors(o.age),
                m = threeLevel(o.muscle, "muscle"), w = threeLevel(o.weight, "weight"),
                h = twoSided(o.height, "minheight", "maxheight"),
                p = twoSided(o.proportions, "uncommonproportions", "idealproportions"),
                r = raceFactors(o.ethnicity);
  expand({&r, &g, &a}, "macrodetails/", "", out);
  expand({&g, &a, &m, &w}, "macrodetails/universal-", "", out);
  expand({&g, &a, &m, &w, &h}, "macrodetails/height/", "", out);
  expand({&g, &a, &m, &w, &p}, "macrodetails/proportions/", "", out);
  return out;
}

BodyModel loadMpfb2(const fs::path& dir, const Mpfb2Options& options, Mpfb2Report* reportOut) {
  checkOptions(options);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw IoError("MPFB2 folder " + dir.string() +
                  " does not exist or is not a directory (give the folder holding 3dobjs/, "
                  "targets/, rigs/)");
  Mpfb2Report rep;

  // === Files
  const fs::path objFile = dir / "3dobjs" / "base.obj";
  const Mpfb2Obj obj = readMpfb2Obj(objFile);
  const int nAll = static_cast<int>(obj.V.rows());
  const auto bodyIt = obj.groupVertices.find("body");
  if (bodyIt == obj.groupVertices.end())
    throw FormatError("MPFB2 folder: " + objFile.string() + " has no group 'body'");
  const int nb = static_cast<int>(bodyIt->second.size());
  if (bodyIt->second.front() != 0 || bodyIt->second.back() != nb - 1)
    throw FormatError("MPFB2 folder: " + objFile.string() +
                      ": group 'body' does not use the vertex range 0.." + std::to_string(nb - 1) +
                      " the targets and weights index");
  rep.bodyVertices = nb;
  json groupsJson;
  const fs::path groupsFile = dir / "mesh_metadata" / "basemesh_vertex_groups.json";
  if (fs::exists(groupsFile, ec)) {
    groupsJson = readJsonFile(groupsFile);
    try {
      const json& r = groupsJson.at("body");
      if (r.size() != 1 || r[0][0].get<int>() != 0 || r[0][1].get<int>() != nb - 1)
        throw FormatError("MPFB2 folder: " + groupsFile.string() +
                          ": 'body' range disagrees with " + objFile.string());
    } catch (const json::exception& e) {
      throw FormatError("MPFB2 folder: " + groupsFile.string() + ": bad 'body' entry (" + e.what() +
                        ")");
    }
  }
  const fs::path macroFile = dir / "targets" / "macrodetails" / "macro.json";
  checkMacroJson(readJsonFile(macroFile), macroFile);
  const fs::path targetIndexFile = dir / "targets" / "target.json";
  const json targetIndex = readJsonFile(targetIndexFile);
  const fs::path rigFile = dir / "rigs" / "standard" / "rig.game_engine.json";
  const json rig = readJsonFile(rigFile);
  const fs::path weightsFile = dir / "rigs" / "standard" / "weights.game_engine.json";
  const json weightsJson = readJsonFile(weightsFile);

  // === Macro combination: template and one central-difference direction per slider
  std::map<std::string, Mpfb2Target> cache;
  auto target = [&](const std::string& name) -> const Mpfb2Target* {
    auto it = cache.find(name);
    if (it != cache.end()) return &it->second;
    const fs::path file = dir / "targets" / (name + ".target.gz");
    if (optionalTarget(name) && !fs::exists(file, ec)) return nullptr;
    ++rep.targetsRead;
    return &cache.emplace(name, readMpfb2Target(file, nAll)).first->second;
  };
  auto accumulate = [&](const std::map<std::string, double>& w, double scale, auto&& col) {
    for (const auto& [name, wt] : w) {
      if (wt == 0.0) continue;
      const Mpfb2Target* t = target(name);
      if (!t) continue;
      for (size_t i = 0; i < t->index.size(); ++i)
        col.template segment<3>(3 * t->index[i]) += (scale * wt) * t->delta[i];
    }
  };
  Eigen::VectorXd X0(3 * nAll);  // full mesh at the setting, file units
  for (int v = 0; v < nAll; ++v) X0.segment<3>(3 * v) = obj.V.row(v).transpose();
  accumulate(mpfb2MacroTargetWeights(options), 1.0, X0);

  std::vector<Eigen::VectorXd> dirCols;
  std::vector<ShapeParam> params;
  for (int s = 0; s < 6; ++s) {
    Mpfb2Options lo = options, hi = options;
    slider(lo, s) = std::max(0.0, slider(lo, s) - kSliderStep);
    slider(hi, s) = std::min(1.0, slider(hi, s) + kSliderStep);
    const double scale = kSliderStep / (slider(hi, s) - slider(lo, s));
    std::map<std::string, double> diff = mpfb2MacroTargetWeights(hi);
    for (const auto& [name, wt] : mpfb2MacroTargetWeights(lo)) diff[name] -= wt;
    Eigen::VectorXd col = Eigen::VectorXd::Zero(3 * nAll);
    accumulate(diff, scale, col);
    dirCols.push_back(std::move(col));
    const double v0 = sliderValue(options, s);
    params.push_back({std::string("macro-") + kSliderNames[s], kSliderDescriptions[s],
                      -v0 / kSliderStep, (1.0 - v0) / kSliderStep});
  }

  // === measure-* targets: (incr − decr)/2 per pair, the linear fit through decr, 0, incr
  if (options.includeMeasureTargets) {
    try {
      for (const auto& [group, entry] : targetIndex.items()) {
        if (!entry.is_object() || !entry.contains("categories")) continue;
        for (const json& cat : entry.at("categories")) {
          const std::string name = cat.at("name").get<std::string>();
          if (name.rfind("measure-", 0) != 0) continue;
          const json& opp = cat.at("opposites");
          const std::string decr = opp.at("negative-unsided").get<std::string>();
          const std::string incr = opp.at("positive-unsided").get<std::string>();
          if (decr.empty() || incr.empty()) continue;
          const std::string decrName = group + "/" + decr, incrName = group + "/" + incr;
          const bool hasDecr = fs::exists(dir / "targets" / (decrName + ".target.gz"), ec);
          const bool hasIncr = fs::exists(dir / "targets" / (incrName + ".target.gz"), ec);
          if (!hasDecr && !hasIncr) continue;  // listed by MakeHuman, not in this data subset
          Eigen::VectorXd col = Eigen::VectorXd::Zero(3 * nAll);
          accumulate({{incrName, 0.5}, {decrName, -0.5}}, 1.0, col);
          dirCols.push_back(std::move(col));
          std::string pname = name;
          const std::string suffix = "-decr-incr";
          if (pname.size() > suffix.size() &&
              pname.compare(pname.size() - suffix.size(), suffix.size(), suffix) == 0)
            pname.resize(pname.size() - suffix.size());
          params.push_back({pname,
                            "MakeHuman " + pname + " modifier, +1 ≈ " + incr +
                                " at weight 1, −1 ≈ " + decr + " (linearised: (incr − decr)/2)",
                            -1.0, 1.0});
        }
      }
    } catch (const json::exception& e) {
      throw FormatError("MPFB2 folder: " + targetIndexFile.string() +
                        ": malformed target category (" + e.what() + ")");
    }
  }
  const int S = static_cast<int>(dirCols.size());

  // === Frame: metres, facing +Z, the body's left on +X, feet on y = 0
  Eigen::Vector3d axis(1, 1, 1);
  {
    double ymin = 1e300, ymax = -1e300;
    for (int v = 0; v < nb; ++v) {
      ymin = std::min(ymin, X0[3 * v + 1]);
      ymax = std::max(ymax, X0[3 * v + 1]);
    }
    const double hgt = ymax - ymin;
    double footZ = 0, ankleZ = 0;
    int nf = 0, na = 0;
    for (int v = 0; v < nb; ++v) {
      const double y = X0[3 * v + 1] - ymin;
      if (y < 0.03 * hgt)
        footZ += X0[3 * v + 2], ++nf;
      else if (y > 0.05 * hgt && y < 0.07 * hgt)
        ankleZ += X0[3 * v + 2], ++na;
    }
    if (nf && na && footZ / nf < ankleZ / na) axis = Eigen::Vector3d(-1, 1, -1);  // toes to −Z
    if (groupsJson.contains("Left")) {
      double sx = 0;
      int n = 0;
      for (const json& r : groupsJson.at("Left")) {
        for (int v = r[0].get<int>(); v <= r[1].get<int>() && v < nb; ++v)
          sx += axis.x() * X0[3 * v], ++n;
      }
      if (n && sx < 0) axis.x() = -axis.x();
    }
  }
  const bool mirrored = axis.prod() < 0;
  Eigen::MatrixX3d Xm(nAll, 3);
  for (int v = 0; v < nAll; ++v)
    Xm.row(v) = kFileUnit * axis.cwiseProduct(X0.segment<3>(3 * v)).transpose();
  Eigen::MatrixXd Dm(3 * nAll, S);
  for (int s = 0; s < S; ++s)
    for (int v = 0; v < nAll; ++v)
      Dm.block<3, 1>(3 * v, s) = kFileUnit * axis.cwiseProduct(dirCols[s].segment<3>(3 * v));
  dirCols.clear();
  // Training displacements for the joint regressor: the shape directions and every target
  // read (at 0.1 weight), so helper-defined joints follow the body across the macro space.
  Eigen::MatrixXd train(3 * nAll, S + static_cast<int>(cache.size()));
  train.leftCols(S) = Dm;
  {
    int c = S;
    for (const auto& [name, t] : cache) {
      train.col(c).setZero();
      for (size_t i = 0; i < t.index.size(); ++i)
        train.block<3, 1>(3 * t.index[i], c) =
            kFileUnit * kSliderStep * axis.cwiseProduct(t.delta[i]);
      ++c;
    }
  }
  rep.translation = Eigen::Vector3d(0, -Xm.topRows(nb).col(1).minCoeff(), 0);
  Xm.rowwise() += rep.translation.transpose();

  // === Mesh: body polygons → triangles, closed, manifold, one component
  std::vector<const std::vector<int>*> polys;
  const int bodyGroup = static_cast<int>(std::find(obj.groups.begin(), obj.groups.end(), "body") -
                                         obj.groups.begin());
  for (size_t f = 0; f < obj.faces.size(); ++f)
    if (obj.faceGroup[f] == bodyGroup) polys.push_back(&obj.faces[f]);
  std::vector<Eigen::Vector3i> tris = triangulate(polys, Xm);
  if (mirrored)
    for (auto& t : tris) std::swap(t[1], t[2]);
  MeshClosure closure = closeTriangleMesh(tris, nb, "MPFB2 " + objFile.string());
  rep.holesClosed = closure.holes;
  rep.holeVertices = closure.holeVertices;
  rep.splitVertices = closure.splitVertices;
  const std::vector<std::vector<int>>& extra = closure.extra;
  const int nv = nb + static_cast<int>(extra.size());

  BodyModel model;
  model.source = "mpfb2:" + dir.string();
  model.rest.V.resize(nv, 3);
  model.rest.V.topRows(nb) = Xm.topRows(nb);
  model.shapeDirs.resize(3 * nv, S);
  model.shapeDirs.topRows(3 * nb) = Dm.topRows(3 * nb);
  for (size_t e = 0; e < extra.size(); ++e) {
    const int v = nb + static_cast<int>(e);
    model.rest.V.row(v).setZero();
    model.shapeDirs.middleRows<3>(3 * v).setZero();
    for (int src : extra[e]) {
      model.rest.V.row(v) += model.rest.V.row(src) / extra[e].size();
      model.shapeDirs.middleRows<3>(3 * v) +=
          model.shapeDirs.middleRows<3>(3 * src) / extra[e].size();
    }
  }
  model.rest.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (size_t f = 0; f < tris.size(); ++f) model.rest.F.row(static_cast<Eigen::Index>(f)) = tris[f];
  model.shapeParams = std::move(params);

  // === Skeleton: bones in parent-first order, joint = bone head
  std::map<std::string, std::vector<std::string>> children;
  std::vector<std::string> roots;
  std::map<std::string, std::vector<int>> headIds;
  try {
    for (const auto& [name, bone] : rig.items()) {
      const std::string parent = bone.at("parent").get<std::string>();
      if (parent.empty())
        roots.push_back(name);
      else if (!rig.contains(parent))
        throw FormatError("MPFB2 folder: " + rigFile.string() + ": bone '" + name +
                          "' has unknown parent '" + parent + "'");
      else
        children[parent].push_back(name);
      const json& head = bone.at("head");
      const std::string strategy = head.at("strategy").get<std::string>();
      std::vector<int> ids;
      if (strategy == "MEAN") {
        ids = head.at("vertex_indices").get<std::vector<int>>();
      } else if (strategy == "CUBE") {
        const std::string cube = head.at("cube_name").get<std::string>();
        auto it = obj.groupVertices.find(cube);
        if (it == obj.groupVertices.end())
          throw FormatError("MPFB2 folder: " + rigFile.string() + ": bone '" + name +
                            "' uses joint cube '" + cube + "' absent from " + objFile.string());
        ids = it->second;
      } else {
        throw FormatError("MPFB2 folder: " + rigFile.string() + ": bone '" + name +
                          "' has unknown head strategy '" + strategy + "'");
      }
      if (ids.empty())
        throw FormatError("MPFB2 folder: " + rigFile.string() + ": bone '" + name +
                          "' head lists no vertices");
      for (int v : ids)
        if (v < 0 || v >= nAll)
          throw FormatError("MPFB2 folder: " + rigFile.string() + ": bone '" + name +
                            "' head vertex " + std::to_string(v) + " out of range");
      headIds[name] = ids;
    }
  } catch (const json::exception& e) {
    throw FormatError("MPFB2 folder: " + rigFile.string() + ": malformed bone (" + e.what() + ")");
  }
  if (roots.size() != 1)
    throw FormatError("MPFB2 folder: " + rigFile.string() + " has " + std::to_string(roots.size()) +
                      " root bones (one with an empty parent is needed)");
  std::vector<std::string> order{roots[0]};
  model.parents.push_back(-1);
  for (size_t i = 0; i < order.size(); ++i) {
    const std::string cur = order[i];  // copy: order grows
    for (const auto& c : children[cur]) {
      order.push_back(c);
      model.parents.push_back(static_cast<int>(i));
    }
  }
  if (order.size() != rig.size())
    throw FormatError("MPFB2 folder: " + rigFile.string() + ": bones form a cycle");
  model.jointNames = order;
  const int J = static_cast<int>(order.size());

  // Joint regressor: exact means over body vertices, regressed for helper-defined heads.
  rep.trueJoints.resize(J, 3);
  rep.trueJointDirs.resize(3 * J, S);
  std::vector<Eigen::Triplet<double>> jr;
  for (int j = 0; j < J; ++j) {
    const auto& ids = headIds[order[j]];
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Eigen::MatrixXd dp = Eigen::MatrixXd::Zero(3, train.cols());
    bool allBody = true;
    for (int v : ids) {
      p += Xm.row(v).transpose() / ids.size();
      dp += train.middleRows<3>(3 * v) / ids.size();
      allBody = allBody && v < nb;
    }
    rep.trueJoints.row(j) = p.transpose();
    rep.trueJointDirs.middleRows<3>(3 * j) = dp.leftCols(S);
    if (allBody) {
      std::map<int, double> w;
      for (int v : ids) w[v] += 1.0 / ids.size();
      for (const auto& [v, x] : w) jr.emplace_back(j, v, x);
    } else {
      ++rep.regressedJoints;
      for (const auto& [v, x] : regressPoint(p, dp, Xm, train, nb)) jr.emplace_back(j, v, x);
    }
  }
  model.jointRegressor.resize(J, nv);
  model.jointRegressor.setFromTriplets(jr.begin(), jr.end());

  // === Skinning weights
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(nv, J);  // dense while assembling
  try {
    const json& wj = weightsJson.at("weights");
    for (int j = 0; j < J; ++j) {
      if (!wj.contains(order[j])) continue;
      for (const json& pair : wj.at(order[j])) {
        const int v = pair.at(0).get<int>();
        const double x = pair.at(1).get<double>();
        if (v < 0 || v >= nAll || !std::isfinite(x) || x < 0)
          throw FormatError("MPFB2 folder: " + weightsFile.string() + ": bone '" + order[j] +
                            "' has a bad entry (vertex " + std::to_string(v) + ")");
        if (v < nb) W(v, j) += x;
      }
    }
  } catch (const json::exception& e) {
    throw FormatError("MPFB2 folder: " + weightsFile.string() + ": malformed weights (" + e.what() +
                      ")");
  }
  std::vector<int> weighted;
  for (int v = 0; v < nb; ++v)
    if (W.row(v).sum() > 0) weighted.push_back(v);
  if (weighted.empty())
    throw FormatError("MPFB2 folder: " + weightsFile.string() + " gives no body vertex a weight");
  for (int v = 0; v < nb; ++v) {
    if (W.row(v).sum() > 0) continue;
    ++rep.unweightedVertices;
    int best = weighted[0];
    for (int u : weighted)
      if ((Xm.row(u) - Xm.row(v)).squaredNorm() < (Xm.row(best) - Xm.row(v)).squaredNorm())
        best = u;
    W.row(v) = W.row(best);
  }
  for (int v = 0; v < nb; ++v) W.row(v) /= W.row(v).sum();
  for (size_t e = 0; e < extra.size(); ++e)
    for (int src : extra[e]) W.row(nb + static_cast<int>(e)) += W.row(src) / extra[e].size();
  model.weights = W.sparseView(1e-12);

  // === Canonical joints and landmarks by rule
  auto bone = [&](const char* name) {
    const int j = static_cast<int>(std::find(order.begin(), order.end(), name) - order.begin());
    if (j == J)
      throw FormatError("MPFB2 folder: " + rigFile.string() + " lacks bone '" + name +
                        "' (the game_engine rig is needed)");
    return j;
  };
  const std::pair<Canonical, const char*> jointMap[] = {{Canonical::Pelvis, "pelvis"},
                                                        {Canonical::Spine, "spine_01"},
                                                        {Canonical::Chest, "spine_03"},
                                                        {Canonical::Neck, "neck_01"},
                                                        {Canonical::Head, "head"},
                                                        {Canonical::LeftClavicle, "clavicle_l"},
                                                        {Canonical::RightClavicle, "clavicle_r"},
                                                        {Canonical::LeftShoulder, "upperarm_l"},
                                                        {Canonical::RightShoulder, "upperarm_r"},
                                                        {Canonical::LeftElbow, "lowerarm_l"},
                                                        {Canonical::RightElbow, "lowerarm_r"},
                                                        {Canonical::LeftWrist, "hand_l"},
                                                        {Canonical::RightWrist, "hand_r"},
                                                        {Canonical::LeftHip, "thigh_l"},
                                                        {Canonical::RightHip, "thigh_r"},
                                                        {Canonical::LeftKnee, "calf_l"},
                                                        {Canonical::RightKnee, "calf_r"},
                                                        {Canonical::LeftAnkle, "foot_l"},
                                                        {Canonical::RightAnkle, "foot_r"}};
  for (const auto& [c, name] : jointMap) model.canonical[static_cast<int>(c)].joint = bone(name);

  // Per-vertex weight of a joint's subtree (the body part it moves).
  auto region = [&](int root) {
    std::vector<bool> in(J, false);
    in[root] = true;
    for (int j = root + 1; j < J; ++j) in[j] = model.parents[j] >= 0 && in[model.parents[j]];
    Eigen::VectorXd r = Eigen::VectorXd::Zero(nv);
    for (int j = 0; j < J; ++j)
      if (in[j]) r += W.col(j);
    return r;
  };
  const Eigen::MatrixX3d& V = model.rest.V;
  // Mean of the region's vertices within `tol` of the maximum of score.
  auto extreme = [&](const Eigen::VectorXd& reg, const std::function<bool(int)>& keep,
                     const std::function<double(int)>& score, double tol) {
    double best = -1e300;
    for (int v = 0; v < nv; ++v)
      if (reg[v] >= 0.5 && keep(v)) best = std::max(best, score(v));
    std::vector<int> pick;
    for (int v = 0; v < nv; ++v)
      if (reg[v] >= 0.5 && keep(v) && score(v) >= best - tol) pick.push_back(v);
    CanonicalDef d;
    for (int v : pick) d.vertices.emplace_back(v, 1.0 / pick.size());
    return d;
  };
  const Eigen::MatrixX3d& TJ = rep.trueJoints;
  auto any = [](int) { return true; };
  for (int side = 0; side < 2; ++side) {
    const char* s = side == 0 ? "_l" : "_r";
    const std::string sfx(s);
    const int hand = bone(("hand" + sfx).c_str()), mid = bone(("middle_01" + sfx).c_str());
    const int foot = bone(("foot" + sfx).c_str()), ball = bone(("ball" + sfx).c_str());
    // Hand tip: farthest along wrist → middle knuckle.
    const Eigen::Vector3d hd = (TJ.row(mid) - TJ.row(hand)).normalized();
    model
        .canonical[static_cast<int>(side == 0 ? Canonical::LeftHandTip : Canonical::RightHandTip)] =
        extreme(
            region(hand), any, [&](int v) { return V.row(v).dot(hd); }, 0.003);
    // Toe tip: farthest along the horizontal ankle → ball direction.
    Eigen::Vector3d fd = TJ.row(ball) - TJ.row(foot);
    fd.y() = 0;
    fd.normalize();
    const Eigen::VectorXd footReg = region(foot);
    model.canonical[static_cast<int>(side == 0 ? Canonical::LeftToeTip : Canonical::RightToeTip)] =
        extreme(
            footReg, any, [&](int v) { return V.row(v).dot(fd); }, 0.003);
    // Heel: the rearmost of the lowest (within 1 cm) foot vertices behind the ankle.
    double footMin = 1e300;
    for (int v = 0; v < nv; ++v)
      if (footReg[v] >= 0.5) footMin = std::min(footMin, V(v, 1));
    const double ankleProj = TJ.row(foot).dot(fd);
    model.canonical[static_cast<int>(side == 0 ? Canonical::LeftHeel : Canonical::RightHeel)] =
        extreme(
            footReg,
            [&](int v) { return V(v, 1) <= footMin + 0.01 && V.row(v).dot(fd) < ankleProj; },
            [&](int v) { return -V.row(v).dot(fd); }, 0.003);
  }
  const int head = bone("head");
  const Eigen::VectorXd headReg = region(head);
  model.canonical[static_cast<int>(Canonical::HeadTop)] = extreme(
      headReg, any, [&](int v) { return V(v, 1); }, 0.003);
  model.canonical[static_cast<int>(Canonical::Nose)] = extreme(
      headReg, [&](int v) { return std::abs(V(v, 0) - TJ(head, 0)) < 0.01; },
      [&](int v) { return V(v, 2); }, 0.002);
  for (int c = 0; c < kNumCanonical; ++c)
    if (model.canonical[c].joint < 0 && model.canonical[c].vertices.empty())
      throw FormatError("MPFB2 folder " + dir.string() + ": no vertex satisfies the rule for " +
                        "canonical point '" + toString(static_cast<Canonical>(c)) + "'");
  model.validate();

  if (reportOut) *reportOut = std::move(rep);
  return model;
}

}  // namespace s2p
