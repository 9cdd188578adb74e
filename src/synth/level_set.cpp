#include "synth/level_set.h"

#include "body/level_set_mesh.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <string>

#include "core/error.h"
#include "core/surface_point.h"

namespace s2p {

struct BodyField::Grids {
  openvdb::math::Transform::Ptr xform;
  openvdb::FloatGrid::Ptr sdf;    // posed body signed distance (metres), narrow band
  openvdb::Int32Grid::Ptr face;   // closest posed body face of every band voxel
};

BodyField::BodyField(const TriMesh& posed, const TriMesh& rest, double voxel, double exteriorBand)
    : posed_(posed), rest_(rest), voxel_(voxel), grids_(std::make_unique<Grids>()),
      query_(posed) {
  if (!(voxel >= 0.001 && voxel <= 0.05))
    throw InputError("clothed surface: voxel size " + std::to_string(voxel) +
                     " m is outside 1–50 mm; pick e.g. 0.004");
  if (posed.numFaces() != rest.numFaces() || posed.numVertices() != rest.numVertices())
    throw InputError("BodyField: posed and rest bodies differ in size");
  openvdb::initialize();
  Grids& g = *grids_;
  g.xform = openvdb::math::Transform::createLinearTransform(voxel);
  std::vector<openvdb::Vec3s> points(posed.numVertices());
  for (int v = 0; v < posed.numVertices(); ++v) {
    const openvdb::Vec3d w(posed.V(v, 0), posed.V(v, 1), posed.V(v, 2));
    points[v] = openvdb::Vec3s(g.xform->worldToIndex(w));
  }
  std::vector<openvdb::Vec3I> tris(posed.numFaces());
  for (int f = 0; f < posed.numFaces(); ++f)
    tris[f] = openvdb::Vec3I(posed.F(f, 0), posed.F(f, 1), posed.F(f, 2));
  openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points,
                                                                                     tris);
  g.face = openvdb::Int32Grid::create(-1);
  g.face->setTransform(g.xform);
  openvdb::util::NullInterrupter interrupter;
  g.sdf = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      interrupter, adapter, *g.xform, static_cast<float>(exteriorBand / voxel + 3), 3.0f, 0,
      g.face.get());
}

BodyField::~BodyField() = default;

Eigen::Vector3d BodyField::restPoint(int face, const Eigen::Vector3d& bary) const {
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) q += bary[k] * rest_.V.row(rest_.F(face, k)).transpose();
  return q;
}

BodySample BodyField::sample(const Eigen::Vector3d& p) const {
  const ClosestHit h = query_.closestPoint(p);
  auto acc = grids_->sdf->getConstAccessor();
  const openvdb::Vec3d ip = grids_->xform->worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z()));
  const float s = openvdb::tools::BoxSampler::sample(acc, ip);
  BodySample out;
  out.d = s < 0 ? -h.distance : h.distance;
  out.rest = restPoint(h.face, h.bary);
  out.hasRest = true;
  return out;
}

std::vector<BodySample> BodyField::samples(const Eigen::MatrixX3d& P) const {
  std::vector<BodySample> out(P.rows());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(P.rows()), 256),
                    [&](const tbb::blocked_range<int>& r) {
                      for (int i = r.begin(); i < r.end(); ++i)
                        out[i] = sample(P.row(i).transpose());
                    });
  return out;
}

namespace {

// Keeps the component with the most faces; returns the number of components dropped.
int keepLargestComponent(TriMesh& mesh, int* removedFaces) {
  const int nv = mesh.numVertices();
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 1; k < 3; ++k) {
      const int a = find(mesh.F(f, k)), b = find(mesh.F(f, 0));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<int> count(nv, 0);
  for (int f = 0; f < mesh.numFaces(); ++f) ++count[find(mesh.F(f, 0))];
  const int best = static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
  int components = 0;
  for (int v = 0; v < nv; ++v) components += (count[v] > 0);
  Eigen::MatrixX3i F(count[best], 3);
  int n = 0;
  for (int f = 0; f < mesh.numFaces(); ++f)
    if (find(mesh.F(f, 0)) == best) F.row(n++) = mesh.F.row(f);
  if (removedFaces) *removedFaces = mesh.numFaces() - n;
  mesh.F = F;
  std::vector<int> newIndex(nv, -1);
  for (int f = 0; f < n; ++f)
    for (int k = 0; k < 3; ++k) newIndex[F(f, k)] = 0;
  int m = 0;
  for (int v = 0; v < nv; ++v)
    if (newIndex[v] == 0) newIndex[v] = m++;
  Eigen::MatrixX3d V(m, 3);
  for (int v = 0; v < nv; ++v)
    if (newIndex[v] >= 0) V.row(newIndex[v]) = mesh.V.row(v);
  for (int f = 0; f < n; ++f)
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = newIndex[mesh.F(f, k)];
  mesh.V = V;
  return components - 1;
}

}  // namespace

TriMesh meshUnion(const BodyField& body, const GarmentLayers& layers, UnionMeshStats* stats,
                  Progress& progress) {
  using openvdb::Coord;
  const BodyField::Grids& g = body.grids();
  const double voxel = body.voxel();
  const float w = static_cast<float>(3 * voxel);  // band half width of the union grid

  progress.begin("synth: union level set");
  auto out = openvdb::FloatGrid::create(w);
  out->setTransform(g.xform);
  out->setGridClass(openvdb::GRID_LEVEL_SET);
  out->tree().topologyUnion(g.sdf->tree());

  // Analytic shapes: activate the voxels near their surfaces.
  for (int i = 0; i < layers.size(); ++i) {
    Eigen::Vector3d lo, hi;
    if (!layers.layer(i).analyticBox(lo, hi)) continue;
    lo.array() -= 2 * w;
    hi.array() += 2 * w;
    const Coord c0 = g.xform->worldToIndexCellCentered(openvdb::Vec3d(lo.x(), lo.y(), lo.z()));
    const Coord c1 = g.xform->worldToIndexCellCentered(openvdb::Vec3d(hi.x(), hi.y(), hi.z()));
    const int nz = c1.z() - c0.z() + 1;
    std::vector<std::vector<Coord>> slabs(std::max(nz, 0));
    tbb::parallel_for(0, std::max(nz, 0), [&](int kz) {
      std::vector<LayerValue> values(layers.size());
      BodySample far;
      for (int j = c0.y(); j <= c1.y(); ++j)
        for (int k = c0.x(); k <= c1.x(); ++k) {
          const Coord ijk(k, j, c0.z() + kz);
          const openvdb::Vec3d p = g.xform->indexToWorld(ijk);
          layers.evaluate(Eigen::Vector3d(p.x(), p.y(), p.z()), far, values.data());
          if (std::abs(values[i].value) < w) slabs[kz].push_back(ijk);
        }
    });
    auto acc = out->getAccessor();
    for (const auto& slab : slabs)
      for (const Coord& c : slab) acc.setValueOn(c, w);
  }

  // Union value at every active voxel.
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(out->tree());
  const TriMesh& posed = body.posed();
  tbb::parallel_for(leaves.leafRange(), [&](const openvdb::tree::LeafManager<
                                            openvdb::FloatTree>::LeafRange& range) {
    auto sdfAcc = g.sdf->getConstAccessor();
    auto faceAcc = g.face->getConstAccessor();
    for (auto leaf = range.begin(); leaf; ++leaf) {
      for (auto it = leaf->beginValueOn(); it; ++it) {
        const Coord ijk = it.getCoord();
        const openvdb::Vec3d pw = g.xform->indexToWorld(ijk);
        const Eigen::Vector3d p(pw.x(), pw.y(), pw.z());
        BodySample s;
        s.d = sdfAcc.getValue(ijk);
        int f = -1;
        if (faceAcc.probeValue(ijk, f) && f >= 0 && f < posed.numFaces()) {
          const Eigen::Vector3d bary = closestPointBarycentric(
              p, posed.V.row(posed.F(f, 0)).transpose(), posed.V.row(posed.F(f, 1)).transpose(),
              posed.V.row(posed.F(f, 2)).transpose());
          s.rest = body.restPoint(f, bary);
          s.hasRest = true;
        }
        const double u = layers.unionValue(p, s);
        it.setValue(static_cast<float>(std::clamp(u, -double(w), double(w))));
      }
    }
  });
  openvdb::tools::signedFloodFill(out->tree());
  if (stats) stats->activeVoxels = static_cast<long>(out->activeVoxelCount());
  progress.end();

  progress.begin("synth: mesh level set");
  TriMesh mesh = levelSetToMesh(*out);
  if (mesh.numFaces() == 0)
    throw TopologyError("clothed surface: the level set produced no surface; check the body");
  int removedFaces = 0;
  const int removed = keepLargestComponent(mesh, &removedFaces);
  if (stats) stats->removedComponents = removed, stats->removedFaces = removedFaces;
  double volume = 0;  // outward orientation: positive enclosed volume
  for (int i = 0; i < mesh.numFaces(); ++i)
    volume += mesh.V.row(mesh.F(i, 0))
                  .dot(Eigen::Vector3d(mesh.V.row(mesh.F(i, 1)))
                           .cross(Eigen::Vector3d(mesh.V.row(mesh.F(i, 2)))));
  if (volume < 0) mesh.F.col(1).swap(mesh.F.col(2));
  progress.end();
  return mesh;
}

}  // namespace s2p
