#include "io/read_ply.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/error.h"

namespace s2p {

namespace {

enum class Encoding { Ascii, BinaryLe, BinaryBe };
enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct Property {
  std::string name;
  Type type = Type::Float32;
  bool isList = false;
  Type countType = Type::UInt8;
};

struct Element {
  std::string name;
  std::int64_t count = 0;
  std::vector<Property> properties;
};

bool parseType(const std::string& s, Type& t) {
  if (s == "char" || s == "int8")
    t = Type::Int8;
  else if (s == "uchar" || s == "uint8")
    t = Type::UInt8;
  else if (s == "short" || s == "int16")
    t = Type::Int16;
  else if (s == "ushort" || s == "uint16")
    t = Type::UInt16;
  else if (s == "int" || s == "int32")
    t = Type::Int32;
  else if (s == "uint" || s == "uint32")
    t = Type::UInt32;
  else if (s == "float" || s == "float32")
    t = Type::Float32;
  else if (s == "double" || s == "float64")
    t = Type::Float64;
  else
    return false;
  return true;
}

int typeSize(Type t) {
  switch (t) {
    case Type::Int8:
    case Type::UInt8:
      return 1;
    case Type::Int16:
    case Type::UInt16:
      return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32:
      return 4;
    case Type::Float64:
      return 8;
  }
  return 1;
}

// Reads values one by one from the body, with bounds checks (truncation → FormatError).
class Cursor {
 public:
  Cursor(const std::string& bytes, std::size_t pos, Encoding enc, const std::string& what)
      : data_(bytes.data()), end_(bytes.size()), pos_(pos), enc_(enc), what_(what) {}

  double read(Type t) { return enc_ == Encoding::Ascii ? readAscii() : readBinary(t); }
  std::size_t remaining() const { return end_ - pos_; }

 private:
  [[noreturn]] void truncated() const {
    throw FormatError(
        fmt::format("{}: the PLY body is truncated or malformed at byte {}; "
                    "re-export the file",
                    what_, pos_));
  }

  template <typename T>
  T raw() {
    if (end_ - pos_ < sizeof(T)) truncated();
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    if (enc_ == Encoding::BinaryBe && sizeof(T) > 1) {
      unsigned char b[sizeof(T)];
      std::memcpy(b, &v, sizeof(T));
      std::reverse(b, b + sizeof(T));
      std::memcpy(&v, b, sizeof(T));
    }
    return v;
  }

  double readBinary(Type t) {
    switch (t) {
      case Type::Int8:
        return raw<std::int8_t>();
      case Type::UInt8:
        return raw<std::uint8_t>();
      case Type::Int16:
        return raw<std::int16_t>();
      case Type::UInt16:
        return raw<std::uint16_t>();
      case Type::Int32:
        return raw<std::int32_t>();
      case Type::UInt32:
        return raw<std::uint32_t>();
      case Type::Float32:
        return raw<float>();
      case Type::Float64:
        return raw<double>();
    }
    return 0;
  }

  double readAscii() {
    while (pos_ < end_ && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    if (pos_ >= end_) truncated();
    std::size_t stop = pos_;
    while (stop < end_ && !std::isspace(static_cast<unsigned char>(data_[stop]))) ++stop;
    double v = 0;
    const char* first = data_ + pos_;
    // from_chars rejects a leading '+', which some writers emit.
    if (*first == '+' && stop - pos_ > 1) ++first;
    const auto [ptr, ec] = std::from_chars(first, data_ + stop, v);
    if (ec == std::errc::result_out_of_range) {
      v = std::strtod(std::string(first, data_ + stop).c_str(), nullptr);  // ±inf or denormal
    } else if (ec != std::errc() || ptr != data_ + stop) {
      // "nan"/"inf" are accepted by from_chars; anything else is garbage.
      throw FormatError(
          fmt::format("{}: '{}' at byte {} is not a number", what_,
                      std::string(data_ + pos_, std::min<std::size_t>(stop - pos_, 32)), pos_));
    }
    pos_ = stop;
    return v;
  }

  const char* data_;
  std::size_t end_;
  std::size_t pos_;
  Encoding enc_;
  const std::string& what_;
};

int findProperty(const Element& e, std::initializer_list<const char*> names) {
  for (const char* n : names)
    for (std::size_t i = 0; i < e.properties.size(); ++i)
      if (e.properties[i].name == n) return static_cast<int>(i);
  return -1;
}

}  // namespace

PlyData parsePly(const std::string& bytes, const std::string& what) {
  if (bytes.empty()) throw FormatError(fmt::format("{}: the file is empty", what));
  if (bytes.compare(0, 4, "ply\n") != 0 && bytes.compare(0, 5, "ply\r\n") != 0)
    throw FormatError(fmt::format("{}: not a PLY file (no 'ply' magic line)", what));
  const std::size_t headerEnd = bytes.find("end_header", 0);
  if (headerEnd == std::string::npos || headerEnd > (1u << 20))
    throw FormatError(fmt::format("{}: the PLY header has no end_header line", what));
  std::size_t bodyStart = bytes.find('\n', headerEnd);
  if (bodyStart == std::string::npos)
    throw FormatError(fmt::format("{}: the PLY file ends after its header", what));
  ++bodyStart;

  // === Header
  std::istringstream header(bytes.substr(0, headerEnd));
  std::string line;
  bool haveFormat = false;
  Encoding enc = Encoding::Ascii;
  std::vector<Element> elements;
  while (std::getline(header, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key.empty() || key == "ply" || key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      std::string f;
      ls >> f;
      if (f == "ascii")
        enc = Encoding::Ascii;
      else if (f == "binary_little_endian")
        enc = Encoding::BinaryLe;
      else if (f == "binary_big_endian")
        enc = Encoding::BinaryBe;
      else
        throw FormatError(fmt::format("{}: unknown PLY format '{}'", what, f));
      haveFormat = true;
    } else if (key == "element") {
      Element e;
      long long count = -1;
      ls >> e.name >> count;
      if (!ls || count < 0 || count > (1ll << 31) - 1)
        throw FormatError(fmt::format("{}: bad PLY element line '{}'", what, line));
      e.count = count;
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty())
        throw FormatError(fmt::format("{}: PLY property before any element", what));
      Property p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        if (!parseType(ct, p.countType) || !parseType(it, p.type) || p.countType == Type::Float32 ||
            p.countType == Type::Float64)
          throw FormatError(fmt::format("{}: bad PLY list property '{}'", what, line));
        p.isList = true;
      } else {
        ls >> p.name;
        if (!parseType(t, p.type))
          throw FormatError(fmt::format("{}: unknown PLY property type in '{}'", what, line));
      }
      elements.back().properties.push_back(std::move(p));
    } else {
      throw FormatError(fmt::format("{}: unknown PLY header line '{}'", what, line));
    }
  }
  if (!haveFormat) throw FormatError(fmt::format("{}: the PLY header has no format line", what));

  // Cheap size check before allocating: every row needs at least its minimal size in bytes
  // (binary) or one byte per value plus a separator (ASCII).
  {
    double needed = 0;
    for (const Element& e : elements) {
      double row = 0;
      for (const Property& p : e.properties)
        row += enc == Encoding::Ascii ? 2.0 : (p.isList ? typeSize(p.countType) : typeSize(p.type));
      needed += row * static_cast<double>(e.count);
    }
    if (needed > static_cast<double>(bytes.size() - bodyStart) + 1)
      throw FormatError(
          fmt::format("{}: the PLY header announces more data than the file holds "
                      "({} bytes after the header); the file is truncated",
                      what, bytes.size() - bodyStart));
  }

  // === Body
  PlyData out;
  Cursor cur(bytes, bodyStart, enc, what);
  std::vector<int> tris;  // flat #F·3
  std::vector<int> groups, faceLabels;
  bool haveVertex = false;
  int skippedPolygons = 0;
  for (const Element& e : elements) {
    if (e.name == "vertex") {
      if (haveVertex) throw FormatError(fmt::format("{}: two PLY vertex elements", what));
      haveVertex = true;
      const int ix = findProperty(e, {"x"}), iy = findProperty(e, {"y"}),
                iz = findProperty(e, {"z"});
      if (ix < 0 || iy < 0 || iz < 0)
        throw FormatError(fmt::format("{}: the PLY vertex element has no x, y, z", what));
      const int ir = findProperty(e, {"red", "r", "diffuse_red"});
      const int ig = findProperty(e, {"green", "g", "diffuse_green"});
      const int ib = findProperty(e, {"blue", "b", "diffuse_blue"});
      const bool colour = ir >= 0 && ig >= 0 && ib >= 0;
      const int il = findProperty(e, {"label"});
      out.mesh.V.resize(e.count, 3);
      if (colour) out.colour.resize(e.count, 3);
      if (il >= 0) out.labels.resize(e.count);
      std::vector<double> row(e.properties.size());
      for (std::int64_t v = 0; v < e.count; ++v) {
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
          const Property& p = e.properties[i];
          if (p.isList) {
            const double n = cur.read(p.countType);
            if (!(n >= 0) || n > static_cast<double>(cur.remaining()))
              throw FormatError(fmt::format("{}: bad list length in vertex {}", what, v));
            for (int k = 0; k < static_cast<int>(n); ++k) cur.read(p.type);
            row[i] = 0;
          } else {
            row[i] = cur.read(p.type);
          }
        }
        out.mesh.V.row(v) << row[ix], row[iy], row[iz];
        if (colour) {
          for (int k = 0; k < 3; ++k) {
            const int pi = k == 0 ? ir : (k == 1 ? ig : ib);
            const Type t = e.properties[pi].type;
            const double c = row[pi];
            const double scaled = t == Type::Float32 || t == Type::Float64 ? c
                                  : t == Type::UInt16                      ? c / 65535.0
                                                                           : c / 255.0;
            out.colour(v, k) = std::isfinite(scaled) ? std::clamp(scaled, 0.0, 1.0) : 0.0;
          }
        }
        if (il >= 0) {
          const double l = row[il];
          out.labels(v) = std::isfinite(l) && std::abs(l) < 2.2e9 ? static_cast<int>(l) : 0;
        }
      }
    } else if (e.name == "face") {
      const int ii = findProperty(e, {"vertex_indices", "vertex_index"});
      if (ii < 0 || !e.properties[ii].isList)
        throw FormatError(fmt::format("{}: the PLY face element has no vertex_indices list", what));
      const int ig = findProperty(e, {"group"});
      const int il = findProperty(e, {"label"});
      tris.reserve(static_cast<std::size_t>(std::min<std::int64_t>(e.count, 1 << 26)) * 3);
      std::vector<int> poly;
      for (std::int64_t f = 0; f < e.count; ++f) {
        int group = 0, label = 0;
        poly.clear();
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
          const Property& p = e.properties[i];
          if (p.isList) {
            const double n = cur.read(p.countType);
            if (!(n >= 0) || n > static_cast<double>(cur.remaining()))
              throw FormatError(fmt::format("{}: bad list length in face {}", what, f));
            for (int k = 0; k < static_cast<int>(n); ++k) {
              const double x = cur.read(p.type);
              if (static_cast<int>(i) == ii) {
                if (!(x >= 0) || x >= 2147483647.0)
                  throw FormatError(fmt::format("{}: face {} has vertex index {}", what, f, x));
                poly.push_back(static_cast<int>(x));
              }
            }
          } else {
            const double x = cur.read(p.type);
            const bool integral = std::isfinite(x) && std::abs(x) < 2.2e9;
            if (static_cast<int>(i) == ig && integral) group = static_cast<int>(x);
            if (static_cast<int>(i) == il && integral) label = static_cast<int>(x);
          }
        }
        if (poly.size() < 3) {
          ++skippedPolygons;
          continue;
        }
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {  // fan triangulation
          tris.insert(tris.end(), {poly[0], poly[k], poly[k + 1]});
          if (ig >= 0) groups.push_back(group);
          if (il >= 0) faceLabels.push_back(label);
        }
      }
    } else if (!e.properties.empty()) {
      for (std::int64_t r = 0; r < e.count; ++r)
        for (const Property& p : e.properties) {
          if (p.isList) {
            const double n = cur.read(p.countType);
            if (!(n >= 0) || n > static_cast<double>(cur.remaining()))
              throw FormatError(fmt::format("{}: bad list length in element {}", what, e.name));
            for (int k = 0; k < static_cast<int>(n); ++k) cur.read(p.type);
          } else {
            cur.read(p.type);
          }
        }
    }
  }
  if (!haveVertex) throw FormatError(fmt::format("{}: the PLY file has no vertex element", what));
  const int nv = static_cast<int>(out.mesh.V.rows());
  out.mesh.F.resize(static_cast<Eigen::Index>(tris.size() / 3), 3);
  for (std::size_t t = 0; t < tris.size() / 3; ++t)
    for (int k = 0; k < 3; ++k) {
      const int idx = tris[3 * t + k];
      if (idx >= nv)
        throw FormatError(fmt::format("{}: a face refers to vertex {} but the file has {} vertices",
                                      what, idx, nv));
      out.mesh.F(static_cast<Eigen::Index>(t), k) = idx;
    }
  if (!groups.empty())
    out.faceGroup =
        Eigen::Map<Eigen::VectorXi>(groups.data(), static_cast<Eigen::Index>(groups.size()));
  if (!faceLabels.empty())
    out.faceLabels = Eigen::Map<Eigen::VectorXi>(faceLabels.data(),
                                                 static_cast<Eigen::Index>(faceLabels.size()));
  if (skippedPolygons > 0)
    out.warnings.push_back(
        fmt::format("{}: {} faces with fewer than 3 vertices skipped", what, skippedPolygons));
  return out;
}

std::string readFileBytes(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError(fmt::format("{}: no such file; check the path", path.string()));
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw IoError(fmt::format("{}: cannot open the file; check permissions", path.string()));
  const std::streamoff size = in.tellg();
  if (size < 0) throw IoError(fmt::format("{}: cannot read the file", path.string()));
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  if (!in) throw IoError(fmt::format("{}: reading failed", path.string()));
  return bytes;
}

PlyData readPly(const std::filesystem::path& path) {
  return parsePly(readFileBytes(path), path.string());
}

}  // namespace s2p
