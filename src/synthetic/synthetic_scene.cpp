#include "risas/synthetic_scene.hpp"

#include "risas/errors.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace risas {

struct SyntheticScene::Hit {
  double t = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal_world;
  Eigen::Vector2d surface;  // texture coordinates on the surface, metres
  const Primitive* primitive = nullptr;
};

namespace {

constexpr double kEps = 1e-9;

cv::Mat makeTexture(int seed) {
  cv::RNG rng(static_cast<uint64>(seed) * 7919u + 17u);
  // One draw per statement: the arguments of one call are evaluated in an
  // order each compiler chooses (GCC's right to left, clang's left to
  // right), which rendered another texture with clang. This is GCC's order,
  // in which the tests' scenes were made.
  const auto point = [&rng](int lo, int hi) {
    const int y = rng.uniform(lo, hi);
    const int x = rng.uniform(lo, hi);
    return cv::Point(x, y);
  };
  cv::Mat texture(512, 512, CV_8UC1, cv::Scalar(rng.uniform(90, 170)));
  for (int i = 0; i < 90; ++i) {
    const cv::Scalar grey(rng.uniform(0, 256));
    const cv::Point c = point(0, 512);
    switch (rng.uniform(0, 3)) {
      case 0: {
        const cv::Point d = point(8, 60);
        cv::rectangle(texture, c - d, c + d, grey, cv::FILLED);
        break;
      }
      case 1: {
        const double angle = rng.uniform(0.0, 180.0);
        const cv::Point axes = point(6, 40);
        cv::ellipse(texture, c, cv::Size(axes.x, axes.y), angle, 0, 360, grey, cv::FILLED, cv::LINE_AA);
        break;
      }
      default: {
        const cv::Point a = point(-60, 60);
        const cv::Point b = point(-60, 60);
        const cv::Point tri[3] = {c, c + a, c + b};
        cv::fillConvexPoly(texture, tri, 3, grey, cv::LINE_AA);
      }
    }
  }
  cv::GaussianBlur(texture, texture, cv::Size(), 1.0);
  return texture;
}

double sampleTexture(const cv::Mat& texture, const Eigen::Vector2d& surface, double texels_per_metre) {
  const double x = surface.x() * texels_per_metre, y = surface.y() * texels_per_metre;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double a = x - x0, b = y - y0;
  const auto at = [&](int r, int c) {
    const int n = texture.rows;
    return static_cast<double>(texture.at<uchar>(((r % n) + n) % n, ((c % n) + n) % n));
  };
  return (1 - b) * ((1 - a) * at(y0, x0) + a * at(y0, x0 + 1)) + b * ((1 - a) * at(y0 + 1, x0) + a * at(y0 + 1, x0 + 1));
}

}  // namespace

int SyntheticScene::textureFor(const Material& material) {
  if (!material.textured) return -1;
  textures_.push_back(makeTexture(material.texture_seed));
  return static_cast<int>(textures_.size()) - 1;
}

void SyntheticScene::addPlane(const Eigen::Isometry3d& world_T_plane, double half_width, double half_height,
                              const Material& material) {
  primitives_.push_back({Primitive::Kind::Plane, world_T_plane, {half_width, half_height, 0.0}, material,
                         textureFor(material)});
}

void SyntheticScene::addBox(const Eigen::Isometry3d& world_T_box, const Eigen::Vector3d& half_extents,
                            const Material& material) {
  primitives_.push_back({Primitive::Kind::Box, world_T_box, half_extents, material, textureFor(material)});
}

void SyntheticScene::addSphere(const Eigen::Vector3d& centre, double radius, const Material& material) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = centre;
  primitives_.push_back({Primitive::Kind::Sphere, pose, Eigen::Vector3d::Constant(radius), material,
                         textureFor(material)});
}

void SyntheticScene::setLightDirection(const Eigen::Vector3d& towards_light) {
  const double length = towards_light.stableNorm();  // (1e300, 1e300, 0) is a direction too
  if (!std::isfinite(length) || length == 0.0) throw InputError("the light's direction must be finite and non-zero");
  towards_light_ = towards_light / length;
}

SyntheticRender SyntheticScene::render(const Intrinsics& K, cv::Size size, const Eigen::Isometry3d& world_T_camera) const {
  K.validate();
  SyntheticRender out;
  out.bgr.create(size, CV_8UC3);
  out.depth_mm.create(size, CV_16UC1);
  out.normals.create(size, CV_32FC3);
  const Eigen::Matrix3d camera_R_world = world_T_camera.linear().transpose();
  const Eigen::Vector3d eye = world_T_camera.translation();

  // Per primitive, once for all rays: its local frame, the eye in it, and a
  // bounding sphere (world) that lets most rays skip it with one test.
  struct Prepared {
    Eigen::Matrix3d local_R_world;
    Eigen::Vector3d eye_local;
    Eigen::Vector3d centre;  // bounding sphere, world
    double radius2;
    bool unbounded;          // planes too large to be worth bounding
  };
  std::vector<Prepared> prepared;
  for (const Primitive& p : primitives_) {
    const Eigen::Isometry3d local_T_world = p.world_T_local.inverse();
    const double radius = p.half_extents.norm();
    prepared.push_back({local_T_world.linear(), local_T_world * eye, p.world_T_local.translation(), radius * radius,
                        p.kind == Primitive::Kind::Plane});
  }

  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < size.width; ++u) {
        const Eigen::Vector3d ray_camera((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
        const Eigen::Vector3d dir = world_T_camera.linear() * ray_camera;  // z-component 1 in the camera frame
        Hit best;
        for (size_t i = 0; i < primitives_.size(); ++i) {
          const Primitive& p = primitives_[i];
          const Prepared& q = prepared[i];
          if (!q.unbounded) {
            // Distance of the sphere's centre from the ray (dir is not unit).
            const Eigen::Vector3d to_centre = q.centre - eye;
            const double along = to_centre.dot(dir) / dir.squaredNorm();
            if (along > 0.0 && (to_centre - along * dir).squaredNorm() > q.radius2) continue;
          }
          const Eigen::Vector3d& o = q.eye_local;
          const Eigen::Vector3d d = q.local_R_world * dir;
          const Eigen::Vector3d& h = p.half_extents;
          Hit hit;
          if (p.kind == Primitive::Kind::Plane) {
            if (std::abs(d.z()) < kEps) continue;
            const double t = -o.z() / d.z();
            const Eigen::Vector3d q = o + t * d;
            if (t <= kEps || std::abs(q.x()) > h.x() || std::abs(q.y()) > h.y()) continue;
            hit.t = t;
            hit.normal_world = p.world_T_local.linear() * Eigen::Vector3d(0, 0, d.z() < 0 ? 1 : -1);
            hit.surface = q.head<2>();
          } else if (p.kind == Primitive::Kind::Box) {
            double t_near = -std::numeric_limits<double>::infinity(), t_far = std::numeric_limits<double>::infinity();
            int axis = -1;
            bool miss = false;
            for (int a = 0; a < 3 && !miss; ++a) {
              if (std::abs(d[a]) < kEps) {
                miss = std::abs(o[a]) > h[a];
                continue;
              }
              double t0 = (-h[a] - o[a]) / d[a], t1 = (h[a] - o[a]) / d[a];
              if (t0 > t1) std::swap(t0, t1);
              if (t0 > t_near) {
                t_near = t0;
                axis = a;
              }
              t_far = std::min(t_far, t1);
              miss = t_near > t_far;
            }
            if (miss || axis < 0 || t_near <= kEps) continue;
            const Eigen::Vector3d q = o + t_near * d;
            Eigen::Vector3d n = Eigen::Vector3d::Zero();
            n[axis] = d[axis] < 0 ? 1 : -1;
            hit.t = t_near;
            hit.normal_world = p.world_T_local.linear() * n;
            // The face's two other coordinates, offset per face so faces differ.
            hit.surface = Eigen::Vector2d(q[(axis + 1) % 3] + 0.37 * axis + (n[axis] > 0 ? 0.11 : 0.0),
                                          q[(axis + 2) % 3] + 0.23 * axis);
          } else {
            const double r = h.x(), b = o.dot(d), a = d.squaredNorm(), c = o.squaredNorm() - r * r;
            const double disc = b * b - a * c;
            if (disc < 0) continue;
            const double t = (-b - std::sqrt(disc)) / a;
            if (t <= kEps) continue;
            const Eigen::Vector3d n = (o + t * d) / r;
            hit.t = t;
            hit.normal_world = n;
            hit.surface = Eigen::Vector2d(r * std::atan2(n.y(), n.x()), r * std::asin(std::clamp(n.z(), -1.0, 1.0)));
          }
          if (hit.t < best.t) {
            best = hit;
            best.primitive = &p;
          }
        }

        if (!best.primitive) {
          out.bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(0, 0, 0);
          out.depth_mm.at<uint16_t>(v, u) = 0;
          out.normals.at<cv::Vec3f>(v, u) = cv::Vec3f(0, 0, 0);
          continue;
        }
        const Material& m = best.primitive->material;
        double albedo = m.albedo * 255.0;
        if (best.primitive->texture >= 0) {
          const double texel = sampleTexture(textures_[static_cast<size_t>(best.primitive->texture)], best.surface,
                                             m.texels_per_metre);
          albedo = 128.0 + m.albedo * 1.6 * (texel - 128.0);
        }
        const Eigen::Vector3d n_camera = camera_R_world * best.normal_world;
        // The ray in camera coordinates has z = 1, so the hit's depth is t.
        // Normals face the camera, so a face turned from a fixed light is dark.
        const double lambert = towards_light_ ? std::max(0.0, best.normal_world.dot(*towards_light_))
                                              : std::abs(n_camera.dot(ray_camera.normalized()));
        const double shade = lighting_ ? 0.35 + 0.65 * lambert : 1.0;
        const uchar grey = cv::saturate_cast<uchar>(albedo * shade);
        out.bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(grey, grey, grey);
        out.depth_mm.at<uint16_t>(v, u) = cv::saturate_cast<uint16_t>(best.t * 1000.0);
        out.normals.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>(n_camera.x()), static_cast<float>(n_camera.y()),
                                                    static_cast<float>(n_camera.z()));
      }
    }
  });
  return out;
}

SyntheticScene SyntheticScene::demo() {
  SyntheticScene scene;
  const auto pose = [](const Eigen::Vector3d& t, const Eigen::Matrix3d& R) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = t;
    return T;
  };
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d wall = Eigen::AngleAxisd(CV_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const auto yaw = [](double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); };
  Material floor{true, 0.5, 600.0, 11};
  Material back{true, 0.7, 500.0, 12};
  Material crate{true, 0.8, 900.0, 13};
  Material plain{false, 0.55, 0.0, 0};
  Material ball{true, 0.8, 800.0, 14};
  scene.addPlane(pose({0, 0, 0}, I), 2.0, 2.0, floor);
  scene.addPlane(pose({0, 1.0, 1.0}, wall), 2.0, 1.0, back);
  scene.addBox(pose({-0.35, 0.1, 0.15}, yaw(0.4)), {0.15, 0.12, 0.15}, crate);
  scene.addBox(pose({0.3, 0.35, 0.2}, yaw(-0.3)), {0.2, 0.15, 0.2}, plain);
  scene.addBox(pose({0.05, -0.3, 0.08}, yaw(1.1)), {0.12, 0.08, 0.08}, crate);
  scene.addSphere({0.45, -0.2, 0.12}, 0.12, ball);
  return scene;
}

Eigen::Isometry3d SyntheticScene::demoCamera(double angle_rad) {
  const double a = angle_rad - CV_PI / 2;
  return lookAt({1.5 * std::cos(a), 1.5 * std::sin(a) - 0.2, 1.0}, {0.0, 0.1, 0.15});
}

Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();  // image right
  const Eigen::Vector3d y = z.cross(x);                // image down
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

Intrinsics syntheticIntrinsics() { return {570.0, 570.0, 319.5, 239.5}; }

}  // namespace risas
