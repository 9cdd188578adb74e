#include "io/read_obj.h"

#include <fmt/format.h>

#include <charconv>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "io/read_ply.h"

namespace s2p {
namespace {

// One vertex reference of an `f` record ("7", "7/2", "7//3", "-1"): the 0-based vertex index.
bool parseReference(const std::string& token, int numVertices, int* index) {
  const std::string head = token.substr(0, token.find('/'));
  long value = 0;
  const auto [end, ec] = std::from_chars(head.data(), head.data() + head.size(), value);
  if (ec != std::errc() || end != head.data() + head.size() || value == 0) return false;
  const long i = value > 0 ? value - 1 : numVertices + value;  // negative: relative to the end
  if (i < 0 || i >= numVertices) return false;
  *index = static_cast<int>(i);
  return true;
}

}  // namespace

TriMesh parseObjGeometry(const std::string& text, const std::string& what) {
  std::vector<double> V;
  std::vector<int> F;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream record(line);
    std::string kind;
    if (!(record >> kind)) continue;
    if (kind == "v") {
      double x, y, z;
      if (!(record >> x >> y >> z))
        throw FormatError(fmt::format("{}, line {}: a vertex needs three coordinates", what, number));
      V.insert(V.end(), {x, y, z});
    } else if (kind == "f") {
      std::vector<int> polygon;
      std::string token;
      const int nv = static_cast<int>(V.size() / 3);
      while (record >> token) {
        int index = 0;
        if (!parseReference(token, nv, &index))
          throw FormatError(fmt::format("{}, line {}: '{}' is not a vertex of the {} before it",
                                        what, number, token, nv));
        polygon.push_back(index);
      }
      if (polygon.size() < 3)
        throw FormatError(fmt::format("{}, line {}: a face needs three vertices", what, number));
      for (size_t k = 1; k + 1 < polygon.size(); ++k)
        F.insert(F.end(), {polygon[0], polygon[k], polygon[k + 1]});
    }
  }
  if (V.empty()) throw FormatError(fmt::format("{} holds no vertex: not an OBJ mesh", what));
  TriMesh mesh;
  mesh.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      V.data(), static_cast<int>(V.size() / 3), 3);
  mesh.F = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      F.data(), static_cast<int>(F.size() / 3), 3);
  return mesh;
}

TriMesh readObjGeometry(const std::filesystem::path& path) {
  return parseObjGeometry(readFileBytes(path), path.string());
}

}  // namespace s2p
