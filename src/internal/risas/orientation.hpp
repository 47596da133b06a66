// Paper III-B-2: dominant orientation of a keypoint's patch.
#pragma once

#include "risas/encoding.hpp"
#include "risas/geometry.hpp"
#include "risas/intrinsics.hpp"
#include "risas/neighbourhood.hpp"
#include "risas/params.hpp"

namespace risas {

// Which branch of eq. 7 (or the fallback) gave theta.
enum class OrientationSource {
  Rejected,        // e2 > gamma e1 and e3 > gamma e1: no distinctive shape
  PatchNormal,     // e2 > gamma e1, e3 <= gamma e1: d3D = v1 x v2
  MajorAxis,       // otherwise: d3D = v1
  IntensityCentroid,  // d3D (nearly) along the viewing ray: its projection is noise
};

struct Orientation {
  OrientationSource source = OrientationSource::Rejected;
  double theta = 0.0;  // radians, angle of d2D to the image u axis (v pointing down)
};

// PCA of the kept 3D points (e1 >= e2 >= e3, v1, v2, v3) and eq. 7's gamma
// rule reject shapeless patches. Otherwise theta comes from
//  - with params.shape_orientation, the paper: d3D projected into the image
//    at k_i. An eigenvector has no sign of its own, so one is chosen
//    deterministically: v1 x v2 faces the camera, v1 points to the side of the
//    patch with more intensity mass. When d3D lies within
//    min_projection_angle_deg of the viewing ray (a patch facing the camera)
//    its projection is noise and the intensity centroid decides;
//  - without, the rank-weighted intensity centroid (ORB's orientation on
//    ranks, so monotonic illumination changes cannot turn it).
Orientation dominantOrientation(const Neighbourhood& neighbourhood, const Intrinsics& intrinsics,
                                const DescriptorParams& params);

// Whether the theta a descriptor keeps can depend on the neighbourhood's
// intensity centroid: with shape_orientation (an eigenvector's sign, the
// fallback), or without gradient_orientation (theta itself). Otherwise the
// gradients replace the centroid's theta, and selectNeighbourhood may leave
// it out.
bool intensityCentroidNeeded(const DescriptorParams& params);

// theta from the patch's grey gradients at the patch's own scale
// (descriptor.gradient_orientation), SIFT's orientation assignment (Lowe
// 2004, section 5) on the descriptor's sample grid: the disc of radius_px,
// unrotated, patch_radius samples per radius, read where the pyramid's blur
// is kOrientationBlur sample spacings (encoding.hpp). Each sample's
// gradient, from its four grid neighbours, votes its magnitude, weighted by
// a Gaussian as wide as the disc, into 36 bins of 10 degrees; the histogram
// is smoothed, and theta is the highest bin's angle refined by a parabola
// through it and its neighbours. A sample votes when it and its neighbours
// are counted as the encoder counts samples (a normal, foreground by
// eq. 5) and no background sample lies within the blur's reach: there a
// gradient would point at the background. Radians, v pointing down, as
// Orientation::theta; 0 when nothing votes.
double gradientOrientation(const GreyPyramid& grey, const FrameGeometry& geometry, const Neighbourhood& neighbourhood,
                           float radius_px, const DescriptorParams& params);

}  // namespace risas
