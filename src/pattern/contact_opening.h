// Fused contacts (beyond the paper; issue 14). Where an arm hangs against the trunk a scan shows
// only the outer cloth: the sleeve's underside and the trunk's side under the arm are pressed
// together in the contact and hidden, and the sleeve's outer cloth meets the trunk's along a
// crease, one in front of the contact and one behind it, joined below it. Every curve that parts
// sleeve from trunk then runs down that crease (armholeFolds): the sleeve comes out as the
// crescent the cameras saw and the bodice with a scoop down to the cuff.
//
// openFusedContacts opens the contact. The armhole seam's loop around an arm is cut along its
// crease part: the stretch below the top of the fold it follows or the fitted body's armpit,
// whichever is lower (above the armpit arm and torso are one, and a fold there is the arm's
// root, where an armhole belongs). The cut leaves two lips, the sleeve's and the trunk's. Each lip
// is closed with the cloth the contact hid: a patch spanning the crease and the line under the arm
// between the crease's two tops (the contact's top, at the armpit), the sleeve's underside on the
// sleeve's lip and the side under the arm on the trunk's. The two patches share that line, so the
// sleeve joins the trunk all round its armhole as an unfused garment's does. Both lie in the
// contact (a harmonic fill of the crease loop over its best-fit plane, meshed by remeshPanel): two
// layers pressed together, held `separation` apart in the middle, the sleeve's towards the arm. The
// seams are then found again on the completed garment, where the armhole can pass under the arm.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "core/tri_mesh.h"
#include "pattern/body_frame.h"
#include "pattern/seam_lines.h"

namespace s2p {

struct ContactOpeningOptions {
  // A fold reaching less far down than this (m) is a rounded armpit, not a contact (the same
  // measure as SeamOptions::creaseReportDrop).
  double minDrop = 0.03;
  // m between the middles of the two hidden layers (they meet at the crease and under the arm).
  double separation = 0.004;
  // The patches' mesh spacing: the garment's median edge length, clamped to this range (m).
  double minSpacing = 0.003, maxSpacing = 0.015;
  // Hints (ContactOpening::hints) where a patch's bump is at least this, about hintSpacing (m)
  // apart.
  double hintBump = 0.5, hintSpacing = 0.02;
};

struct OpenedContact {
  std::string side;         // "left", "right"
  double creaseLength = 0;  // m of the armhole's loop cut open
  double drop = 0;          // m from the contact's top down to the crease's lowest point
  double topWidth = 0;      // m: the line under the arm between the crease's two tops
  double sleeveArea = 0;    // m² of the sleeve's underside supplied
  double trunkArea = 0;     // m² of the side under the arm supplied
};

struct ContactOpening {
  TriMesh mesh;                // the garment, opened and completed (the input when none opened)
  Eigen::VectorXi faceOrigin;  // #F: the scan face of each face (a patch's: its lip's face)
  std::vector<OpenedContact> opened;
  // The supplied cloth's middles, about hintSpacing apart: the sleeve's underside −1, the side
  // under the arm +1 (for estimateSeams on the completed garment; the two layers lie a few
  // millimetres apart, and nothing else says which is which).
  std::vector<ArmholeHint> hints;
  std::vector<std::string> notes;  // contacts found and left fused, and why
};

// garment: the cut garment (consistently oriented manifold); faceOrigin: its faces' scan faces;
// armhole: its armhole seam (SeamKind::Armhole) estimated on it; armpit: the posed fitted body's
// armpit heights, left and right (armpitHeight; NaN: not known), which bound the contact from
// above. A seam that is not kept, or follows no fold reaching minDrop down and minDrop below the
// armpit, leaves the garment as it is.
ContactOpening openFusedContacts(const TriMesh& garment, const Eigen::VectorXi& faceOrigin,
                                 const SeamLine& armhole, const std::array<double, 2>& armpit,
                                 const BodyFrame& frame, const SeamOptions& seamOptions,
                                 const ContactOpeningOptions& options = {});

}  // namespace s2p
