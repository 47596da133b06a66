// Parameters of every RISAS stage, named as the paper names them.
//
// Plain structs like OpenCV's ORB/SIFT parameters: defaults are the paper's
// values (or the authors' reference implementation where the paper is silent),
// validate() throws InputError (a std::invalid_argument) naming the offending
// field, and write()/read() use cv::FileStorage so a parameter file
// round-trips. read() rejects unknown names, values out of range and
// fractions in whole-number fields with InputError. The
// field names are the same in the YAML files, the tools and the ROS .cfg.
#pragma once

#include <opencv2/core.hpp>

#include <string>

namespace risas {

// Depth -> points -> normals (paper III-A step 1).
struct GeometryParams {
  // Half-width of the square window the normal is fitted over (ref: 5 -> 11x11).
  static constexpr int kDefaultNormalRadius = 5;
  int normal_radius = kDefaultNormalRadius;
  // Two 4-neighbours whose depths differ by more than this fraction of the
  // depth lie on different surfaces; windows never straddle such a jump.
  double depth_change_factor = 0.02;
  // Fewest valid points a window needs for a normal (ref: 4).
  int min_normal_points = 4;
  // Normals are fitted on a grid of normal_stride x normal_stride blocks,
  // each the mean of its points on one surface, and a pixel on that surface
  // takes its block's normal (neighbouring windows overlap almost
  // entirely). 1: a fit at every pixel. (The default stride and radius have
  // a compiled fast path.)
  static constexpr int kDefaultNormalStride = 2;
  int normal_stride = kDefaultNormalStride;

  void validate() const;
  void write(cv::FileStorage& fs) const;
  void read(const cv::FileNode& node);
};

// Keypoint detector (paper III-A steps 2-5, eq. 1).
struct DetectorParams {
  // Weight of appearance against shape in eq. 1: tau * grey + (1 - tau) * dot-product.
  double tau = 0.8;
  // Sectors per axis angle when labelling normals for the main normal.
  static constexpr int kDefaultN_s = 4;
  int n_s = kDefaultN_s;
  // Harris constant k of R = det(M) - k trace(M)^2.
  double harris_k = 0.04;
  // Gaussian pre-blur of the grey image (ref: 0.7 px).
  double gray_sigma = 1.0;
  // Gaussian smoothing of the dot-product image (px; the ref's 5).
  double dp_sigma = 5.0;
  // Gaussian window w(x, y) of eq. 1 (ref: 1 px).
  double window_sigma = 1.5;
  // Keep responses above this fraction of the frame's largest response (ref: 0.001).
  double response_threshold = 0.001;
  // Half-width of the non-maximum suppression window: 1, the ref's 3x3. A
  // wider window also removes maxima that lie on the flank of a stronger
  // response, and their counterparts in another view, where that flank is
  // weaker, are kept: they then repeat in one view only (docs/evaluation.md,
  // "The non-maximum suppression's window").
  int nms_radius = 1;
  // Cap on keypoints per frame, spread over a grid_cols x grid_rows grid.
  int max_keypoints = 500;
  // Floor on keypoints per frame: when fewer maxima than this pass
  // response_threshold, the strongest maxima of any positive response make
  // up this many (at most max_keypoints). The threshold is relative to the
  // frame's largest response, and on Kinect depth that is often an artefact
  // at a hole's edge: alone it leaves a texture-poor frame a dozen keypoints,
  // too few for a pose. A VO front end needs a minimum, as ORB-SLAM lowers
  // its FAST threshold where it finds too few corners. The default sits
  // below the counts textured frames get from the threshold (docs/
  // evaluation.md, "A floor under the relative threshold"), so that it acts
  // only where the threshold has collapsed. 0: no floor.
  int min_keypoints = 150;
  int grid_cols = 8;
  int grid_rows = 6;
  // No keypoint closer than this to the image border (px).
  int border = 8;

  void validate() const;
  void write(cv::FileStorage& fs) const;
  void read(const cv::FileNode& node);
};

// Descriptor (paper III-B: scale, neighbourhood, orientation, encoding).
struct DescriptorParams {
  // Orientation eq. 6: when the second (third) eigenvalue exceeds gamma * e1.
  double gamma = 0.8;
  // Spatial sectors, intensity-rank groups and normal groups: the descriptor
  // has n_ring * n_pie * n_bin * (n_vec + 1) dimensions (2, 8, 4, 0 -> 64;
  // the paper's 1, 8, 8, 2 -> 192; shape_weight gives another layout).
  // n_vec 0: no shape labels, every sample one label and rho_threshold
  // unused. The default: the shape labels, on
  // Kinect normals, differ between views of the same point and cost
  // matches on every set measured (docs/evaluation.md, "The shape labels").
  // n_bin 4, not the paper's 8: on a Kinect patch the order of close grey
  // levels is the sensor's noise, so finer groups move a point's votes
  // between views; the dimensions go to a second ring instead, which keeps
  // where the faces around a point lie (docs/evaluation.md, "The
  // descriptor's layout").
  int n_pie = 8;
  int n_bin = 4;
  int n_vec = 0;
  // How the shape labels enter the histogram (with n_vec >= 1). 0: eq. 8's
  // joint histogram, each (sector, intensity group) bin split by shape label.
  // > 0: a histogram of their own per spatial sector, n_ring * n_pie *
  // (n_vec + 1) bins after the intensity histogram's n_ring * n_pie * n_bin;
  // each part is L2-normalised, the shape part weighted by shape_weight, then
  // the whole normalised. A label that differs between views then moves one
  // vote of the shape part instead of a sample's whole intensity vote. Off
  // by default: it trades a few correct matches on textured recordings for
  // the texture-poor ones' (docs/evaluation.md, "The shape labels as a
  // histogram of their own").
  double shape_weight = 0.0;
  // Rings of equal area the disc is cut into, each of n_pie sectors: the
  // spatial label is (ring, sector) and the descriptor n_ring times longer.
  // 1: the paper's sectors only.
  int n_ring = 2;
  // How a sample votes. true: its vote split between the two intensity-rank
  // groups whose centres its mid-rank lies between, as SIFT's histogram
  // interpolates, so that a grey level's noise or a sub-pixel shift of the
  // keypoint moves the descriptor a little rather than moving whole votes.
  // false: one vote in its group, the paper's histogram. docs/method.md
  // (descriptor step 5, "Encoding") says what it buys.
  bool soft_binning = true;
  // How smooth a grey image the disc's samples read, as a Gaussian's sigma in
  // units of their spacing (R-bar / patch_radius pixels). A patch is sampled
  // on the same grid at every size, so at 0.5 m its samples lie 3 px apart
  // and bilinear reads of the raw image alias the surface's fine texture:
  // what they see then depends on where the grid falls. > 0: each patch reads
  // the grey pyramid level (trilinear) whose blur is this many spacings,
  // so every distance sees the pattern smoothed alike. 0: the frame's grey
  // image, the paper's sampling. docs/method.md (descriptor step 5).
  double sample_blur = 0.5;
  // The grey image's noise that the intensity ranks allow for, as a standard
  // deviation in grey levels (with soft_binning). Two samples whose grey
  // levels differ by less than the noise of a difference are not surely in
  // that order: each sample takes its expected rank under the noise, so that
  // on a patch of low contrast (a plain face, dim light) the noise moves the
  // votes little instead of reordering them. Samples further apart keep
  // their order, and with it the ranks' invariance to monotonic changes of
  // light. < 0 (-1): each frame's own noise, estimated from its grey image
  // (Immerkaer's estimator); 0: exact ranks, the paper's; > 0: this many
  // grey levels. docs/method.md (descriptor step 5).
  double grey_noise = -1.0;
  // rho-bar: normal dot products rho >= rho_threshold form one label.
  double rho_threshold = 0.9;
  // Patch radius before the ellipse fit. 0: the paper's eq. 3-4, in pixels,
  // constant for every depth below 2 m (eq. 3 truncates s to 1 there). > 0:
  // the projection of a disc of this radius in metres, R = f r / z, which
  // keeps the described surface the same at every distance.
  double support_radius = 0.04;
  // t of eq. 5: neighbours farther than this from the keypoint's 3D point (m)
  // are background and eliminated.
  double background_distance = 0.1;
  // The rotated patch is resampled to a disc of this radius (ref: 20 -> 41x41;
  // docs/method.md says what 14 gives).
  int patch_radius = 14;
  // Patch radius bounds in image pixels (ref: fall back above 50 px).
  double min_radius_px = 6.0;
  double max_radius_px = 50.0;
  // Reject a keypoint when fewer than this fraction of its disc samples are
  // foreground with a normal (ref: 0.7).
  double min_valid_fraction = 0.5;
  // Where theta comes from. true: the paper's eq. 7, the 3D direction d3D
  // projected into the image. false: the rank-weighted intensity centroid of
  // the patch, on which the descriptor matches better across viewpoints
  // (docs/evaluation.md); eq. 7's gamma rule still rejects
  // shapeless patches either way.
  bool shape_orientation = false;
  // With shape_orientation: below this angle (deg) between d3D and the
  // viewing ray d3D's projection is noise, and the intensity centroid gives
  // theta instead.
  double min_projection_angle_deg = 15.0;
  // Without shape_orientation (and where eq. 7's projection is noise): true,
  // theta from the patch's grey gradients read at its own scale
  // (gradientOrientation, SIFT's rule), which holds across a change of
  // distance; false, from the rank-weighted intensity centroid of the
  // frame's grey image (ORB's rule, on ranks), which turns with the fine
  // texture a farther view no longer resolves but costs nothing
  // (docs/evaluation.md, "The orientation across a change of distance").
  bool gradient_orientation = true;

  // The largest descriptor validate() accepts: 8 KB a keypoint. Far past it
  // a patch's few thousand samples leave nearly every bin empty, and one
  // frame's descriptors would run to hundreds of megabytes.
  static constexpr int kMaxDimension = 2048;
  // Whether the shape labels have a histogram of their own (shape_weight).
  bool ownShapeHistogram() const { return shape_weight > 0.0; }
  int dimension() const {
    return n_ring * n_pie * (ownShapeHistogram() ? n_bin + n_vec + 1 : n_bin * (n_vec + 1));
  }
  // What the descriptor's columns count, "n_ring=2 n_pie=8 n_bin=4 n_vec=0",
  // and " shape_weight=W" after it with a shape histogram of its own:
  // descriptors compare only with descriptors of the same layout, and two
  // layouts can share a dimension (2 x 8 x 4 and 1 x 8 x 8 are both 64).
  std::string layout() const;
  void validate() const;
  void write(cv::FileStorage& fs) const;
  void read(const cv::FileNode& node);
};

// Nearest-neighbour distance ratio matching (paper IV-A).
struct MatchParams {
  double ratio = 0.8;
  bool cross_check = false;

  void validate() const;
  void write(cv::FileStorage& fs) const;
  void read(const cv::FileNode& node);
};

// RANSAC over 3-point samples with Umeyama refinement.
struct MotionParams {
  double inlier_threshold = 0.03;  // metres
  int max_iterations = 2000;
  double confidence = 0.999;
  int min_inliers = 6;
  unsigned int seed = 0x5eed;

  void validate() const;
  void write(cv::FileStorage& fs) const;
  void read(const cv::FileNode& node);
};

// Frame-to-keyframe visual odometry (risas::Odometry).
struct OdometryParams {
  // Fewest RANSAC inliers for a frame to count as tracked.
  int min_inliers = 12;
  // A tracked frame becomes the keyframe when its inliers fall below this,
  // or it has moved farther than these from the keyframe.
  int keyframe_inliers = 50;
  double keyframe_translation = 0.10;  // metres
  double keyframe_rotation_deg = 10.0;
  // Refine each frame's RANSAC motion on the keyframe points' reprojection
  // errors into the frame (refineByReprojection) with this Huber width in
  // normalised image units (pixels / focal length); 0: keep the Umeyama
  // refit of the 3D points (the pose-recovery evaluation's). The depth's
  // noise lies along the rays: the 3D refit takes all of it, the
  // reprojection only the keyframe's (docs/odometry.md).
  double reprojection_huber = 0.004;
  // Variance (m^2, rad^2) reported for each axis while lost, as rtabmap's
  // odometry does: large enough that a filter ignores the pose.
  double lost_variance = 9999.0;

  void validate() const;
  void write(cv::FileStorage& fs) const;
  void read(const cv::FileNode& node);
};

// Everything together, as stored in a parameter file (top-level nodes
// geometry, detector, descriptor, match, motion, odometry; any may be
// absent).
struct RisasParams {
  GeometryParams geometry;
  DetectorParams detector;
  DescriptorParams descriptor;
  MatchParams match;
  MotionParams motion;
  OdometryParams odometry;

  void validate() const;
  void write(cv::FileStorage& fs) const;
  void read(const cv::FileNode& root);

  // Throws std::runtime_error when the file cannot be read or parsed and
  // std::invalid_argument (InputError) when a value is out of range.
  static RisasParams load(const std::string& path);
  void save(const std::string& path) const;
};

}  // namespace risas
