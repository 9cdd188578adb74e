// Sewing and draping at two resolutions. A pattern remeshed at its default 10 mm edge has ~40k
// vertices for a t-shirt and trousers, and XPBD at one iteration per substep needs hundreds of
// steps to sew it and bring it to rest (1166 s on the 2 cores, bench/RESULTS.md "Drape IV"): the
// number of steps grows with the resolution as well as the cost of each. The same pattern remeshed
// coarser (a tenth of the vertices) sews and settles in seconds. Its drape is carried onto the
// fine mesh through the flat pattern both share: each fine vertex's 2D position is located in
// its panel's coarse 2D mesh, and its start is the draped coarse triangle's point at the same
// barycentric weights. The fine mesh so starts sewn (stitched partners land on the same welded
// coarse seam) and hanging, and a short drape at its own resolution settles what the coarse mesh
// could not represent (folds finer than its edges, the contact with the body between its
// vertices). The fine drape is the result: its figures, seams and rest are judged as always.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "drape/drape.h"

namespace s2p {

struct CoarseToFineOptions {
  int fineMinSteps = 20;  // steps of the fine drape at least (two rest windows of 10)
  // Its budget: the cloth starts near its rest, but the fine mesh may still have to work loose
  // where the coarse one left layers tangled (arms_down's armholes: a fold sliding out along the
  // sleeve's seam for 100 steps before the cloth came to rest at step 150).
  int fineMaxSteps = 300;
  int fineSewSteps = 30;  // budget for stitch pairs the carrying left open (none: see below)
  int fineSubsteps = 4;   // XPBD substeps per step of the fine drape; 0: DrapeOptions' own
  // 1/s: the fine drape's damping (0: DrapeOptions' own). Without gravity it only relaxes the
  // carried drape to the fine mesh's own rest and contacts; heavy damping stops it creeping
  // (the trousers' hems crept at 1–3 cm/s for 70 steps at 4/s, at rest after 50 at 20/s).
  double fineDamping = 20.0;
  // Gravity in the fine drape. Off by default: the coarse drape already hangs the cloth, and the
  // fine mesh relaxes to its own pattern (stretch, bending) and contacts from there. On, a fine
  // mesh's single-sweep solver must carry the hanging load through corners of a few small
  // triangles (the neck ends of the shoulder seams stretched past 3× within 12 steps at 6
  // substeps, 2.3× at 12; bench/RESULTS.md "Drape V").
  bool fineGravity = false;
  // Metres: a coarse drape that came to rest with stitch pairs still open (their sewing stalled
  // where three or four panels meet, a crotch or a waist under a hem, held apart by the cloth's
  // own contacts) is carried when its widest open pair is at most this: half a coarse edge (the
  // default 30 mm), so the fine mesh, which starts every stitched group at its mean, closes it
  // within one triangle. The coarse warnings stay in the report; the fine drape is judged as
  // always. Wider gaps (a sleeve not closed round its arm) are not a drape to carry.
  double maxCarriedGap = 0.015;
};

struct CoarseToFineDrape {
  DrapeResult coarse;     // the coarse mesh sewn and draped
  DrapeResult fine;       // the fine mesh from the carried drape (the coarse result when the coarse
                          // drape did not settle: nothing to carry)
  bool carried = false;   // the fine mesh was started from the coarse drape
  double carriedGap = 0;  // metres: the widest stitch gap of the fine mesh as carried (the
                          // partners then start at their mean: one point of the sewn seam)
  double carriedOutside = 0;  // metres: farthest a fine vertex lies outside its coarse panel (2D)
  double seconds = 0;         // both drapes and the carrying
};

// The fine panels' start carried from a drape of the coarse ones: per panel, fine.panels[p]
// (rest2d) located in coarse.panels[p] (rest2d, F), its point on draped[p] (#V of the coarse
// panel × 3). Both inputs must list the same panels, each in the same 2D frame. outside: the
// farthest a fine vertex lies outside its coarse panel in 2D (a curved outline sampled less
// densely), metres. Throws InputError when the panels do not correspond.
std::vector<Eigen::MatrixX3d> carryDrape(const DrapeInput& coarse,
                                         const std::vector<Eigen::MatrixX3d>& draped,
                                         const DrapeInput& fine, double* outside = nullptr);

// Sews and drapes `coarse` with `options`, carries the drape onto `fine` and drapes it from there
// (options with startsDraped and the fine budgets). fine and coarse: the same pattern at two
// resolutions (same panels, same 2D frames, each with its own stitches).
// progress (optional): the phases of both drapes (runDrape), labelled coarse and fine.
CoarseToFineDrape runDrapeCoarseToFine(const DrapeInput& fine, const DrapeInput& coarse,
                                       const DrapeOptions& options = {},
                                       const CoarseToFineOptions& c2f = {},
                                       Progress* progress = nullptr);

}  // namespace s2p
