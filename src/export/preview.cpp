#include "export/preview.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.h"
#include "export/bitmap_text.h"

namespace s2p {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kBandRows = 16;                 // sample rows per parallel task
constexpr long long kMaxSamples = 1LL << 26;  // per view: ~1.3 GB of buffers at most
// Lighting in camera space (x right, y up, z towards the camera). The key light sits above the
// camera so that a symmetric object renders symmetric.
constexpr float kAmbient = 0.25f;
constexpr float kKey = 0.55f;
constexpr float kHead = 0.25f;  // soft headlight along the view direction
const Eigen::Vector3f kKeyLight = Eigen::Vector3f(0.0f, 0.5f, 1.0f).normalized();
// Barycentric tolerance so that samples on a shared edge are never missed by both triangles.
constexpr double kEdgeEps = 1e-7;

Eigen::Vector3f toUnit(Rgb c) {
  return Eigen::Vector3f(c.r, c.g, c.b) / 255.0f;
}

std::uint8_t toByte(float v) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

bool allFinite(const Eigen::MatrixX3d& M) {
  return M.allFinite();
}

// === Framing

// One view's camera: world → supersampled image coordinates (x right, y down, depth in metres
// from the camera plane, smaller is nearer).
struct ViewFrame {
  Eigen::Matrix3d R;
  Eigen::Vector2d centre;  // camera-space point at the image centre
  double k = 1;            // samples per metre
  int w = 0, h = 0;        // supersampled size

  Eigen::Vector3f project(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d c = R * p;
    return {static_cast<float>((c.x() - centre.x()) * k + 0.5 * w),
            static_cast<float>(0.5 * h - (c.y() - centre.y()) * k), static_cast<float>(-c.z())};
  }
};

struct Extent2 {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity());
  bool empty() const { return !(lo.x() <= hi.x()); }
  void add(const Eigen::Vector2d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void add(const Extent2& o) {
    if (o.empty()) return;
    add(o.lo);
    add(o.hi);
  }
};

Extent2 cameraExtent(const Eigen::Matrix3d& R, const Eigen::MatrixX3d& P) {
  const Eigen::Matrix<double, Eigen::Dynamic, 2> C = P * R.topRows<2>().transpose();  // #P×2
  Extent2 e;
  if (C.rows() == 0) return e;
  e.lo = C.colwise().minCoeff().transpose();
  e.hi = C.colwise().maxCoeff().transpose();
  return e;
}

Extent2 sceneExtent(const Scene& scene, const Eigen::Matrix3d& R) {
  Extent2 e;
  for (const SceneMesh& m : scene.meshes)
    if (m.mesh->numFaces() > 0) e.add(cameraExtent(R, m.mesh->V));
  for (const Polyline& l : scene.lines) e.add(cameraExtent(R, l.points));
  for (const PointSet& p : scene.points) e.add(cameraExtent(R, p.points));
  return e;
}

// === Validation

void validateScene(const Scene& scene, const RenderOptions& o) {
  if (o.views.empty()) throw InputError("renderScene: no view requested; add at least one view");
  if (o.heightPx < 8 || o.heightPx > 16384)
    throw InputError("renderScene: heightPx = " + std::to_string(o.heightPx) +
                     " is out of range; use 8 to 16384");
  if (o.supersample < 1 || o.supersample > 8)
    throw InputError("renderScene: supersample = " + std::to_string(o.supersample) +
                     " is out of range; use 1 to 8");
  if (!(o.margin >= 0 && o.margin <= 0.45))
    throw InputError("renderScene: margin = " + std::to_string(o.margin) +
                     " is out of range; use 0 to 0.45 (fraction of the height)");
  if (o.gapPx < 0 || o.gapPx > 4096)
    throw InputError("renderScene: gapPx = " + std::to_string(o.gapPx) + "; use 0 to 4096");
  if (o.maxViewWidthPx < 0 || o.maxViewWidthPx > 65536)
    throw InputError("renderScene: maxViewWidthPx = " + std::to_string(o.maxViewWidthPx) +
                     "; use 0 (automatic) to 65536");
  if (!(o.overlayDepthBias >= 0 && o.overlayDepthBias <= 1))
    throw InputError("renderScene: overlayDepthBias must be in [0, 1]");
  if (!o.captions.empty() && o.captions.size() != o.views.size())
    throw InputError("renderScene: " + std::to_string(o.captions.size()) + " captions for " +
                     std::to_string(o.views.size()) + " views; give one per view or none");
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    const SceneMesh& m = scene.meshes[i];
    const std::string name = "renderScene: mesh " + std::to_string(i);
    if (m.mesh == nullptr) throw InputError(name + " is a null pointer");
    if (m.mesh->numFaces() > 0) validateMesh(*m.mesh, name);
    if (m.colour != nullptr) {
      if (m.colour->rows() != m.mesh->V.rows())
        throw InputError(name + " has " + std::to_string(m.colour->rows()) + " colour rows for " +
                         std::to_string(m.mesh->V.rows()) +
                         " vertices; pass one sRGB row per vertex or no colour");
      if (!allFinite(*m.colour)) throw InputError(name + " has non-finite vertex colours");
    }
    if (!(m.opacity >= 0.0f && m.opacity <= 1.0f))
      throw InputError(name + " has opacity " + std::to_string(m.opacity) + "; use 0 to 1");
  }
  for (std::size_t i = 0; i < scene.lines.size(); ++i) {
    const Polyline& l = scene.lines[i];
    if (!allFinite(l.points))
      throw InputError("renderScene: polyline " + std::to_string(i) + " has non-finite points");
    if (!(l.widthPx > 0 && l.widthPx <= 64))
      throw InputError("renderScene: polyline " + std::to_string(i) + " has width " +
                       std::to_string(l.widthPx) + " px; use (0, 64]");
  }
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    const PointSet& p = scene.points[i];
    if (!allFinite(p.points))
      throw InputError("renderScene: point set " + std::to_string(i) + " has non-finite points");
    if (!(p.radiusPx > 0 && p.radiusPx <= 64))
      throw InputError("renderScene: point set " + std::to_string(i) + " has radius " +
                       std::to_string(p.radiusPx) + " px; use (0, 64]");
  }
}

// === Rasterisation

// One view's supersampled buffers.
struct Target {
  int w = 0, h = 0;
  std::vector<float> depth;             // w·h, opaque surfaces; +inf where empty
  std::vector<float> overlay;           // w·h, nearest depth-tested curve or point; +inf: none
  std::vector<Eigen::Vector3f> colour;  // w·h, sRGB in [0, 1]

  Target(int width, int height, const Eigen::Vector3f& background)
      : w(width),
        h(height),
        depth(std::size_t(width) * height, kInf),
        overlay(std::size_t(width) * height, kInf),
        colour(std::size_t(width) * height, background) {}
};

// Calls frag(x, y, ba, bb, bc) for every sample centre (x + ½, y + ½) inside triangle abc with
// rows in [rowBegin, rowEnd); ba, bb, bc are its barycentric coordinates.
template <class Fragment>
void rasteriseTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                       int width, int rowBegin, int rowEnd, Fragment&& frag) {
  const double area = (double(b.x()) - a.x()) * (double(c.y()) - a.y()) -
                      (double(b.y()) - a.y()) * (double(c.x()) - a.x());
  if (!(std::abs(area) > 1e-12)) return;
  const double minX = std::min({a.x(), b.x(), c.x()}), maxX = std::max({a.x(), b.x(), c.x()});
  const double minY = std::min({a.y(), b.y(), c.y()}), maxY = std::max({a.y(), b.y(), c.y()});
  const int x0 = static_cast<int>(std::max(0.0, std::ceil(minX - 0.5)));
  const int x1 = static_cast<int>(std::min(width - 1.0, std::floor(maxX - 0.5)));
  const int y0 = static_cast<int>(std::max<double>(rowBegin, std::ceil(minY - 0.5)));
  const int y1 = static_cast<int>(std::min<double>(rowEnd - 1, std::floor(maxY - 0.5)));
  if (x0 > x1 || y0 > y1) return;
  // ba(p) = cross(c - b, p - b) / area, linear in p: ba = ax·x + ay·y + a0 (same for bb).
  const double inv = 1.0 / area;
  const double aax = -(double(c.y()) - b.y()) * inv, aay = (double(c.x()) - b.x()) * inv;
  const double aa0 = -(aax * b.x() + aay * b.y());
  const double bax = -(double(a.y()) - c.y()) * inv, bay = (double(a.x()) - c.x()) * inv;
  const double ba0 = -(bax * c.x() + bay * c.y());
  for (int y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5;
      const double wa = aax * px + aay * py + aa0;
      const double wb = bax * px + bay * py + ba0;
      const double wc = 1.0 - wa - wb;
      if (wa < -kEdgeEps || wb < -kEdgeEps || wc < -kEdgeEps) continue;
      frag(x, y, static_cast<float>(wa), static_cast<float>(wb), static_cast<float>(wc));
    }
  }
}

// A mesh transformed into one view.
struct ProjectedMesh {
  const Eigen::MatrixX3i* F = nullptr;
  std::vector<Eigen::Vector3f> p;       // #V: sample x, sample y, depth
  std::vector<Eigen::Vector3f> normal;  // #V (smooth) or #F (flat), camera space
  std::vector<Eigen::Vector3f> albedo;  // #V, or empty for a flat colour
  Eigen::Vector3f flat;
  bool smooth = true;
};

// Area-weighted vertex normals (#V×3, unnormalised sums are fine: shading normalises).
Eigen::MatrixX3d areaWeightedNormals(const TriMesh& mesh) {
  Eigen::MatrixX3d N = Eigen::MatrixX3d::Zero(mesh.numVertices(), 3);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) N.row(mesh.F(f, k)) += n;
  }
  return N;
}

// World-space normals and colours of a mesh, computed once for all views.
struct PreparedMesh {
  const SceneMesh* source = nullptr;
  Eigen::MatrixX3d normal;  // #V×3 (smooth) or #F×3 (flat)
};

ProjectedMesh projectMesh(const PreparedMesh& pm, const ViewFrame& frame) {
  const SceneMesh& sm = *pm.source;
  const TriMesh& mesh = *sm.mesh;
  ProjectedMesh out;
  out.F = &mesh.F;
  out.smooth = sm.smooth;
  out.flat = toUnit(sm.flatColour);
  out.p.resize(mesh.V.rows());
  out.normal.resize(pm.normal.rows());
  if (sm.colour != nullptr) out.albedo.resize(mesh.V.rows());
  const Eigen::Matrix3f Rf = frame.R.cast<float>();
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, mesh.V.rows(), 4096), [&](auto r) {
    for (Eigen::Index v = r.begin(); v != r.end(); ++v) {
      out.p[v] = frame.project(mesh.V.row(v).transpose());
      if (sm.colour != nullptr)
        out.albedo[v] = sm.colour->row(v).transpose().cast<float>().cwiseMax(0.0f).cwiseMin(1.0f);
    }
  });
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, pm.normal.rows(), 4096), [&](auto r) {
    for (Eigen::Index i = r.begin(); i != r.end(); ++i)
      out.normal[i] = Rf * pm.normal.row(i).transpose().cast<float>();
  });
  return out;
}

Eigen::Vector3f shade(Eigen::Vector3f n, bool backFacing, const Eigen::Vector3f& albedo) {
  const float len = n.norm();
  n = len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f(0, 0, 1);
  if (backFacing) n = -n;  // the inside of an open surface is lit like its outside
  const float intensity =
      kAmbient + kKey * std::max(0.0f, n.dot(kKeyLight)) + kHead * std::max(0.0f, n.z());
  return (albedo * intensity).cwiseMin(1.0f);
}

// Triangles of a projected mesh sorted into bands of kBandRows sample rows (CSR layout), so
// that bands can be drawn in parallel, each triangle in index order (deterministic).
struct Bins {
  std::vector<int> start;  // #bands+1
  std::vector<int> tris;
};

Bins binTriangles(const ProjectedMesh& pm, int w, int h) {
  const Eigen::MatrixX3i& F = *pm.F;
  const int nBands = (h + kBandRows - 1) / kBandRows;
  const Eigen::Index nF = F.rows();
  std::vector<std::array<int, 2>> range(nF);  // first and last band, or {1, 0}: none
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nF, 8192), [&](auto r) {
    for (Eigen::Index f = r.begin(); f != r.end(); ++f) {
      const Eigen::Vector3f& a = pm.p[F(f, 0)];
      const Eigen::Vector3f& b = pm.p[F(f, 1)];
      const Eigen::Vector3f& c = pm.p[F(f, 2)];
      const double minX = std::min({a.x(), b.x(), c.x()}), maxX = std::max({a.x(), b.x(), c.x()});
      const double minY = std::min({a.y(), b.y(), c.y()}), maxY = std::max({a.y(), b.y(), c.y()});
      const double x0 = std::max(0.0, std::ceil(minX - 0.5));
      const double x1 = std::min(w - 1.0, std::floor(maxX - 0.5));
      const double y0 = std::max(0.0, std::ceil(minY - 0.5));
      const double y1 = std::min(h - 1.0, std::floor(maxY - 0.5));
      if (x0 > x1 || y0 > y1) {
        range[f] = {1, 0};  // covers no sample centre
        continue;
      }
      range[f] = {static_cast<int>(y0) / kBandRows, static_cast<int>(y1) / kBandRows};
    }
  });
  Bins bins;
  bins.start.assign(nBands + 1, 0);
  for (const auto& r : range)
    for (int b = r[0]; b <= r[1]; ++b) ++bins.start[b + 1];
  for (int b = 0; b < nBands; ++b) bins.start[b + 1] += bins.start[b];
  bins.tris.resize(bins.start[nBands]);
  std::vector<int> fill(bins.start.begin(), bins.start.end() - 1);
  for (Eigen::Index f = 0; f < nF; ++f)
    for (int b = range[f][0]; b <= range[f][1]; ++b) bins.tris[fill[b]++] = static_cast<int>(f);
  return bins;
}

// Draws every triangle of `pm`, band by band in parallel; frag(i, z, colour-thunk) decides.
template <class Fragment>
void drawMesh(const ProjectedMesh& pm, int w, int h, Fragment&& frag) {
  const Bins bins = binTriangles(pm, w, h);
  const Eigen::MatrixX3i& F = *pm.F;
  const int nBands = static_cast<int>(bins.start.size()) - 1;
  tbb::parallel_for(tbb::blocked_range<int>(0, nBands, 1), [&](auto r) {
    for (int band = r.begin(); band != r.end(); ++band) {
      const int rowBegin = band * kBandRows, rowEnd = std::min(h, rowBegin + kBandRows);
      // Front faces first: on closed surfaces the back faces then mostly fail the depth test
      // before being shaded.
      for (int pass = 0; pass < 2; ++pass)
        for (int t = bins.start[band]; t < bins.start[band + 1]; ++t) {
          const int f = bins.tris[t];
          const int ia = F(f, 0), ib = F(f, 1), ic = F(f, 2);
          const Eigen::Vector3f &a = pm.p[ia], &b = pm.p[ib], &c = pm.p[ic];
          // Counter-clockwise in camera space (y up) is clockwise in sample space (y down).
          const bool backFacing =
              (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x()) > 0;
          if (backFacing != (pass == 1)) continue;
          rasteriseTriangle(
              a, b, c, w, rowBegin, rowEnd, [&](int x, int y, float wa, float wb, float wc) {
                const std::size_t i = std::size_t(y) * w + x;
                const float z = wa * a.z() + wb * b.z() + wc * c.z();
                frag(i, z, [&]() {
                  const Eigen::Vector3f n =
                      pm.smooth ? Eigen::Vector3f(wa * pm.normal[ia] + wb * pm.normal[ib] +
                                                  wc * pm.normal[ic])
                                : pm.normal[f];
                  const Eigen::Vector3f albedo =
                      pm.albedo.empty() ? pm.flat
                                        : Eigen::Vector3f(wa * pm.albedo[ia] + wb * pm.albedo[ib] +
                                                          wc * pm.albedo[ic]);
                  return shade(n, backFacing, albedo);
                });
              });
        }
    }
  });
}

void drawOpaque(const ProjectedMesh& pm, Target& t) {
  drawMesh(pm, t.w, t.h, [&](std::size_t i, float z, auto&& colour) {
    if (z < t.depth[i]) {
      t.depth[i] = z;
      t.colour[i] = colour();
    }
  });
}

// Nearest surface of one semi-transparent mesh in front of the opaque ones, then blended over
// the target except where a curve lies on or in front of it.
void drawTransparent(const ProjectedMesh& pm, float opacity, float bias, Target& t) {
  std::vector<float> depth(t.depth.size(), kInf);
  std::vector<Eigen::Vector3f> colour(t.depth.size());
  drawMesh(pm, t.w, t.h, [&](std::size_t i, float z, auto&& shadeColour) {
    if (z < t.depth[i] && z < depth[i]) {
      depth[i] = z;
      colour[i] = shadeColour();
    }
  });
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] == kInf) continue;
    if (t.overlay[i] != kInf && depth[i] > t.overlay[i] - bias) continue;
    t.colour[i] = (1.0f - opacity) * t.colour[i] + opacity * colour[i];
  }
}

// A capsule of radius r (samples) around segment p→q; depth interpolated along the segment.
// Depth-tested overlays pass when at most `bias` behind the surface and behind other overlays.
void drawSegment(const Eigen::Vector3f& p, const Eigen::Vector3f& q, float r, bool onTop,
                 float bias, const Eigen::Vector3f& colour, Target& t) {
  const double x0 = std::max(0.0, std::ceil(std::min(p.x(), q.x()) - r - 0.5));
  const double x1 = std::min(t.w - 1.0, std::floor(std::max(p.x(), q.x()) + r - 0.5));
  const double y0 = std::max(0.0, std::ceil(std::min(p.y(), q.y()) - r - 0.5));
  const double y1 = std::min(t.h - 1.0, std::floor(std::max(p.y(), q.y()) + r - 0.5));
  if (x0 > x1 || y0 > y1) return;
  const Eigen::Vector2d a(p.x(), p.y()), d = Eigen::Vector2d(q.x(), q.y()) - a;
  const double len2 = d.squaredNorm();
  const double r2 = double(r) * r;
  for (int y = static_cast<int>(y0); y <= static_cast<int>(y1); ++y) {
    for (int x = static_cast<int>(x0); x <= static_cast<int>(x1); ++x) {
      const Eigen::Vector2d s(x + 0.5, y + 0.5);
      const double u = len2 > 0 ? std::clamp((s - a).dot(d) / len2, 0.0, 1.0) : 0.0;
      if ((a + u * d - s).squaredNorm() > r2) continue;
      const std::size_t i = std::size_t(y) * t.w + x;
      const float z = static_cast<float>(p.z() + u * (q.z() - p.z()));
      if (!onTop) {
        if (z > t.depth[i] + bias || z > t.overlay[i] + bias) continue;
        t.overlay[i] = std::min(t.overlay[i], z);
      }
      t.colour[i] = colour;
    }
  }
}

void drawLines(const Scene& scene, const ViewFrame& frame, bool onTop, float bias, int ss,
               Target& t) {
  for (const Polyline& l : scene.lines) {
    if (l.onTop != onTop || l.points.rows() == 0) continue;
    const float r = 0.5f * l.widthPx * ss;
    const float b = bias + static_cast<float>(r / frame.k);
    const Eigen::Vector3f colour = toUnit(l.colour);
    const Eigen::Index n = l.points.rows();
    std::vector<Eigen::Vector3f> p(n);
    for (Eigen::Index i = 0; i < n; ++i) p[i] = frame.project(l.points.row(i).transpose());
    if (n == 1) drawSegment(p[0], p[0], r, onTop, b, colour, t);
    for (Eigen::Index i = 0; i + 1 < n; ++i) drawSegment(p[i], p[i + 1], r, onTop, b, colour, t);
    if (l.closed && n > 2) drawSegment(p[n - 1], p[0], r, onTop, b, colour, t);
  }
}

void drawPoints(const Scene& scene, const ViewFrame& frame, bool onTop, float bias, int ss,
                Target& t) {
  for (const PointSet& ps : scene.points) {
    if (ps.onTop != onTop) continue;
    const float r = ps.radiusPx * ss;
    const float b = bias + static_cast<float>(r / frame.k);
    const Eigen::Vector3f colour = toUnit(ps.colour);
    for (Eigen::Index i = 0; i < ps.points.rows(); ++i) {
      const Eigen::Vector3f p = frame.project(ps.points.row(i).transpose());
      drawSegment(p, p, r, onTop, b, colour, t);
    }
  }
}

// Box filter of ss×ss samples into the panel starting at column x0 of the image.
void downsample(const Target& t, int ss, int x0, Image& image) {
  const int w = t.w / ss, h = t.h / ss;
  const float norm = 1.0f / float(ss * ss);
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](auto r) {
    for (int y = r.begin(); y != r.end(); ++y) {
      for (int x = 0; x < w; ++x) {
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        for (int sy = 0; sy < ss; ++sy)
          for (int sx = 0; sx < ss; ++sx)
            sum += t.colour[std::size_t(y * ss + sy) * t.w + (x * ss + sx)];
        sum *= norm;
        std::uint8_t* px = &image.rgb[(std::size_t(y) * image.width + x0 + x) * 3];
        px[0] = toByte(sum.x());
        px[1] = toByte(sum.y());
        px[2] = toByte(sum.z());
      }
    }
  });
}

// Caption centred in the top margin of a panel: as large as the margin allows (up to 1/200 of
// the height per font pixel), shortened if it does not fit the panel's width even at scale 1.
void drawCaption(const std::string& caption, const ViewPanel& panel, int marginPx, Rgb background,
                 Image& image) {
  if (caption.empty()) return;
  int scale = std::max(1, std::min(image.height / 200, (marginPx - 2) / 7));
  while (scale > 1 && textWidth(caption, scale) > panel.width - 2) --scale;
  std::string text = caption;
  while (!text.empty() && textWidth(text, scale) > panel.width - 2) text.pop_back();
  const int luminance = 299 * background.r + 587 * background.g + 114 * background.b;
  const Rgb ink = luminance > 128 * 1000 ? Rgb{40, 40, 40} : Rgb{230, 230, 230};
  const int x = panel.x0 + (panel.width - textWidth(text, scale)) / 2;
  const int y = std::max(1, (marginPx - textHeight(scale)) / 2);
  drawText(image, x, y, text, scale, ink);
}

}  // namespace

// === Views

std::optional<View> parseView(std::string_view name) {
  std::string s(name);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (s == "front") return View::Front;
  if (s == "back") return View::Back;
  if (s == "left") return View::Left;
  if (s == "right") return View::Right;
  if (s == "three-quarter" || s == "three_quarter" || s == "threequarter" || s == "3/4")
    return View::ThreeQuarter;
  return std::nullopt;
}

const char* toString(View view) {
  switch (view) {
    case View::Front:
      return "front";
    case View::Back:
      return "back";
    case View::Left:
      return "left";
    case View::Right:
      return "right";
    case View::ThreeQuarter:
      return "three-quarter";
  }
  return "front";
}

Eigen::Matrix3d viewRotation(View view) {
  // Rows: image right, image up, towards the camera (a right-handed frame).
  const double h = std::numbers::sqrt2 / 2;
  Eigen::Matrix3d R;
  switch (view) {
    case View::Front:
      R << 1, 0, 0, 0, 1, 0, 0, 0, 1;
      break;
    case View::Back:
      R << -1, 0, 0, 0, 1, 0, 0, 0, -1;
      break;
    case View::Left:
      R << 0, 0, -1, 0, 1, 0, 1, 0, 0;
      break;
    case View::Right:
      R << 0, 0, 1, 0, 1, 0, -1, 0, 0;
      break;
    case View::ThreeQuarter:
      R << h, 0, -h, 0, 1, 0, h, 0, h;
      break;
  }
  return R;
}

// === Rendering

Image renderScene(const Scene& scene, const RenderOptions& options) {
  return renderScene(scene, options, nullptr);
}

Image renderScene(const Scene& scene, const RenderOptions& options,
                  std::vector<ViewPanel>* panels) {
  validateScene(scene, options);
  const int H = options.heightPx, ss = options.supersample;
  const int marginPx = static_cast<int>(std::lround(options.margin * H));
  const int maxWidth = options.maxViewWidthPx > 0 ? options.maxViewWidthPx : 4 * H;

  // One scale for all views: the tallest content fills the height, no panel exceeds maxWidth.
  const std::size_t nViews = options.views.size();
  std::vector<Eigen::Matrix3d> rotations(nViews);
  std::vector<Extent2> extents(nViews);
  double extY = 0, extX = 0;
  bool empty = true;
  for (std::size_t v = 0; v < nViews; ++v) {
    rotations[v] = viewRotation(options.views[v]);
    extents[v] = sceneExtent(scene, rotations[v]);
    if (extents[v].empty()) continue;
    empty = false;
    const Eigen::Vector2d e = extents[v].hi - extents[v].lo;
    extX = std::max(extX, e.x());
    extY = std::max(extY, e.y());
  }
  if (!(extX <= 1e9 && extY <= 1e9))
    throw InputError("renderScene: the scene spans more than 1e9 units; check the coordinates");
  double ppm = std::numeric_limits<double>::infinity();  // pixels per metre
  if (extY > 0) ppm = std::max(1.0, H - 2.0 * marginPx) / extY;
  if (extX > 0) ppm = std::min(ppm, std::max(1.0, maxWidth - 2.0 * marginPx) / extX);
  if (!std::isfinite(ppm)) ppm = std::max(1.0, H - 2.0 * marginPx);  // a point: 1 m across
  const float bias = static_cast<float>(options.overlayDepthBias * std::max(extX, extY));

  std::vector<ViewPanel> layout(nViews);
  int totalWidth = 0;
  for (std::size_t v = 0; v < nViews; ++v) {
    ViewPanel& p = layout[v];
    p.view = options.views[v];
    p.pixelsPerMetre = ppm;
    if (empty) {
      p.width = H;
    } else {
      const Eigen::Vector2d e = extents[v].hi - extents[v].lo;
      p.width = std::clamp(static_cast<int>(std::ceil(e.x() * ppm - 1e-9)) + 2 * marginPx, 1,
                           std::max(1, maxWidth));
      p.centre = 0.5 * (extents[v].lo + extents[v].hi);
    }
    p.x0 = totalWidth;
    totalWidth += p.width + (v + 1 < nViews ? options.gapPx : 0);
    if (static_cast<long long>(p.width) * ss * H * ss > kMaxSamples)
      throw InputError("renderScene: view " + std::string(toString(p.view)) + " needs " +
                       std::to_string(p.width * ss) + "x" + std::to_string(H * ss) +
                       " samples; reduce heightPx or supersample");
  }

  Image image;
  image.width = totalWidth;
  image.height = H;
  image.rgb.resize(std::size_t(totalWidth) * H * 3);
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    image.rgb[i] = options.background.r;
    image.rgb[i + 1] = options.background.g;
    image.rgb[i + 2] = options.background.b;
  }

  // Normals once per mesh, shared by the views.
  std::vector<PreparedMesh> prepared;
  for (const SceneMesh& m : scene.meshes) {
    if (m.mesh->numFaces() == 0 || m.opacity <= 0.0f) continue;
    PreparedMesh pm;
    pm.source = &m;
    pm.normal = m.smooth ? areaWeightedNormals(*m.mesh) : faceNormals(*m.mesh);
    prepared.push_back(std::move(pm));
  }

  const Eigen::Vector3f background = toUnit(options.background);
  for (std::size_t v = 0; v < nViews; ++v) {
    const ViewPanel& panel = layout[v];
    ViewFrame frame;
    frame.R = rotations[v];
    frame.centre = panel.centre;
    frame.k = ppm * ss;
    frame.w = panel.width * ss;
    frame.h = H * ss;
    Target target(frame.w, frame.h, background);
    // Opaque surfaces, then depth-tested curves and points, then semi-transparent surfaces
    // blended over them in scene order, then everything drawn on top.
    for (const PreparedMesh& pm : prepared)
      if (pm.source->opacity >= 1.0f) drawOpaque(projectMesh(pm, frame), target);
    drawLines(scene, frame, false, bias, ss, target);
    drawPoints(scene, frame, false, bias, ss, target);
    for (const PreparedMesh& pm : prepared)
      if (pm.source->opacity < 1.0f)
        drawTransparent(projectMesh(pm, frame), pm.source->opacity, bias, target);
    drawLines(scene, frame, true, bias, ss, target);
    drawPoints(scene, frame, true, bias, ss, target);
    downsample(target, ss, panel.x0, image);
    if (!options.captions.empty())
      drawCaption(options.captions[v], panel, marginPx, options.background, image);
  }
  if (panels != nullptr) *panels = std::move(layout);
  return image;
}

}  // namespace s2p
