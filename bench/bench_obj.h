// A minimal OBJ reader for the pattern files the benchmarks read (panels.obj, panels_flat.obj,
// panels_3d.obj, body_rest.obj): vertices, triangles and groups. Bench programs only: the
// program's own readers are in io/.
#pragma once

#include <Eigen/Core>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace s2p {

struct ObjFile {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  std::vector<int> group;  // per face, −1 before the first group
  std::vector<std::string> names;
};

inline ObjFile readObjFile(const std::string& path) {
  ObjFile o;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string tag;
    ss >> tag;
    if (tag == "v") {
      double x = 0, y = 0, z = 0;
      ss >> x >> y >> z;
      o.V.emplace_back(x, y, z);
    } else if (tag == "g") {
      std::string name;
      ss >> name;
      o.names.push_back(name);
    } else if (tag == "f") {
      std::string a, b, c;  // "i", "i/t" or "i/t/n"
      ss >> a >> b >> c;
      o.F.emplace_back(std::stoi(a) - 1, std::stoi(b) - 1, std::stoi(c) - 1);
      o.group.push_back(static_cast<int>(o.names.size()) - 1);
    }
  }
  return o;
}

}  // namespace s2p
