// Raw-scan degradations of a synthetic scan (issue 17's realistic family): what a photogrammetry
// app or a camera rig exports besides the person's surface. Applied after the colours, so every
// degradation keeps each remaining vertex's colour, label and rest position:
//   - small holes at random places (specks no camera saw), each a disc of faces;
//   - the legs' skin under a free-hanging hem left unseen (the rig cannot look up the skirt):
//     the cap under the hem and the thighs up to `unseenBelowHem` below it are dropped, so the
//     legs become pieces of their own; holes along the hem;
//   - floor remnants: flat, nearly horizontal patches just under the soles, reaching beyond the
//     feet (separate pieces);
//   - texture charts: the faces split into charts and every vertex on a chart border duplicated
//     once per chart (as an OBJ/GLB exporter does at UV seams), so the mesh arrives as many
//     pieces that share positions;
//   - coordinates rounded to a grid (1 mm in a phone app's export);
//   - shoes as pieces of their own and fins (an image-to-3D tool's GLB): a triangle standing on
//     an edge of the surface makes that edge non-manifold.
// All lengths in metres.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

namespace s2p {

struct SynthScan;

struct RawScanOptions {
  int smallHoles = 0;              // holes at random surface points, [0, 400]
  double smallHoleRadius = 0.012;  // m; each hole's radius drawn in [0.6, 1.4]× this
  bool unseenUnderHem = false;     // legs under a free-hanging lower garment unseen (see above)
  double unseenBelowHem = 0.04;    // m of leg below the hem's lowest point also unseen
  int hemHoles = 0;                // holes on the lower garment within 3 cm of its hem, [0, 40]
  int floorPatches = 0;            // floor remnants around the feet, [0, 8]
  double floorPatchSize = 0.22;    // m, side of each (irregular) patch
  double floorGap = 0.006;         // m between the lowest point of the scan and the floor
  int textureCharts = 0;           // 0 or 1: no split; else faces split into about this many
  double quantisation = 0;         // m grid the coordinates are rounded to (0: none)
  bool detachShoes = false;        // the shoes' rim faces dropped: each shoe a piece of its own
  int fins = 0;                    // non-manifold edges: a 6 mm fin on this many edges, [0, 200]
  bool any() const {
    return smallHoles > 0 || unseenUnderHem || hemHoles > 0 || floorPatches > 0 ||
           textureCharts > 1 || quantisation > 0 || detachShoes || fins > 0;
  }
};

// What degradeScan did.
struct RawScanStats {
  int holes = 0;               // small and hem holes cut
  int unseenFaces = 0;         // faces dropped under the hem
  int floorFaces = 0;          // faces added as floor remnants
  int charts = 0;              // texture charts
  int duplicatedVertices = 0;  // vertex copies made at chart borders
  int detachedFaces = 0;       // shoe rim faces dropped
  int fins = 0;                // fin faces added (each makes one edge non-manifold)
};

nlohmann::json rawScanOptionsToJson(const RawScanOptions& options);
// Missing entries keep their defaults; bad ones → InputError.
RawScanOptions rawScanOptionsFromJson(const nlohmann::json& json);
// Out-of-range values → InputError naming them.
void validateRawScanOptions(const RawScanOptions& options);

// Degrades `scan` in place (mesh, colours, vertex and face labels, rest positions, layers).
// Floor faces are labelled Other, layer −1. The truth's garments and boundaries are kept as they
// were (like the existing scanner holes, a boundary stretch a hole swallows stays in the truth),
// except boundary curves with the gap cap, which no longer exists when the hem is unseen.
// Deterministic for a given seed.
RawScanStats degradeScan(SynthScan& scan, const RawScanOptions& options, std::uint64_t seed);

}  // namespace s2p
