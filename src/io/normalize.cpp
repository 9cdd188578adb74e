#include "io/normalize.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>
#include <set>

#include "core/error.h"

namespace s2p {

double metresPerUnit(Units units) {
  switch (units) {
    case Units::Millimetres:
      return 0.001;
    case Units::Centimetres:
      return 0.01;
    case Units::Decimetres:
      return 0.1;
    case Units::Metres:
      return 1.0;
    case Units::Auto:
      return 1.0;
  }
  return 1.0;
}

Eigen::Matrix3d upRotation(UpAxis up) {
  Eigen::Matrix3d R;
  switch (up) {
    case UpAxis::NegY:
      R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
      break;  // 180° about x
    case UpAxis::PosZ:
      R << 1, 0, 0, 0, 0, 1, 0, -1, 0;
      break;  // y' = z, z' = −y
    case UpAxis::NegZ:
      R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
      break;  // y' = −z, z' = y
    default:
      R.setIdentity();
  }
  return R;
}

const char* toString(Units units) {
  switch (units) {
    case Units::Auto:
      return "auto";
    case Units::Millimetres:
      return "mm";
    case Units::Centimetres:
      return "cm";
    case Units::Decimetres:
      return "dm";
    case Units::Metres:
      return "m";
  }
  return "auto";
}

const char* toString(UpAxis up) {
  switch (up) {
    case UpAxis::Auto:
      return "auto";
    case UpAxis::PosY:
      return "+y";
    case UpAxis::NegY:
      return "-y";
    case UpAxis::PosZ:
      return "+z";
    case UpAxis::NegZ:
      return "-z";
  }
  return "auto";
}

namespace {

// Heights accepted when the user forces the units (metres); detection uses 0.5–2.5 m.
constexpr double kMinForcedHeight = 0.2;
constexpr double kMaxForcedHeight = 3.0;

std::string lower(std::string_view text) {
  std::string s(text);
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}
}  // namespace

std::optional<Units> parseUnits(std::string_view text) {
  const std::string s = lower(text);
  if (s == "auto") return Units::Auto;
  if (s == "mm" || s == "millimetres" || s == "millimeters") return Units::Millimetres;
  if (s == "cm" || s == "centimetres" || s == "centimeters") return Units::Centimetres;
  if (s == "dm" || s == "decimetres" || s == "decimeters") return Units::Decimetres;
  if (s == "m" || s == "metres" || s == "meters") return Units::Metres;
  return std::nullopt;
}

std::optional<UpAxis> parseUpAxis(std::string_view text) {
  const std::string s = lower(text);
  if (s == "auto") return UpAxis::Auto;
  if (s == "+y" || s == "y") return UpAxis::PosY;
  if (s == "-y") return UpAxis::NegY;
  if (s == "+z" || s == "z") return UpAxis::PosZ;
  if (s == "-z") return UpAxis::NegZ;
  return std::nullopt;
}

namespace {

// Number of groups of faces touching a slab, joined through shared vertices.
int slabGroups(const TriMesh& mesh, const std::vector<char>& inSlab) {
  std::vector<int> parent(mesh.numVertices());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<int> used;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    if (!inSlab[f]) continue;
    const int a = find(mesh.F(f, 0));
    parent[find(mesh.F(f, 1))] = a;
    parent[find(mesh.F(f, 2))] = a;
    used.push_back(mesh.F(f, 0));
  }
  std::set<int> roots;
  for (int v : used) roots.insert(find(v));
  return static_cast<int>(roots.size());
}

// Sign vote of the up direction along `axis` (see normalize.h).
int upVote(const TriMesh& mesh, int axis, std::string& notes) {
  const Eigen::VectorXd t = mesh.V.col(axis);
  const double tmin = t.minCoeff(), tmax = t.maxCoeff(), h = tmax - tmin;
  if (!(h > 0)) return 0;
  const double band = 0.05;
  const int u = 0, w = axis == 1 ? 2 : 1;  // horizontal coordinates

  // Contact regions at each end.
  std::vector<char> low(mesh.numFaces(), 0), high(mesh.numFaces(), 0);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    double smin = 1, smax = 0;
    for (int k = 0; k < 3; ++k) {
      const double s = (t(mesh.F(f, k)) - tmin) / h;
      smin = std::min(smin, s);
      smax = std::max(smax, s);
    }
    low[f] = smin < band;
    high[f] = smax > 1 - band;
  }
  const int lowGroups = slabGroups(mesh, low), highGroups = slabGroups(mesh, high);
  int contact = 0;
  if (lowGroups >= 2 && highGroups == 1) contact = 2;
  if (highGroups >= 2 && lowGroups == 1) contact = -2;

  // Horizontal bounding box of each end slab (vertices inside it and edge crossings of its
  // inner plane, so coarse meshes count too).
  auto slabArea = [&](bool bottom) {
    const double cut = bottom ? tmin + band * h : tmax - band * h;
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
    auto add = [&](const Eigen::Vector3d& p) {
      const Eigen::Vector2d q(p[u], p[w]);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    };
    for (int f = 0; f < mesh.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d a = mesh.V.row(mesh.F(f, k)), b = mesh.V.row(mesh.F(f, (k + 1) % 3));
        const bool ina = bottom ? a[axis] <= cut : a[axis] >= cut;
        const bool inb = bottom ? b[axis] <= cut : b[axis] >= cut;
        if (ina) add(a);
        if (ina != inb) add(a + (cut - a[axis]) / (b[axis] - a[axis]) * (b - a));
      }
    if (lo[0] > hi[0]) return 0.0;
    const double eps = 0.01 * h;
    return (hi[0] - lo[0] + eps) * (hi[1] - lo[1] + eps);
  };
  const double lowArea = slabArea(true), highArea = slabArea(false);
  int width = 0;
  if (lowArea > 1.5 * highArea) width = 1;
  if (highArea > 1.5 * lowArea) width = -1;

  // Area centroid height.
  double num = 0, den = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    num += area * ((a[axis] + b[axis] + c[axis]) / 3 - tmin) / h;
    den += area;
  }
  const double centroid = den > 0 ? num / den : 0.5;
  const int centre = centroid > 0.52 ? 1 : (centroid < 0.48 ? -1 : 0);

  notes = (fmt::format(
      "up-axis cues along {}: contact groups low {} / high {} (vote {}), "
      "end areas {:.3g} / {:.3g} (vote {}), area centroid at {:.3f} of "
      "the height (vote {})",
      "xyz"[axis], lowGroups, highGroups, contact, lowArea, highArea, width, centroid, centre));
  return contact + width + centre;
}

}  // namespace

NormalizeReport normalizeScan(Scan& scan, const NormalizeOptions& options) {
  NormalizeReport report;
  const std::string what = scan.sourcePath.empty() ? std::string("scan") : scan.sourcePath;
  TriMesh& mesh = scan.mesh;
  if (mesh.numVertices() == 0) throw InputError(fmt::format("{}: the mesh has no vertices", what));
  if (!mesh.V.allFinite())
    throw InputError(fmt::format("{}: non-finite coordinates; repair or re-export the mesh", what));
  const BoundingBox box = boundingBox(mesh.V);
  const Eigen::Vector3d extent = box.extent();

  // === Up axis.
  UpAxis up = options.up;
  if (up == UpAxis::Auto) {
    report.upDetected = true;
    const int axis = extent.z() > extent.y() ? 2 : 1;
    report.upScore = upVote(mesh, axis, report.upCues);
    if (report.upScore == 0) {
      report.upAmbiguous = true;
      report.warnings.push_back(
          fmt::format("{}: the up direction is ambiguous; assuming +{} (give "
                      "--up to choose)",
                      what, "xyz"[axis]));
    }
    up = axis == 1 ? (report.upScore >= 0 ? UpAxis::PosY : UpAxis::NegY)
                   : (report.upScore >= 0 ? UpAxis::PosZ : UpAxis::NegZ);
  }
  report.up = up;
  const int axis = (up == UpAxis::PosY || up == UpAxis::NegY) ? 1 : 2;
  const double height = extent[axis];

  // === Units.
  Units units = options.units;
  if (units == Units::Auto) {
    report.unitsDetected = true;
    for (Units u : {Units::Metres, Units::Decimetres, Units::Centimetres, Units::Millimetres}) {
      const double hm = height * metresPerUnit(u);
      if (hm >= 0.5 && hm <= 2.5) {
        units = u;
        break;
      }
    }
    if (units == Units::Auto)
      throw InputError(
          fmt::format("{}: not a person: height {:.6g} in file units; give --units", what, height));
  }
  report.units = units;
  report.scale = metresPerUnit(units);
  report.heightMetres = height * report.scale;
  // Given units may stretch the range (a child, a doll-sized test scan), but not to absurdity.
  if (report.heightMetres < kMinForcedHeight || report.heightMetres > kMaxForcedHeight)
    throw InputError(fmt::format(
        "{}: not a person: {:.3g} m tall in the units given ({}); a person is 0.5–2.5 m: check "
        "--units",
        what, report.heightMetres, toString(units)));
  if (report.heightMetres < 0.5 || report.heightMetres > 2.5)
    report.warnings.push_back(fmt::format("{}: height {:.3g} m is outside 0.5–2.5 m for a person",
                                          what, report.heightMetres));

  // === p_norm = s·R·p + t: feet on y = 0, x/z centred on the lowest 5 %.
  const Eigen::Matrix3d R = upRotation(up);
  const double s = report.scale;
  Eigen::MatrixX3d P = (mesh.V * R.transpose()) * s;
  const double ymin = P.col(1).minCoeff();
  const double ycut = ymin + 0.05 * (P.col(1).maxCoeff() - ymin);
  double xlo = 1e300, xhi = -1e300, zlo = 1e300, zhi = -1e300;
  for (Eigen::Index v = 0; v < P.rows(); ++v)
    if (P(v, 1) <= ycut) {
      xlo = std::min(xlo, P(v, 0));
      xhi = std::max(xhi, P(v, 0));
      zlo = std::min(zlo, P(v, 2));
      zhi = std::max(zhi, P(v, 2));
    }
  const Eigen::RowVector3d t(-0.5 * (xlo + xhi), -ymin, -0.5 * (zlo + zhi));
  P.rowwise() += t;
  mesh.V = std::move(P);

  Eigen::Affine3d back = Eigen::Affine3d::Identity();  // p_file = Rᵀ(p − t)/s
  back.linear() = R.transpose() / s;
  back.translation() = -R.transpose() * t.transpose() / s;
  scan.toInputFrame = scan.toInputFrame * back;
  return report;
}

}  // namespace s2p
