#include "app/drape_output.h"

#include <fmt/format.h>

#include <algorithm>

#include "app/commands.h"
#include "export/bitmap_text.h"
#include "export/pattern_sheet.h"
#include "export/preview.h"
#include "io/write_mesh.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

constexpr double kLegendMaxMm = 30;  // the colour scale's top: the p95 bound

json statsJson(const SurfaceDistanceStats& s) {
  return {{"mean_mm", s.meanMm},
          {"p95_mm", s.p95Mm},
          {"max_mm", s.maxMm},
          {"worst", {s.worst.x(), s.worst.y(), s.worst.z()}}};
}

// Copies `src` into `dst` with its top-left corner at (x, y).
void blit(Image& dst, const Image& src, int x, int y) {
  for (int r = 0; r < src.height && y + r < dst.height; ++r)
    for (int c = 0; c < src.width && x + c < dst.width; ++c)
      for (int k = 0; k < 3; ++k)
        dst.rgb[3 * ((y + r) * dst.width + x + c) + k] = src.rgb[3 * (r * src.width + c) + k];
}

void writeComparePng(const fs::path& path, const PipelineResult& run) {
  const DrapeStage& d = run.drape;
  const std::vector<Rgb> ramp = strainColours();
  std::vector<Eigen::MatrixX3d> colours(d.garments.size());
  Scene draped, scanned;
  // The scanned garment alone: fitted under it, the rest body would show through it.
  draped.meshes.push_back({&run.pattern.placement.restBody, nullptr, {215, 205, 195}});
  for (size_t g = 0; g < d.garments.size(); ++g) {
    const GarmentDrape& gd = d.garments[g];
    colours[g].resize(gd.draped.numVertices(), 3);
    for (int v = 0; v < gd.draped.numVertices(); ++v) {
      const Rgb c = colourAt(ramp, 1e3 * gd.comparison.distanceA[v] / kLegendMaxMm);
      colours[g].row(v) << c.r / 255.0, c.g / 255.0, c.b / 255.0;
    }
    draped.meshes.push_back({&gd.draped, &colours[g]});
    scanned.meshes.push_back({&gd.scanned, nullptr, {120, 150, 200}});
  }
  RenderOptions ro;
  ro.views = {View::Front, View::Back};
  ro.heightPx = 720;
  ro.captions = {"draped front", "draped back"};
  const Image a = renderScene(draped, ro);
  ro.views = {View::Front};
  ro.captions = {"scanned garment"};
  const Image b = renderScene(scanned, ro);
  const int legendPx = 60, gap = 16;
  Image out;
  out.width = a.width + gap + b.width;
  out.height = std::max(a.height, b.height) + legendPx;
  out.rgb.assign(3 * out.width * out.height, 255);
  blit(out, a, 0, 0);
  blit(out, b, a.width + gap, 0);
  // Legend: the ramp from 0 to kLegendMaxMm, ticks every 10 mm.
  const int y0 = out.height - legendPx + 8, barW = std::min(360, out.width - 40), x0 = 20;
  drawText(out, x0, y0, "distance to the scanned garment (mm; 30: 30 or more)", 2, {0, 0, 0});
  const int barY = y0 + textHeight(2) + 4;
  for (int x = 0; x < barW; ++x) {
    const Rgb c = colourAt(ramp, static_cast<double>(x) / (barW - 1));
    for (int y = barY; y < barY + 12 && y < out.height; ++y) {
      std::uint8_t* px = &out.rgb[3 * (y * out.width + x0 + x)];
      px[0] = c.r, px[1] = c.g, px[2] = c.b;
    }
  }
  for (int mm = 0; mm <= static_cast<int>(kLegendMaxMm); mm += 10) {
    const std::string label = fmt::format("{}", mm);  // the bitmap font has no '+' or '≥
    const int x = x0 + static_cast<int>((barW - 1) * mm / kLegendMaxMm);
    drawText(out, std::min(x, out.width - textWidth(label, 1) - 1), barY + 16, label, 1, {0, 0, 0});
  }
  writePng(path, out);
}

// The drape phase's rest windows: step, the fastest vertex's net speed (mm/s) and where it is.
json restWindowsJson(const DrapeResult& r) {
  json windows = json::array();
  for (const DrapeResult::RestWindow& w : r.restWindows)
    windows.push_back({{"step", w.step}, {"speed_mm_s", 1e3 * w.speed}, {"fastest", w.where}});
  return windows;
}

}  // namespace

json drapeToJson(const PipelineResult& run) {
  const DrapeStage& d = run.drape;
  if (!d.ran) return {{"ran", false}, {"warnings", d.warnings}};
  const DrapeResult& r = d.drape;
  json garments = json::array();
  for (const GarmentDrape& g : d.garments) {
    if (g.draped.numFaces() == 0) continue;
    json panels = json::array();
    for (const auto& [name, stats] : g.panels) {
      json p = statsJson(stats);
      p["panel"] = name;
      panels.push_back(p);
    }
    garments.push_back({{"garment", g.garment},
                        {"panels_draped_to_scanned", panels},
                        {"draped_to_scanned", statsJson(g.comparison.aToB)},
                        {"scanned_to_draped", statsJson(g.comparison.bToA)},
                        {"mean_mm", g.comparison.meanMm()},
                        {"p95_mm", g.comparison.p95Mm()},
                        {"max_mm", g.comparison.maxMm()},
                        {"top_drop_mm", g.topDropMm}});
  }
  json coarse = nullptr;  // the coarse drape the result started from (drape/coarse_to_fine.h)
  if (d.coarseToFine) {
    const DrapeResult& c = d.twoLevel.coarse;
    coarse = {{"vertices", d.coarseVertices},
              {"status", toString(c.status)},
              {"sew_steps", c.sewSteps},
              {"drape_steps", c.drapeSteps},
              {"stitches_sewn", c.sewnStitches},
              {"self_intersections", c.selfIntersections},
              {"rest_windows", restWindowsJson(c)},
              {"seconds", c.seconds},
              {"carried", d.twoLevel.carried},
              {"carried_max_stitch_gap_mm", 1e3 * d.twoLevel.carriedGap},
              {"carried_max_outside_mm", 1e3 * d.twoLevel.carriedOutside}};
  }
  return {{"ran", true},
          {"status", toString(r.status)},
          {"coarse", coarse},
          {"failure", r.failure},
          {"sew_steps", r.sewSteps},
          {"drape_steps", r.drapeSteps},
          {"seams_closed", r.seamsClosed},
          {"at_rest", r.settled},          // the cloth came to rest (the seams may still be open)
          {"written", drapeWritten(run)},  // drape/draped.obj and drape_compare.png
          {"stitches_sewn", r.sewnStitches},
          {"max_stitch_gap_mm", 1e3 * r.maxStitchGap},
          {"mean_stitch_gap_mm", 1e3 * r.meanStitchGap},
          {"max_strain", r.maxStrain},
          {"body_penetrations", r.bodyPenetrations},
          {"max_penetration_mm", 1e3 * r.maxPenetration},
          {"start_inside_body", r.startInsideBody},
          {"self_intersections", r.selfIntersections},
          {"rest_windows", restWindowsJson(r)},
          // GarmentCode's quality gates for a simulated garment.
          {"gates",
           {{"body_penetrations_at_most", 35},
            {"self_intersections_at_most", 300},
            {"passed", r.bodyPenetrations <= 35 && r.selfIntersections <= 300}}},
          {"vertices", r.garment.numVertices()},
          {"triangles", r.garment.numFaces()},
          {"constraints", r.numConstraints},
          {"contact_searches", r.contactSearches},
          {"constraint_solves_per_second", r.constraintSolvesPerSecond},
          {"simulation_seconds", r.seconds},
          {"seconds", d.seconds},
          {"garments", garments},
          {"warnings", d.warnings}};
}

bool drapeWritten(const PipelineResult& run) {
  return run.drape.ran && run.drape.drape.status == DrapeStatus::Settled &&
         run.drape.drape.garment.numFaces() > 0;
}

namespace {

// The cloth as one OBJ with a group per panel (a face belongs to the panel of its vertices).
void writeCloth(const fs::path& file, const PipelineResult& run) {
  const DrapeStage& d = run.drape;
  const DrapeResult& r = d.drape;
  Eigen::VectorXi group(r.garment.numFaces());
  std::vector<std::string> names;
  for (size_t c = 0; c + 1 < r.panelOffset.size(); ++c) {
    const Panel& p = run.pattern.panels.panels[d.panelOf[c]];
    names.push_back(p.garment + "_" + p.name);
  }
  for (int f = 0; f < r.garment.numFaces(); ++f)
    group[f] = static_cast<int>(std::upper_bound(r.panelOffset.begin(), r.panelOffset.end(),
                                                 r.garment.F(f, 0)) -
                                r.panelOffset.begin()) -
               1;
  MeshAttributes attrs;
  attrs.faceGroups = &group;
  attrs.groupNames = &names;
  writeObj(file, r.garment, attrs);
}

}  // namespace

void writeDrape(const fs::path& dir, const PipelineResult& run) {
  const DrapeStage& d = run.drape;
  std::error_code ignored;
  fs::remove(dir / "unsettled.obj", ignored);
  if (!drapeWritten(run)) {
    fs::remove(dir / "draped.obj", ignored);
    fs::remove(dir / "drape_compare.png", ignored);
    // A drape that ran but did not settle (seams left open, still moving): its last state, named
    // as what it is, to show where the seams stayed open (report.json says which pairs).
    const DrapeResult& r = d.drape;
    if (d.ran && r.status == DrapeStatus::NotSettled && r.garment.numFaces() > 0 &&
        r.garment.V.allFinite()) {
      fs::create_directories(dir);
      writeCloth(dir / "unsettled.obj", run);
    }
    return;
  }
  fs::create_directories(dir);
  writeCloth(dir / "draped.obj", run);
  if (!d.garments.empty()) writeComparePng(dir / "drape_compare.png", run);
}

void printDrape(const PipelineResult& run) {
  const DrapeStage& d = run.drape;
  if (!d.ran) {
    for (const std::string& w : d.warnings) fmt::print("  warning: {}\n", w);
    return;
  }
  const DrapeResult& r = d.drape;
  fmt::print(
      "drape: {} after {} sewing + {} draping steps ({:.1f} s), {} of stitches sewn, "
      "largest gap {:.2f} mm, {} body penetrations, {} self-intersections\n",
      toString(r.status), r.sewSteps, r.drapeSteps, d.seconds, r.sewnStitches, 1e3 * r.maxStitchGap,
      r.bodyPenetrations, r.selfIntersections);
  for (const GarmentDrape& g : d.garments)
    if (g.draped.numFaces() > 0)
      fmt::print(
          "  {}: draped vs scanned {:.1f} mm mean, {:.1f} mm p95, {:.1f} mm max; top {:.0f} mm "
          "below the scanned top\n",
          g.garment, g.comparison.meanMm(), g.comparison.p95Mm(), g.comparison.maxMm(),
          g.topDropMm);
  for (const std::string& w : d.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace s2p::app
