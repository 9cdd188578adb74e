#include "io/person_pieces.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <unordered_map>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "io/normalize.h"

namespace s2p {

const char* toString(PieceRole role) {
  switch (role) {
    case PieceRole::Person: return "person";
    case PieceRole::Floor: return "floor";
    case PieceRole::Floater: return "floater";
  }
  return "invalid";
}

namespace {

using Vec3 = Eigen::Vector3d;

// Grid cell key, 21 bits per axis (cells counted from the mesh's minimum corner).
std::uint64_t cellKey(std::int64_t x, std::int64_t y, std::int64_t z) {
  constexpr std::int64_t kMask = (1 << 21) - 1;
  return static_cast<std::uint64_t>(x & kMask) | (static_cast<std::uint64_t>(y & kMask) << 21) |
         (static_cast<std::uint64_t>(z & kMask) << 42);
}

// Pieces closer than `reach` to each other, as adjacency lists (sorted). The vertices are
// thinned to one per piece per voxel of reach/8 (so the work does not grow with the mesh's
// resolution, and distances are exact to about a voxel), then pairs of samples of different
// pieces in neighbouring cells of size `reach` are compared.
std::vector<std::vector<int>> pieceAdjacency(const Eigen::MatrixX3d& V,
                                             const std::vector<int>& vertexPiece, int numPieces,
                                             double reach) {
  const Vec3 lo = V.colwise().minCoeff().transpose();
  auto key = [&](const Vec3& p, double size) {
    const Vec3 q = ((p - lo) / size).array().floor();
    return cellKey(static_cast<std::int64_t>(q.x()), static_cast<std::int64_t>(q.y()),
                   static_cast<std::int64_t>(q.z()));
  };
  // Samples: the first vertex of each (voxel, piece).
  std::unordered_map<std::uint64_t, std::vector<int>> voxels;  // voxel → pieces sampled there
  std::vector<int> sample;  // vertex ids
  for (int v = 0; v < V.rows(); ++v) {
    if (vertexPiece[v] < 0) continue;
    std::vector<int>& list = voxels[key(V.row(v).transpose(), reach / 8)];
    if (std::find(list.begin(), list.end(), vertexPiece[v]) != list.end()) continue;
    list.push_back(vertexPiece[v]);
    sample.push_back(v);
  }
  std::unordered_map<std::uint64_t, std::vector<int>> cells;  // cell → samples
  for (int s : sample) cells[key(V.row(s).transpose(), reach)].push_back(s);
  constexpr std::int64_t kMask = (1 << 21) - 1;
  std::vector<std::vector<int>> adj(numPieces);
  const double reach2 = reach * reach;
  for (const auto& [k, list] : cells) {
    const std::int64_t x = static_cast<std::int64_t>(k & kMask);
    const std::int64_t y = static_cast<std::int64_t>((k >> 21) & kMask);
    const std::int64_t z = static_cast<std::int64_t>((k >> 42) & kMask);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          if (x + dx < 0 || y + dy < 0 || z + dz < 0) continue;
          const auto it = cells.find(cellKey(x + dx, y + dy, z + dz));
          if (it == cells.end()) continue;
          for (int a : list)
            for (int b : it->second) {
              const int pa = vertexPiece[a], pb = vertexPiece[b];
              if (pa == pb || (V.row(a) - V.row(b)).squaredNorm() > reach2) continue;
              if (std::find(adj[pa].begin(), adj[pa].end(), pb) == adj[pa].end())
                adj[pa].push_back(pb);
            }
        }
  }
  for (auto& a : adj) std::sort(a.begin(), a.end());
  return adj;
}

// Gap between two boxes (0 when they overlap).
double boxGap(const BoundingBox& a, const BoundingBox& b) {
  const Vec3 d = (a.min - b.max).cwiseMax(b.min - a.max).cwiseMax(0.0);
  return d.norm();
}

std::string plural(int n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

}  // namespace

PersonPieces findPersonPieces(const TriMesh& mesh, const PersonPiecesOptions& options,
                              const std::string& what) {
  validateMesh(mesh, what);
  const MeshTopology topo(mesh.F, mesh.numVertices());
  const Eigen::VectorXi& faceComponent = topo.faceComponent();
  const int np = topo.numComponents();
  PersonPieces out;
  out.pieces.resize(np);
  out.keepFace.assign(mesh.numFaces(), true);
  std::vector<int> vertexPiece(mesh.numVertices(), -1);
  const Eigen::VectorXd area = faceAreas(mesh);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    PieceInfo& p = out.pieces[faceComponent[f]];
    ++p.faces;
    p.area += area[f];
    for (int k = 0; k < 3; ++k) vertexPiece[mesh.F(f, k)] = faceComponent[f];
  }
  // === Shape of every piece: box, principal axes (vertex covariance), extents along them.
  std::vector<Vec3> mean(np, Vec3::Zero());
  std::vector<Eigen::Matrix3d> cov(np, Eigen::Matrix3d::Zero());
  for (PieceInfo& p : out.pieces) {
    p.box.min = Vec3::Constant(std::numeric_limits<double>::infinity());
    p.box.max = -p.box.min;
  }
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const int c = vertexPiece[v];
    if (c < 0) continue;
    const Vec3 x = mesh.V.row(v).transpose();
    PieceInfo& p = out.pieces[c];
    ++p.vertices;
    mean[c] += x;
    p.box.min = p.box.min.cwiseMin(x);
    p.box.max = p.box.max.cwiseMax(x);
  }
  for (int c = 0; c < np; ++c) mean[c] /= std::max(1, out.pieces[c].vertices);
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (const int c = vertexPiece[v]; c >= 0) {
      const Vec3 d = mesh.V.row(v).transpose() - mean[c];
      cov[c] += d * d.transpose();
    }
  std::vector<Eigen::Matrix3d> axes(np);
  for (int c = 0; c < np; ++c) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov[c]);
    axes[c] = eig.eigenvectors();  // columns by increasing eigenvalue: thinnest first
  }
  std::vector<Vec3> lo(np, Vec3::Constant(std::numeric_limits<double>::infinity())),
      hi(np, Vec3::Constant(-std::numeric_limits<double>::infinity()));
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (const int c = vertexPiece[v]; c >= 0) {
      const Vec3 q = axes[c].transpose() * mesh.V.row(v).transpose();
      lo[c] = lo[c].cwiseMin(q);
      hi[c] = hi[c].cwiseMax(q);
    }
  for (int c = 0; c < np; ++c) {
    PieceInfo& p = out.pieces[c];
    p.thickness = hi[c][0] - lo[c][0];
    p.length = hi[c][2] - lo[c][2];
    p.normal = axes[c].col(0);
  }
  auto flat = [&](const PieceInfo& p) {
    return p.thickness <= std::max(options.floorThickness, 0.04 * p.length);
  };

  // === The largest piece is the person's core.
  int largest = 0;
  for (int c = 1; c < np; ++c)
    if (out.pieces[c].area > out.pieces[largest].area) largest = c;
  out.largest = largest;
  const PieceInfo& core = out.pieces[largest];
  if (flat(core) && core.length >= 0.3)
    throw InputError(fmt::format(
        "{}: the largest piece of the scan ({} vertices, {:.2f} m across) is flat, {:.1f} cm "
        "thick: a floor patch, not a person; crop the floor away so that the person is the "
        "largest piece, or scan the person standing clear of it",
        what, core.vertices, core.length, 100 * core.thickness));
  if (np == 1) {
    out.keptPieces = 1;
    return out;
  }
  const double height = std::max(core.box.extent().y(), 0.1);
  const double reach = options.reachFraction * height;
  const double band = options.floorBandFraction * height;

  // === Pieces within reach of the person, piece by piece from the core; flat horizontal pieces
  // do not pass reach on (a floor patch under the feet would bring in everything on the floor).
  constexpr double kCos25 = 0.906;
  std::vector<bool> floorCandidate(np, false);
  for (int c = 0; c < np; ++c)
    floorCandidate[c] =
        c != largest && flat(out.pieces[c]) && std::abs(out.pieces[c].normal.y()) >= kCos25;
  const std::vector<std::vector<int>> adj =
      pieceAdjacency(mesh.V, vertexPiece, np, reach);
  std::vector<bool> person(np, false);
  person[largest] = true;
  std::vector<int> queue = {largest};
  while (!queue.empty()) {
    const int c = queue.back();
    queue.pop_back();
    for (int d : adj[c])
      if (!person[d] && !floorCandidate[d]) {
        person[d] = true;
        queue.push_back(d);
      }
  }

  // === Floor: flat horizontal pieces at the feet (or head) end reaching beyond the person's
  // footprint there; the rest of the flat pieces (a sole scanned apart) join when within reach.
  BoundingBox personBox{Vec3::Constant(std::numeric_limits<double>::infinity()),
                        Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (int c = 0; c < np; ++c)
    if (person[c]) {
      personBox.min = personBox.min.cwiseMin(out.pieces[c].box.min);
      personBox.max = personBox.max.cwiseMax(out.pieces[c].box.max);
    }
  // The person's footprint at each end: the (x, z) cells of 2 cm holding a vertex of the person
  // in the bottom (top) band. A face is inside it when a cell within 2 cm of it is occupied, so a
  // sole scanned apart (right under the shoe) is inside and the floor between and around the
  // feet is not (the box of both feet would hold the floor between them).
  constexpr double kFootprintMargin = 0.02;  // m, also the cell size
  std::set<std::pair<std::int64_t, std::int64_t>> foot, head;
  auto cellOf = [&](double x, double z) {
    return std::pair{static_cast<std::int64_t>(std::floor(x / kFootprintMargin)),
                     static_cast<std::int64_t>(std::floor(z / kFootprintMargin))};
  };
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const int c = vertexPiece[v];
    if (c < 0 || !person[c]) continue;
    const double y = mesh.V(v, 1);
    if (y <= personBox.min.y() + band) foot.insert(cellOf(mesh.V(v, 0), mesh.V(v, 2)));
    if (y >= personBox.max.y() - band) head.insert(cellOf(mesh.V(v, 0), mesh.V(v, 2)));
  }
  std::vector<double> outside(np, 0.0);  // area of the piece's faces outside the end footprint
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const int c = faceComponent[f];
    if (!floorCandidate[c]) continue;
    const Vec3 m = (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) + mesh.V.row(mesh.F(f, 2)))
                       .transpose() / 3.0;
    const auto& fp = m.y() < 0.5 * (personBox.min.y() + personBox.max.y()) ? foot : head;
    const auto [cx, cz] = cellOf(m.x(), m.z());
    bool in = false;
    for (std::int64_t dx = -1; dx <= 1 && !in; ++dx)
      for (std::int64_t dz = -1; dz <= 1 && !in; ++dz) in = fp.count({cx + dx, cz + dz}) > 0;
    if (!in) outside[c] += area[f];
  }
  for (int c = 0; c < np; ++c) {
    PieceInfo& p = out.pieces[c];
    if (person[c]) continue;
    const bool atEnd =
        p.box.max.y() <= personBox.min.y() + band || p.box.min.y() >= personBox.max.y() - band;
    if (floorCandidate[c] && atEnd && outside[c] >= 0.5 * p.area) {
      p.role = PieceRole::Floor;
      continue;
    }
    bool near = false;
    for (int d : adj[c]) near = near || person[d];
    p.role = near ? PieceRole::Person : PieceRole::Floater;
  }
  for (int c = 0; c < np; ++c) {
    PieceInfo& p = out.pieces[c];
    if (p.role != PieceRole::Person) p.distance = boxGap(p.box, personBox);
  }

  // === Two people: a person-sized piece out of reach.
  for (int c = 0; c < np; ++c) {
    const PieceInfo& p = out.pieces[c];
    if (p.role == PieceRole::Floater && p.area >= options.personAreaFraction * core.area &&
        p.box.extent().y() >= options.personHeightFraction * height)
      throw InputError(fmt::format(
          "{}: two people? Besides the largest piece ({} vertices, {:.2f} m tall) a second "
          "piece of {} vertices, {:.2f} m tall and {:.0f} % of its area stands {:.2f} m away; "
          "scan one person at a time, or crop the scan to the person to fit",
          what, core.vertices, height, p.vertices, p.box.extent().y(),
          100 * p.area / core.area, p.distance));
  }

  // === What is kept, what is dropped, and the report's lines.
  int extraVertices = 0;
  double extraArea = 0;
  int floorVertices = 0, floaterVertices = 0, farthest = -1;
  double floorArea = 0, floaterArea = 0;
  BoundingBox floorBox{Vec3::Constant(1e300), Vec3::Constant(-1e300)};
  for (int c = 0; c < np; ++c) {
    const PieceInfo& p = out.pieces[c];
    switch (p.role) {
      case PieceRole::Person:
        ++out.keptPieces;
        if (c != largest) extraVertices += p.vertices, extraArea += p.area;
        break;
      case PieceRole::Floor:
        ++out.floorPieces;
        floorVertices += p.vertices;
        floorArea += p.area;
        floorBox.min = floorBox.min.cwiseMin(p.box.min);
        floorBox.max = floorBox.max.cwiseMax(p.box.max);
        break;
      case PieceRole::Floater:
        ++out.floaterPieces;
        floaterVertices += p.vertices;
        floaterArea += p.area;
        if (farthest < 0 || p.distance > out.pieces[farthest].distance) farthest = c;
        break;
    }
  }
  for (int f = 0; f < mesh.numFaces(); ++f)
    if (out.pieces[faceComponent[f]].role != PieceRole::Person) {
      out.keepFace[f] = false;
      ++out.droppedFaces;
      out.droppedArea += area[f];
    }
  out.droppedVertices = floorVertices + floaterVertices;
  int biggestExtra = 0;
  for (int c = 0; c < np; ++c)
    if (c != largest && out.pieces[c].role == PieceRole::Person)
      biggestExtra = std::max(biggestExtra, out.pieces[c].vertices);
  if (out.keptPieces > 1)
    out.warnings.push_back(fmt::format(
        "kept {} as the person: the largest ({} vertices) and {} within {:.0f} cm of it ({} "
        "vertices, {:.3f} m², the biggest {} vertices{})",
        plural(out.keptPieces, "piece", "pieces"), core.vertices,
        plural(out.keptPieces - 1, "other", "others"), 100 * reach, extraVertices, extraArea,
        biggestExtra,
        biggestExtra >= 0.05 * core.vertices ? ": a limb scanned apart, e.g. legs below a skirt"
                                             : ""));
  if (out.floorPieces > 0) {
    const Vec3 e = floorBox.extent();
    out.warnings.push_back(fmt::format(
        "dropped {} ({} vertices, {:.3f} m², {:.2f} × {:.2f} m): flat and horizontal at the "
        "person's {} and reaching beyond them",
        plural(out.floorPieces, "floor patch", "floor patches"), floorVertices, floorArea, e.x(),
        e.z(), floorBox.max.y() <= personBox.min.y() + band ? "feet" : "head"));
  }
  if (out.floaterPieces > 0)
    out.warnings.push_back(fmt::format(
        "dropped {} out of reach of the person ({} vertices, {:.4f} m²; the farthest {:.2f} m "
        "away)",
        plural(out.floaterPieces, "floater", "floaters"), floaterVertices, floaterArea,
        out.pieces[farthest].distance));
  return out;
}

void keepFaces(Scan& scan, const std::vector<bool>& keepFace) {
  TriMesh& m = scan.mesh;
  if (static_cast<int>(keepFace.size()) != m.numFaces())
    throw InputError(fmt::format("keepFaces: {} flags for {} faces", keepFace.size(),
                                 m.numFaces()));
  std::vector<int> newIndex(m.numVertices(), -1);
  int nf = 0;
  for (int f = 0; f < m.numFaces(); ++f)
    if (keepFace[f]) {
      ++nf;
      for (int k = 0; k < 3; ++k) newIndex[m.F(f, k)] = 0;
    }
  int nv = 0;
  for (int& i : newIndex)
    if (i == 0) i = nv++;
  Eigen::MatrixX3d V(nv, 3);
  const bool hasColour = scan.colour.rows() == m.numVertices() && m.numVertices() > 0;
  Eigen::MatrixX3d C(hasColour ? nv : 0, 3);
  for (int v = 0; v < m.numVertices(); ++v)
    if (newIndex[v] >= 0) {
      V.row(newIndex[v]) = m.V.row(v);
      if (hasColour) C.row(newIndex[v]) = scan.colour.row(v);
    }
  Eigen::MatrixX3i F(nf, 3);
  Eigen::MatrixX3i FUV(scan.texture ? nf : 0, 3);
  for (int f = 0, i = 0; f < m.numFaces(); ++f)
    if (keepFace[f]) {
      for (int k = 0; k < 3; ++k) F(i, k) = newIndex[m.F(f, k)];
      if (scan.texture) FUV.row(i) = scan.texture->FUV.row(f);
      ++i;
    }
  m.V = std::move(V);
  m.F = std::move(F);
  if (hasColour) scan.colour = std::move(C);
  if (scan.texture) scan.texture->FUV = std::move(FUV);
}

PersonPieces normalizePerson(Scan& scan, const NormalizeOptions& options, NormalizeReport& report,
                             const PersonPiecesOptions& pieceOptions) {
  const std::string what = scan.sourcePath.empty() ? std::string("scan") : scan.sourcePath;
  validateMesh(scan.mesh, what);
  const MeshTopology topo(scan.mesh.F, scan.mesh.numVertices());
  if (topo.numComponents() == 1) {
    report = normalizeScan(scan, options);
    PersonPieces out = findPersonPieces(scan.mesh, pieceOptions, what);
    return out;
  }
  const Scan original = scan;
  TriMesh framed;  // the whole scan in a provisional metres / +Y up frame
  bool whole = true;  // the whole scan could be normalised
  try {
    report = normalizeScan(scan, options);
    framed = scan.mesh;
  } catch (const InputError&) {
    whole = false;
    // The largest piece alone gives the frame (a floor patch longer than the person is tall
    // takes the up axis and the units).
    const Eigen::VectorXd area = faceAreas(original.mesh);
    std::vector<double> pieceArea(topo.numComponents(), 0.0);
    for (int f = 0; f < original.mesh.numFaces(); ++f) pieceArea[topo.faceComponent()[f]] += area[f];
    const int largest = static_cast<int>(
        std::max_element(pieceArea.begin(), pieceArea.end()) - pieceArea.begin());
    std::vector<bool> keep(original.mesh.numFaces());
    for (int f = 0; f < original.mesh.numFaces(); ++f) keep[f] = topo.faceComponent()[f] == largest;
    Scan core = original;
    keepFaces(core, keep);
    normalizeScan(core, options);  // throws when the person itself is not usable
    const Eigen::Affine3d toFrame = core.toInputFrame.inverse();
    framed = original.mesh;
    framed.V = (original.mesh.V * toFrame.linear().transpose()).rowwise() +
               toFrame.translation().transpose();
  }
  PersonPieces out = findPersonPieces(framed, pieceOptions, what);
  if (out.droppedFaces == 0 && whole) return out;
  scan = original;
  keepFaces(scan, out.keepFace);
  report = normalizeScan(scan, options);
  return out;
}

}  // namespace s2p
