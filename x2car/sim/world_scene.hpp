// The world as Embree 3 scenes, for ray casting (the LiDAR and the camera).
//
// The static world is one triangle mesh in one scene, built once. Moving objects are placed per
// query time in a small scene of their own (MoverScene): the LiDAR builds one per sweep, with
// every mover near the sensor at its pose at the sweep's middle, and traces each ray against both
// scenes. A mover thus stands still during a sweep: at 50 km/h it moves 0.7 m in 0.05 s, so its
// points are off by up to that much at the sweep's ends; the static world, which is what
// calibration uses, is exact. Each hit carries the id of the object or mover hit and the LiDAR
// reflectivity of the part hit.
//
// Scene coordinates are float, relative to an origin at the centre of the road's bounding box, so
// that a 20 km drive keeps about 1 mm.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>

#include "x2car/sim/world.hpp"
#include "x2car/sim/world_mesh.hpp"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace x2car::sim {

namespace detail {
struct EmbreeDeviceRelease {
  void operator()(RTCDeviceTy* device) const;
};
struct EmbreeSceneRelease {
  void operator()(RTCSceneTy* scene) const;
};
}  // namespace detail

using EmbreeDevice = std::unique_ptr<RTCDeviceTy, detail::EmbreeDeviceRelease>;
using EmbreeScene = std::unique_ptr<RTCSceneTy, detail::EmbreeSceneRelease>;

constexpr std::uint32_t kNoObject = std::numeric_limits<std::uint32_t>::max();

struct RayHit {
  float range = std::numeric_limits<float>::infinity();  // along the unit direction [m]
  std::uint32_t object_id = kNoObject;                   // object or mover hit
  float reflectivity = 0.0f;                             // LiDAR reflectivity of the part hit
  float cos_incidence = 0.0f;  // |cos| of the angle between the ray and the surface normal
};

// A hit as the camera needs it (camera_render.hpp): what was hit and how it faces the ray.
struct SurfaceHit {
  float range = std::numeric_limits<float>::infinity();  // along the unit direction [m]
  std::uint32_t object_id = kNoObject;                   // object or mover hit
  std::uint32_t triangle = 0;                            // in its scene (static or movers)
  Surface surface = Surface::kAsphalt;                   // of the part hit
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();      // unit, ENU, towards the ray's origin
};

// One triangle mesh committed to an Embree scene, with its per-triangle tables.
class TriangleScene {
 public:
  TriangleScene(RTCDeviceTy* device, TriangleMesh mesh);  // an empty mesh gives no scene

  RTCSceneTy* scene() const { return scene_.get(); }
  std::size_t triangle_count() const { return object_.size(); }
  std::uint32_t object(std::uint32_t triangle) const { return object_[triangle]; }
  float reflectivity(std::uint32_t triangle) const { return reflectivity_[triangle]; }
  Surface surface(std::uint32_t triangle) const { return surface_[triangle]; }

 private:
  EmbreeScene scene_;
  std::vector<std::uint32_t> object_;
  std::vector<Surface> surface_;
  std::vector<float> reflectivity_;
};

// Movers at one time (WorldScene::movers_at).
class MoverScene {
 public:
  MoverScene(RTCDeviceTy* device, TriangleMesh mesh) : triangles_(device, std::move(mesh)) {}
  const TriangleScene& triangles() const { return triangles_; }

 private:
  TriangleScene triangles_;
};

class WorldScene {
 public:
  // Meshes and commits the static world. Throws std::runtime_error when Embree fails.
  explicit WorldScene(const World& world);
  explicit WorldScene(World&&) = delete;  // the world must outlive the scene

  const World& world() const { return world_; }
  const Eigen::Vector3d& origin() const { return origin_; }  // ENU [m]
  std::size_t triangle_count() const { return static_->triangle_count(); }

  // The movers present at `time` [s] within `radius_m` [m] of `centre_world` (ENU), placed at
  // their pose then. Thread-safe.
  MoverScene movers_at(double time, const Eigen::Vector3d& centre_world, double radius_m) const;

  // Casts rays from one point (ENU) along unit directions (ENU) up to `max_range` [m] against the
  // static world and, when given, the movers; hits[i] answers directions[i]. Thread-safe.
  void trace(const Eigen::Vector3d& from_world, std::span<const Eigen::Vector3f> directions,
             float max_range, const MoverScene* movers, std::span<RayHit> hits) const;
  // As trace, with the part hit and its normal (the camera).
  void trace_surfaces(const Eigen::Vector3d& from_world,
                      std::span<const Eigen::Vector3f> directions, float max_range,
                      const MoverScene* movers, std::span<SurfaceHit> hits) const;
  // Whether anything lies within `max_range` [m] of each point (ENU) along the one unit direction
  // (ENU): blocked[i] = 1 when so (the camera's shadow rays). Thread-safe.
  void occluded(std::span<const Eigen::Vector3d> from_world, const Eigen::Vector3f& direction,
                float max_range, const MoverScene* movers, std::span<std::uint8_t> blocked) const;

 private:
  template <typename OnHit, typename OnMiss>
  void trace_packets(const Eigen::Vector3f& from, std::span<const Eigen::Vector3f> directions,
                     float max_range, const MoverScene* movers, OnHit on_hit, OnMiss on_miss) const;

  const World& world_;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  EmbreeDevice device_;
  std::unique_ptr<TriangleScene> static_;
};

}  // namespace x2car::sim
