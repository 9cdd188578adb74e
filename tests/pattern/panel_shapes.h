// Panels built in code for the pattern tests: developable strips with known flat shapes and
// doubly curved caps with a known conformal flattening.
#pragma once

#include <Eigen/Core>

#include "core/tri_mesh.h"

namespace s2p::test {

// A disk of `rings` rings in the plane: ring k (1..rings) has 6k vertices at radius k/rings,
// vertex 0 is the centre; the rings are zipped by angle, 6-fold symmetric, counter-clockwise.
// (V.z = 0.) About 6·rings² faces.
TriMesh makePolarDisk(int rings);

// Spherical cap of the given radius and polar half-angle theta0 around +y (the pole at
// (0, radius, 0)), made by mapping makePolarDisk's radius ρ to the polar angle ρ·theta0 (rings
// equally spaced in arc length). Outward normals.
TriMesh makeSphericalCap(int rings, double radius, double theta0);

// Strip of a cylinder of radius r around the y axis: arc length width (around) × height (along
// y), nx × ny grid cells. Outward normals. Developable, flattens to a width × height rectangle.
TriMesh makeCylinderStrip(int nx, int ny, double radius, double width, double height);

// Sector of a cone with apex at the origin opening towards −y: half angle alpha, slant
// distances s0..s1 from the apex, azimuth span phiSpan; ns × nphi cells. Outward normals.
// Developable: flattens to an annulus sector of radii s0, s1 and angle phiSpan·sin(alpha).
TriMesh makeConeSector(int ns, int nphi, double alpha, double s0, double s1, double phiSpan);

// Saddle z = c·(x² − y²) over [−h, h]², n×n cells, normals towards +z (doubly curved, K < 0).
TriMesh makeSaddle(int n, double h, double c);

// Front of a torso-like surface of revolution around +y: radius r(y) = r0 + bulge·cos(2πy/h)
// (waist and chest), azimuth ±span/2 about +z, y ∈ [0, h]; nx × ny cells whose parameter-space
// vertices are jittered by `jitter` × the cell size (inner vertices only, deterministic).
// Doubly curved with K of both signs, like a garment's front panel. Outward normals.
TriMesh makeTorsoPanel(int nx, int ny, double r0, double bulge, double h, double span,
                       double jitter);

// Applies the rotation R to every vertex.
TriMesh rotated(const TriMesh& mesh, const Eigen::Matrix3d& R);

}  // namespace s2p::test
