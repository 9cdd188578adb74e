// The pattern in GarmentCode's specification format (Korosteleva & Sorkine-Hornung 2023;
// ../shared/research/F-patterns.md (a)): what GarmentCode's loader, its box mesher and
// simulator read. Panels as loops of straight and cubic edges with vertices in cm, the control
// points in "relative" coordinates (along the edge, across it, in units of its length),
// placed by a translation (cm) and XYZ Euler rotation (degrees, R = Rz·Ry·Rx) around the rest
// body, stitches edge to edge.
//
// A GarmentCode stitch joins one edge to one edge, while our seams are Bézier chains whose
// segments need not break at the same places on both sides; every seam edge is therefore cut
// exactly (de Casteljau) at its partner's breaks too, so both sides have the same number of
// pieces, stitched piece by piece.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "pattern/flat_pattern.h"
#include "pattern/panels.h"
#include "pattern/placement.h"

namespace s2p {

// GarmentCode's name of a panel: "<garment>_<panel>" ("upper_front"), unique in a pattern.
std::string garmentCodePanelName(const Panel& panel);

// The XYZ Euler angles (degrees) GarmentCode turns into R = Rz(γ)·Ry(β)·Rx(α): (α, β, γ).
Eigen::Vector3d eulerXyzDegrees(const Eigen::Matrix3d& R);

// The whole specification: {"pattern": {"panels", "stitches", "panel_order"}, "parameters": {},
// "parameter_order": [], "properties": {...}}. Only placed panels, and stitches between them.
nlohmann::json garmentCodeSpecification(const PanelsResult& panels, const FlatPatternResult& flat,
                                        const Placement& placement, const StitchSet& stitches);

}  // namespace s2p
