#include "core/mesh_query.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>

#include "core/error.h"
#include "core/surface_point.h"
#include "core/winding_number.h"

namespace s2p {
namespace {

std::string str(const Eigen::Vector3d& v) {
  return "(" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) +
         ")";
}

void requireFinite(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite())
    throw InputError(std::string("MeshQuery: ") + what + " " + str(v) +
                     " is not finite; pass finite coordinates");
}

void requireFiniteRows(const Eigen::MatrixX3d& P, const char* what) {
  for (int i = 0; i < P.rows(); ++i)
    if (!P.row(i).allFinite())
      throw InputError(std::string("MeshQuery: ") + what + " row " + std::to_string(i) +
                       " is not finite; pass finite coordinates");
}

struct PointOnTriangle {
  Eigen::Vector3d bary;
  Eigen::Vector3d point;
};

// Exact closest point on triangle (a, b, c) to p (surface_point.h; robust to degenerate faces).
PointOnTriangle closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d bary = closestPointBarycentric(p, a, b, c);
  return {bary, bary.x() * a + bary.y() * b + bary.z() * c};
}

// Rounds x up to the next float (a query radius must never be smaller than the double one).
float floatAbove(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::max());
}

// One Embree device for the process (Embree's advice: devices own thread pools and caches).
// Each MeshQuery retains it, so it outlives every scene whatever the destruction order.
RTCDevice sharedDevice() {
  struct Holder {
    RTCDevice device = rtcNewDevice(nullptr);
    ~Holder() {
      if (device) rtcReleaseDevice(device);
    }
  };
  static Holder holder;
  if (!holder.device)
    throw Error("MeshQuery: Embree device creation failed (error " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcRetainDevice(holder.device);
  return holder.device;
}

}  // namespace

struct MeshQuery::Impl {
  Eigen::MatrixX3d V;  // #V×3 double copy: exact distances and hits
  Eigen::MatrixX3i F;  // #F×3
  MeshQueryOptions options;
  double pad = 0;  // float rounding of the BVH, metres: the culling radius is padded by it
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  mutable std::once_flag windingOnce;
  mutable std::unique_ptr<WindingNumberTree> winding;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  Eigen::Vector3d corner(int f, int k) const { return V.row(F(f, k)).transpose(); }

  const WindingNumberTree& windingTree() const {
    std::call_once(windingOnce, [this] {
      TriMesh mesh{V, F};
      winding =
          std::make_unique<WindingNumberTree>(mesh, options.windingBeta, options.windingOrder);
    });
    return *winding;
  }

  struct PointQueryState {
    const Impl* impl;
    Eigen::Vector3d p;
    double pad;  // metres added to the culling radius
    ClosestHit best;
  };

  // Called by Embree for every triangle whose bounds meet the current query sphere.
  static bool closestPointCallback(RTCPointQueryFunctionArguments* args) {
    auto* state = static_cast<PointQueryState*>(args->userPtr);
    const Impl& impl = *state->impl;
    const int f = static_cast<int>(args->primID);
    const PointOnTriangle q =
        closestOnTriangle(state->p, impl.corner(f, 0), impl.corner(f, 1), impl.corner(f, 2));
    const double d = (q.point - state->p).norm();
    if (d >= state->best.distance) return false;
    state->best = ClosestHit{f, q.bary, q.point, d};
    const float radius = floatAbove(d + state->pad);
    if (radius >= args->query->radius) return false;  // Embree forbids growing the radius
    args->query->radius = radius;
    return true;
  }
};

MeshQuery::MeshQuery(const TriMesh& mesh, const MeshQueryOptions& options)
    : impl_(std::make_unique<Impl>()) {
  validateMesh(mesh, "MeshQuery mesh");
  if (!(options.windingBeta >= 1.0))
    throw InputError("MeshQuery: windingBeta = " + std::to_string(options.windingBeta) +
                     " must be >= 1; use the default 2");
  if (options.windingOrder < 1 || options.windingOrder > 3)
    throw InputError("MeshQuery: windingOrder = " + std::to_string(options.windingOrder) +
                     " is not supported; use 1, 2 or 3");
  Impl& d = *impl_;
  d.V = mesh.V;
  d.F = mesh.F;
  d.options = options;
  // A float vertex is off by at most 2^-24 of its largest coordinate; allow 4× that.
  d.pad = 4.0 * std::ldexp(mesh.V.cwiseAbs().maxCoeff(), -24);

  d.device = sharedDevice();
  d.scene = rtcNewScene(d.device);
  rtcSetSceneFlags(d.scene, RTC_SCENE_FLAG_ROBUST);  // watertight edges for ray casting
  RTCGeometry geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.V.rows()));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.F.rows()));
  if (!vb || !ib) {
    rtcReleaseGeometry(geom);
    throw Error("MeshQuery: Embree could not allocate buffers for " +
                std::to_string(mesh.numFaces()) + " faces (out of memory?)");
  }
  for (int v = 0; v < mesh.numVertices(); ++v)
    for (int k = 0; k < 3; ++k) vb[3 * v + k] = static_cast<float>(mesh.V(v, k));
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) ib[3 * f + k] = static_cast<unsigned>(mesh.F(f, k));
  rtcCommitGeometry(geom);
  rtcAttachGeometryByID(d.scene, geom, 0);
  rtcReleaseGeometry(geom);
  rtcCommitScene(d.scene);
  if (const RTCError err = rtcGetDeviceError(d.device); err != RTC_ERROR_NONE)
    throw Error("MeshQuery: Embree failed to build the BVH over " +
                std::to_string(mesh.numFaces()) + " faces (error " +
                std::to_string(static_cast<int>(err)) + ")");
}

MeshQuery::~MeshQuery() = default;
MeshQuery::MeshQuery(MeshQuery&&) noexcept = default;
MeshQuery& MeshQuery::operator=(MeshQuery&&) noexcept = default;

int MeshQuery::numFaces() const {
  return static_cast<int>(impl_->F.rows());
}
int MeshQuery::numVertices() const {
  return static_cast<int>(impl_->V.rows());
}

ClosestHit MeshQuery::closestPoint(const Eigen::Vector3d& p) const {
  return closestPointFrom(p, -1);
}

ClosestHit MeshQuery::closestPointFrom(const Eigen::Vector3d& p, int hintFace) const {
  requireFinite(p, "closest-point query");
  Impl::PointQueryState state{impl_.get(), p, impl_->pad + std::ldexp(p.cwiseAbs().maxCoeff(), -22),
                              ClosestHit{}};
  state.best.distance = std::numeric_limits<double>::infinity();
  RTCPointQuery query;
  query.x = static_cast<float>(p.x());
  query.y = static_cast<float>(p.y());
  query.z = static_cast<float>(p.z());
  query.time = 0.0f;
  query.radius = std::numeric_limits<float>::infinity();
  if (hintFace >= 0 && hintFace < numFaces()) {
    // Start from the hinted face: Embree then only visits triangles that can be closer.
    const PointOnTriangle q = closestOnTriangle(
        p, impl_->corner(hintFace, 0), impl_->corner(hintFace, 1), impl_->corner(hintFace, 2));
    const double d = (q.point - p).norm();
    state.best = ClosestHit{hintFace, q.bary, q.point, d};
    query.radius = floatAbove(d + state.pad);
  }
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &query, &context, Impl::closestPointCallback, &state);
  if (state.best.face < 0) {  // cannot happen for a valid mesh; stay exact if it does
    for (int f = 0; f < numFaces(); ++f) {
      const PointOnTriangle q =
          closestOnTriangle(p, impl_->corner(f, 0), impl_->corner(f, 1), impl_->corner(f, 2));
      const double dist = (q.point - p).norm();
      if (dist < state.best.distance) state.best = ClosestHit{f, q.bary, q.point, dist};
    }
  }
  return state.best;
}

std::vector<ClosestHit> MeshQuery::closestPoints(const Eigen::MatrixX3d& P) const {
  requireFiniteRows(P, "closest-point query");
  std::vector<ClosestHit> out(P.rows());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(P.rows()), 64),
                    [&](const tbb::blocked_range<int>& r) {
                      for (int i = r.begin(); i != r.end(); ++i)
                        out[i] = closestPoint(P.row(i).transpose());
                    });
  return out;
}

std::vector<ClosestHit> MeshQuery::closestPoints(const Eigen::MatrixX3d& P,
                                                 const std::vector<int>& hintFaces) const {
  requireFiniteRows(P, "closest-point query");
  if (hintFaces.size() != static_cast<size_t>(P.rows()))
    throw InputError("MeshQuery: " + std::to_string(hintFaces.size()) + " hint faces for " +
                     std::to_string(P.rows()) + " query points; give one per point (-1: none)");
  std::vector<ClosestHit> out(P.rows());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(P.rows()), 64),
                    [&](const tbb::blocked_range<int>& r) {
                      for (int i = r.begin(); i != r.end(); ++i)
                        out[i] = closestPointFrom(P.row(i).transpose(), hintFaces[i]);
                    });
  return out;
}

std::optional<RayHit> MeshQuery::rayCast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                         double tMin, double tMax) const {
  requireFinite(origin, "ray origin");
  requireFinite(dir, "ray direction");
  const double len = dir.norm();
  if (!(len > 0)) throw InputError("MeshQuery: ray direction is zero; pass a non-zero vector");
  if (!(tMin >= 0) || !(tMax >= tMin))
    throw InputError("MeshQuery: ray interval [" + std::to_string(tMin) + ", " +
                     std::to_string(tMax) + "] is invalid; need 0 <= tMin <= tMax");
  const Eigen::Vector3d u = dir / len;  // Embree's t is in units of |dir|: make it a distance

  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(origin.x());
  rh.ray.org_y = static_cast<float>(origin.y());
  rh.ray.org_z = static_cast<float>(origin.z());
  rh.ray.dir_x = static_cast<float>(u.x());
  rh.ray.dir_y = static_cast<float>(u.y());
  rh.ray.dir_z = static_cast<float>(u.z());
  rh.ray.tnear = static_cast<float>(tMin);
  rh.ray.tfar = static_cast<float>(tMax);  // +inf stays +inf
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

  const int f = static_cast<int>(rh.hit.primID);
  const Eigen::Vector3d a = impl_->corner(f, 0), b = impl_->corner(f, 1), c = impl_->corner(f, 2);
  // Embree's (u, v) weight corners 1 and 2: point = (1−u−v) a + u b + v c.
  Eigen::Vector3d bary(1.0 - rh.hit.u - rh.hit.v, rh.hit.u, rh.hit.v);
  double t = rh.ray.tfar;
  // Refine in double (Möller–Trumbore on the same face); keep Embree's answer if it disagrees.
  const Eigen::Vector3d e1 = b - a, e2 = c - a, pvec = u.cross(e2);
  const double det = e1.dot(pvec);
  if (std::abs(det) > 0) {
    const Eigen::Vector3d tvec = origin - a, qvec = tvec.cross(e1);
    const double bu = tvec.dot(pvec) / det, bv = u.dot(qvec) / det, bt = e2.dot(qvec) / det;
    constexpr double kTol = 1e-6;
    if (bu >= -kTol && bv >= -kTol && bu + bv <= 1 + kTol && std::isfinite(bt) &&
        std::abs(bt - t) <= 1e-4 * (1.0 + std::abs(t))) {
      bary = Eigen::Vector3d(1.0 - bu - bv, bu, bv);
      t = std::clamp(bt, tMin, tMax);
    }
  }
  bary = bary.cwiseMax(0.0);
  bary /= bary.sum();
  return RayHit{f, bary, bary(0) * a + bary(1) * b + bary(2) * c, t};
}

double MeshQuery::windingNumber(const Eigen::Vector3d& p) const {
  requireFinite(p, "winding-number query");
  return impl_->windingTree().evaluate(p);
}

bool MeshQuery::isInside(const Eigen::Vector3d& p) const {
  return windingNumber(p) > 0.5;
}

Eigen::VectorXd MeshQuery::windingNumbers(const Eigen::MatrixX3d& P) const {
  requireFiniteRows(P, "winding-number query");
  const WindingNumberTree& tree = impl_->windingTree();
  Eigen::VectorXd out(P.rows());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(P.rows()), 32),
                    [&](const tbb::blocked_range<int>& r) {
                      for (int i = r.begin(); i != r.end(); ++i)
                        out(i) = tree.evaluate(P.row(i).transpose());
                    });
  return out;
}

}  // namespace s2p
