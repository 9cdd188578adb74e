#include "body/mpfb2_files.h"

#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.h"

namespace s2p {
namespace {

// Whole file, decompressed when gzipped (zlib reads plain files transparently).
std::string readMaybeGz(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw IoError("MPFB2 folder: missing file " + file.string() +
                  " (point the program at a complete MPFB2/MakeHuman data folder)");
  gzFile gz = gzopen(file.string().c_str(), "rb");
  if (!gz) throw IoError("MPFB2 folder: cannot open " + file.string());
  std::string out;
  char buf[1 << 16];
  for (;;) {
    const int n = gzread(gz, buf, sizeof buf);
    if (n < 0) {
      gzclose(gz);
      throw FormatError("MPFB2 folder: " + file.string() +
                        " is not a readable gzip file (corrupt or truncated)");
    }
    if (n == 0) break;
    out.append(buf, static_cast<size_t>(n));
  }
  gzclose(gz);
  return out;
}

std::string readText(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw IoError("MPFB2 folder: missing file " + file.string() +
                  " (point the program at a complete MPFB2/MakeHuman data folder)");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError("MPFB2 folder: cannot open " + file.string());
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const char* skipSpace(const char* p, const char* end) {
  while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  return p;
}

// Parses one number at p (after spaces); false when there is none.
template <class T>
bool parseNumber(const char*& p, const char* end, T& value) {
  p = skipSpace(p, end);
  if (p < end && *p == '+') ++p;
  const auto r = std::from_chars(p, end, value);
  if (r.ec != std::errc()) return false;
  p = r.ptr;
  return true;
}

[[noreturn]] void malformed(const std::filesystem::path& file, int line, const std::string& what) {
  throw FormatError("MPFB2 folder: " + file.string() + " line " + std::to_string(line) + ": " +
                    what + " (the file is damaged; restore it from the MPFB2 data)");
}

}  // namespace

Mpfb2Obj readMpfb2Obj(const std::filesystem::path& file) {
  const std::string text = readText(file);
  Mpfb2Obj obj;
  std::vector<Eigen::Vector3d> verts;
  std::vector<std::set<int>> groupSets;
  int group = -1;
  const char* p = text.data();
  const char* end = p + text.size();
  int line = 0;
  while (p < end) {
    const char* eol = std::find(p, end, '\n');
    ++line;
    const char* q = skipSpace(p, eol);
    if (q + 1 < eol && q[0] == 'v' && q[1] == ' ') {
      Eigen::Vector3d v;
      q += 2;
      for (int k = 0; k < 3; ++k)
        if (!parseNumber(q, eol, v[k])) malformed(file, line, "vertex needs three numbers");
      if (!v.allFinite()) malformed(file, line, "non-finite vertex coordinate");
      verts.push_back(v);
    } else if (q + 1 < eol && q[0] == 'f' && q[1] == ' ') {
      std::vector<int> face;
      q += 2;
      for (;;) {
        q = skipSpace(q, eol);
        if (q >= eol) break;
        int idx = 0;
        if (!parseNumber(q, eol, idx)) malformed(file, line, "face index is not a number");
        if (idx < 0) idx = static_cast<int>(verts.size()) + idx + 1;  // OBJ relative index
        if (idx < 1 || idx > static_cast<int>(verts.size()))
          malformed(file, line, "face index " + std::to_string(idx) + " out of range");
        face.push_back(idx - 1);
        while (q < eol && *q != ' ' && *q != '\t') ++q;  // skip /vt/vn
      }
      if (face.size() < 3) malformed(file, line, "face with fewer than 3 vertices");
      if (group < 0) {
        obj.groups.push_back("default");
        groupSets.emplace_back();
        group = 0;
      }
      for (int v : face) groupSets[group].insert(v);
      obj.faces.push_back(std::move(face));
      obj.faceGroup.push_back(group);
    } else if (q + 1 < eol && q[0] == 'g' && (q[1] == ' ' || q[1] == '\t')) {
      std::string name(skipSpace(q + 1, eol), eol);
      while (!name.empty() && (name.back() == ' ' || name.back() == '\r')) name.pop_back();
      auto it = std::find(obj.groups.begin(), obj.groups.end(), name);
      group = static_cast<int>(it - obj.groups.begin());
      if (it == obj.groups.end()) {
        obj.groups.push_back(name);
        groupSets.emplace_back();
      }
    }
    p = eol < end ? eol + 1 : end;
  }
  if (verts.empty() || obj.faces.empty())
    throw FormatError("MPFB2 folder: " + file.string() + " has no vertices or no faces");
  obj.V.resize(static_cast<Eigen::Index>(verts.size()), 3);
  for (size_t i = 0; i < verts.size(); ++i) obj.V.row(static_cast<Eigen::Index>(i)) = verts[i];
  for (size_t g = 0; g < obj.groups.size(); ++g)
    obj.groupVertices[obj.groups[g]].assign(groupSets[g].begin(), groupSets[g].end());
  return obj;
}

Mpfb2Target readMpfb2Target(const std::filesystem::path& file, int numVertices) {
  const std::string text = readMaybeGz(file);
  Mpfb2Target t;
  const char* p = text.data();
  const char* end = p + text.size();
  int line = 0;
  while (p < end) {
    const char* eol = std::find(p, end, '\n');
    ++line;
    const char* q = skipSpace(p, eol);
    if (q < eol && *q != '#') {
      int idx = 0;
      Eigen::Vector3d d;
      if (!parseNumber(q, eol, idx) || !parseNumber(q, eol, d[0]) || !parseNumber(q, eol, d[1]) ||
          !parseNumber(q, eol, d[2]))
        malformed(file, line, "expected `vertex dx dy dz`");
      if (idx < 0 || idx >= numVertices)
        malformed(file, line,
                  "vertex " + std::to_string(idx) + " out of range (base mesh has " +
                      std::to_string(numVertices) + ")");
      if (!d.allFinite()) malformed(file, line, "non-finite offset");
      if (skipSpace(q, eol) != eol) malformed(file, line, "trailing characters");
      t.index.push_back(idx);
      t.delta.push_back(d);
    }
    p = eol < end ? eol + 1 : end;
  }
  return t;
}

nlohmann::json readJsonFile(const std::filesystem::path& file) {
  const std::string text = readText(file);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw FormatError("MPFB2 folder: " + file.string() + " is not valid JSON (" + e.what() + ")");
  }
}

}  // namespace s2p
