// A small ray-cast RGB-D renderer: textured planes, boxes and spheres at
// known poses, rendered with exact depth and normals. Tests use it to check
// geometry, detection and invariances against ground truth; the demo and the
// benchmark use it where no camera or dataset is at hand.
#pragma once

#include "risas/intrinsics.hpp"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <optional>
#include <vector>

namespace risas {

struct Material {
  bool textured = true;       // a random-shape texture fixed to the surface, else a uniform albedo
  double albedo = 0.6;        // grey level / 255 when untextured, contrast scale when textured
  double texels_per_metre = 700.0;
  int texture_seed = 1;       // different seeds, different textures
};

struct SyntheticRender {
  cv::Mat bgr;       // CV_8UC3
  cv::Mat depth_mm;  // CV_16UC1, 0 where nothing was hit
  cv::Mat normals;   // CV_32FC3 camera frame, facing the camera; 0 where nothing was hit
};

class SyntheticScene {
 public:
  // A rectangle of 2 half_width x 2 half_height in the x-y plane of its pose.
  void addPlane(const Eigen::Isometry3d& world_T_plane, double half_width, double half_height, const Material& material);
  // A box with the given half extents along the axes of its pose.
  void addBox(const Eigen::Isometry3d& world_T_box, const Eigen::Vector3d& half_extents, const Material& material);
  void addSphere(const Eigen::Vector3d& centre, double radius, const Material& material);

  // Lambertian shading plus ambient light; off, every surface shows its
  // albedo alone (shape leaves no trace in the grey image). The light sits
  // at the camera unless setLightDirection fixes it in the world: a light
  // at the camera changes a surface's brightness as the camera moves, and
  // on a plain surface its quantised shading draws bands that move with
  // the camera, features a motion estimate would take for still ones.
  void setLighting(bool enabled) { lighting_ = enabled; }
  // A distant light fixed in the world, as a room's is: `towards_light` in
  // world axes, any length but finite and non-zero (InputError otherwise).
  void setLightDirection(const Eigen::Vector3d& towards_light);

  SyntheticRender render(const Intrinsics& intrinsics, cv::Size size, const Eigen::Isometry3d& world_T_camera) const;

  // The demo's scene: a textured wall and floor, textured and untextured
  // boxes, a sphere, around the world origin, about 2 m across.
  static SyntheticScene demo();
  // The demo's camera path: on a circle of 1.5 m around the scene, 1 m up,
  // looking at its middle; angle 0 looks along +y at the wall.
  static Eigen::Isometry3d demoCamera(double angle_rad);

 private:
  struct Primitive {
    enum class Kind { Plane, Box, Sphere } kind;
    Eigen::Isometry3d world_T_local;  // for a sphere: translation = centre
    Eigen::Vector3d half_extents;     // plane: (hw, hh, 0); sphere: (r, r, r)
    Material material;
    int texture = -1;                 // index into textures_, -1 when untextured
  };
  struct Hit;
  std::vector<Primitive> primitives_;
  std::vector<cv::Mat> textures_;
  bool lighting_ = true;
  std::optional<Eigen::Vector3d> towards_light_;  // unit, world axes; none: the light sits at the camera

  int textureFor(const Material& material);
};

// Camera pose (optical frame: z forward, x right, y down) at `eye` looking at
// `target`, with `up` pointing up in the image.
Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                         const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

// A Kinect-like 640x480 camera.
Intrinsics syntheticIntrinsics();

}  // namespace risas
