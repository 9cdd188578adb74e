#include "synth/truth.h"

#include <array>
#include <utility>
#include <fmt/format.h>

#include "core/error.h"
#include "io/read_ply.h"
#include "io/write_mesh.h"

namespace s2p {
namespace {

nlohmann::json curveToJson(const Eigen::MatrixX3d& c) {
  nlohmann::json pts = nlohmann::json::array();
  for (Eigen::Index i = 0; i < c.rows(); ++i) pts.push_back({c(i, 0), c(i, 1), c(i, 2)});
  return pts;
}

// Typed access with errors that name the file and the entry.
struct Reader {
  const std::string& what;

  const nlohmann::json& at(const nlohmann::json& j, const char* key, const std::string& ctx) const {
    if (!j.is_object() || !j.contains(key))
      throw FormatError(fmt::format("{}: missing \"{}\" in {}", what, key, ctx));
    return j.at(key);
  }
  template <class T>
  T get(const nlohmann::json& j, const char* key, const std::string& ctx) const {
    try {
      return at(j, key, ctx).get<T>();
    } catch (const nlohmann::json::exception& e) {
      throw FormatError(fmt::format("{}: \"{}\" in {} has the wrong type ({})", what, key, ctx,
                                    e.what()));
    }
  }
  Label label(const nlohmann::json& j, const std::string& ctx) const {
    const auto s = j.is_string() ? parseLabel(j.get<std::string>()) : std::nullopt;
    if (!s) throw FormatError(fmt::format("{}: unknown label {} in {}", what, j.dump(), ctx));
    return *s;
  }
  Eigen::MatrixX3d curve(const nlohmann::json& j, const std::string& ctx) const {
    if (!j.is_array()) throw FormatError(fmt::format("{}: {} is not a list of points", what, ctx));
    Eigen::MatrixX3d c(static_cast<Eigen::Index>(j.size()), 3);
    for (std::size_t i = 0; i < j.size(); ++i) {
      const auto& p = j[i];
      if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
          !p[2].is_number())
        throw FormatError(fmt::format("{}: point {} of {} is not [x, y, z]", what, i, ctx));
      for (int k = 0; k < 3; ++k) c(static_cast<Eigen::Index>(i), k) = p[k].get<double>();
    }
    return c;
  }
};

}  // namespace

double TrueBoundary::length() const {
  double len = 0;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const Eigen::MatrixX3d& p = curves[c];
    for (Eigen::Index i = 1; i < p.rows(); ++i) len += (p.row(i) - p.row(i - 1)).norm();
    if (c < closed.size() && closed[c] && p.rows() > 2) len += (p.row(0) - p.row(p.rows() - 1)).norm();
  }
  return len;
}

const TrueBoundary* Truth::boundary(Label a, Label b) const {
  for (const TrueBoundary& tb : boundaries)
    if ((tb.a == a && tb.b == b) || (tb.a == b && tb.b == a)) return &tb;
  return nullptr;
}

const TrueGarment* Truth::garment(std::string_view name) const {
  for (const TrueGarment& g : garments)
    if (g.name == name) return &g;
  return nullptr;
}

bool Truth::hasOnePiece() const {
  for (const TrueGarment& g : garments)
    if (g.onePiece) return true;
  return false;
}

nlohmann::json boundariesToJson(const std::vector<TrueBoundary>& boundaries) {
  nlohmann::json out = nlohmann::json::array();
  for (const TrueBoundary& b : boundaries) {
    nlohmann::json curves = nlohmann::json::array();
    for (std::size_t c = 0; c < b.curves.size(); ++c)
      curves.push_back({{"closed", c < b.closed.size() && b.closed[c]},
                        {"points", curveToJson(b.curves[c])}});
    out.push_back({{"labels", {toString(b.a), toString(b.b)}},
                   {"length_m", b.length()},
                   {"curves", curves}});
  }
  return out;
}

std::vector<TrueBoundary> boundariesFromJson(const nlohmann::json& boundaries,
                                             const std::string& what) {
  const Reader r{what};
  if (!boundaries.is_array()) throw FormatError(what + ": \"boundaries\" is not a list");
  std::vector<TrueBoundary> out;
  for (std::size_t i = 0; i < boundaries.size(); ++i) {
    const std::string ctx = fmt::format("boundary {}", i);
    const auto& b = boundaries[i];
    const auto& labels = r.at(b, "labels", ctx);
    if (!labels.is_array() || labels.size() != 2)
      throw FormatError(fmt::format("{}: \"labels\" of {} is not a pair", what, ctx));
    TrueBoundary tb;
    tb.a = r.label(labels[0], ctx);
    tb.b = r.label(labels[1], ctx);
    if (tb.a == tb.b)
      throw FormatError(fmt::format("{}: {} separates \"{}\" from itself", what, ctx,
                                    toString(tb.a)));
    if (tb.b < tb.a) std::swap(tb.a, tb.b);
    const auto& curves = r.at(b, "curves", ctx);
    if (!curves.is_array())
      throw FormatError(fmt::format("{}: curves of {} is not a list", what, ctx));
    for (std::size_t c = 0; c < curves.size(); ++c) {
      const std::string cctx = fmt::format("curve {} of {}", c, ctx);
      tb.curves.push_back(r.curve(r.at(curves[c], "points", cctx), cctx));
      tb.closed.push_back(r.get<bool>(curves[c], "closed", cctx));
    }
    out.push_back(std::move(tb));
  }
  return out;
}

nlohmann::json truthToJson(const Truth& t) {
  nlohmann::json j;
  j["preset"] = t.preset;
  j["seed"] = t.seed;
  j["scan"] = t.scanFile;
  j["labelled_mesh"] = t.labelledMesh;
  j["frame"] = t.frame;
  nlohmann::json labels = nlohmann::json::object();
  for (int i = 0; i < kNumLabels; ++i) labels[toString(static_cast<Label>(i))] = i;
  j["label_codes"] = labels;
  nlohmann::json garments = nlohmann::json::array();
  for (const TrueGarment& g : t.garments) {
    nlohmann::json tg = {{"name", g.name},
                         {"type", g.type},
                         {"label", toString(g.label)},
                         {"one_piece", g.onePiece},
                         {"occludes", g.occludes},
                         {"visible_area_m2", g.visibleArea}};
    if (!g.patternType.empty()) tg["pattern"] = {{"type", g.patternType}, {"panels", g.panels}};
    garments.push_back(tg);
  }
  j["garments"] = garments;
  j["body"] = t.body;
  j["boundaries"] = boundariesToJson(t.boundaries);
  j["generator"] = t.generator;
  return j;
}

Truth truthFromJson(const nlohmann::json& j, const std::string& what) {
  const Reader r{what};
  Truth t;
  t.preset = r.get<std::string>(j, "preset", "the file");
  t.seed = r.get<std::uint64_t>(j, "seed", "the file");
  t.scanFile = r.get<std::string>(j, "scan", "the file");
  t.labelledMesh = r.get<std::string>(j, "labelled_mesh", "the file");
  if (j.contains("frame")) t.frame = r.get<std::string>(j, "frame", "the file");
  const auto& garments = r.at(j, "garments", "the file");
  if (!garments.is_array()) throw FormatError(what + ": \"garments\" is not a list");
  for (std::size_t i = 0; i < garments.size(); ++i) {
    const std::string ctx = fmt::format("garment {}", i);
    const auto& g = garments[i];
    TrueGarment tg;
    tg.name = r.get<std::string>(g, "name", ctx);
    tg.type = r.get<std::string>(g, "type", ctx);
    tg.label = r.label(r.at(g, "label", ctx), ctx);
    tg.onePiece = r.get<bool>(g, "one_piece", ctx);
    if (g.contains("occludes")) tg.occludes = r.get<std::vector<std::string>>(g, "occludes", ctx);
    if (g.contains("visible_area_m2")) tg.visibleArea = r.get<double>(g, "visible_area_m2", ctx);
    if (g.contains("pattern")) {
      const auto& p = g.at("pattern");
      tg.patternType = r.get<std::string>(p, "type", ctx + " pattern");
      tg.panels = r.get<std::vector<std::string>>(p, "panels", ctx + " pattern");
    }
    t.garments.push_back(std::move(tg));
  }
  t.body = r.at(j, "body", "the file");
  t.boundaries = boundariesFromJson(r.at(j, "boundaries", "the file"), what);
  if (j.contains("generator")) t.generator = j.at("generator");
  return t;
}

void writeTruth(const std::filesystem::path& path, const Truth& truth) {
  writeFileAtomically(path, truthToJson(truth).dump(1) + "\n");
}

Truth readTruth(const std::filesystem::path& path) {
  const std::string bytes = readFileBytes(path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(bytes);
  } catch (const nlohmann::json::exception& e) {
    throw FormatError(fmt::format("{} is not JSON: {}", path.string(), e.what()));
  }
  return truthFromJson(j, path.string());
}

}  // namespace s2p
