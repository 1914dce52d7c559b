#include "x2car/sim/world_scene.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace x2car::sim {
namespace {

constexpr std::size_t kPacket = 16;  // rays per rtcIntersect16 call

void throw_on_error(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) {
    throw std::runtime_error(
        fmt::format("embree: {} failed (error {})", what, static_cast<int>(error)));
  }
}

// The centre of the road's stations' bounding box, rounded to the metre [m].
Eigen::Vector3d scene_origin(const World& world) {
  if (world.road.stations.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d low = world.road.stations.front().centre, high = low;
  for (const RoadStation& station : world.road.stations) {
    low = low.cwiseMin(station.centre);
    high = high.cwiseMax(station.centre);
  }
  return (0.5 * (low + high)).array().round().matrix();
}

// Intersects one packet against a scene; hit rays get their geomID set and tfar shortened.
void intersect(RTCScene scene, const std::array<int, kPacket>& valid, RTCRayHit16& rays) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect16(valid.data(), scene, &context, &rays);
}

}  // namespace

namespace detail {
void EmbreeDeviceRelease::operator()(RTCDeviceTy* device) const { rtcReleaseDevice(device); }
void EmbreeSceneRelease::operator()(RTCSceneTy* scene) const { rtcReleaseScene(scene); }
}  // namespace detail

TriangleScene::TriangleScene(RTCDeviceTy* device, TriangleMesh mesh)
    : object_(std::move(mesh.triangle_object)),
      surface_(std::move(mesh.triangle_surface)),
      reflectivity_(std::move(mesh.triangle_reflectivity)) {
  if (mesh.triangles.empty()) return;
  scene_.reset(rtcNewScene(device));
  throw_on_error(device, "creating a scene");
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  throw_on_error(device, "creating a geometry");
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  auto* indices = static_cast<std::uint32_t*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(std::uint32_t), mesh.triangles.size()));
  if (vertices == nullptr || indices == nullptr) {
    rtcReleaseGeometry(geometry);
    throw_on_error(device, "allocating geometry buffers");
    throw std::runtime_error("embree: cannot allocate geometry buffers");
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    std::memcpy(vertices + 3 * i, mesh.vertices[i].data(), 3 * sizeof(float));
  }
  std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * 3 * sizeof(std::uint32_t));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_.get(), geometry);
  rtcReleaseGeometry(geometry);  // the scene holds it now
  rtcSetSceneBuildQuality(
      scene_.get(), mesh.triangles.size() > 10000 ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_LOW);
  rtcCommitScene(scene_.get());
  throw_on_error(device, "committing a scene");
}

WorldScene::WorldScene(const World& world) : world_(world), origin_(scene_origin(world)) {
  device_.reset(rtcNewDevice("verbose=0"));
  if (!device_) {
    throw std::runtime_error(fmt::format("embree: cannot create a device (error {})",
                                         static_cast<int>(rtcGetDeviceError(nullptr))));
  }
  static_ = std::make_unique<TriangleScene>(device_.get(), mesh_static_world(world, origin_));
}

MoverScene WorldScene::movers_at(double time, const Eigen::Vector3d& centre_world,
                                 double radius_m) const {
  TriangleMesh mesh;
  for (const MovingObject& mover : world_.movers) {
    if (!world_.mover_present(mover, time)) continue;
    const Eigen::Vector3d position = world_.mover_pose(mover, time).translation();
    if ((position - centre_world).norm() > radius_m + mover.size.norm()) continue;
    append_mover_mesh(world_, mover, time, origin_, mesh);
  }
  return MoverScene(device_.get(), std::move(mesh));
}

// Casts `directions` from `from` (scene coordinates) in packets against the static scene and the
// movers; calls on_hit(index, scene, triangle, range, geometric normal) for each ray that hits and
// on_miss(index) for each that does not.
template <typename OnHit, typename OnMiss>
void WorldScene::trace_packets(const Eigen::Vector3f& from,
                               std::span<const Eigen::Vector3f> directions, float max_range,
                               const MoverScene* movers, OnHit on_hit, OnMiss on_miss) const {
  RTCScene static_scene = static_->scene();
  RTCScene mover_scene = movers != nullptr ? movers->triangles().scene() : nullptr;
  for (std::size_t start = 0; start < directions.size(); start += kPacket) {
    const std::size_t count = std::min(kPacket, directions.size() - start);
    alignas(64) RTCRayHit16 rays;
    alignas(64) std::array<int, kPacket> valid{};
    for (std::size_t i = 0; i < kPacket; ++i) {
      const Eigen::Vector3f d = i < count ? directions[start + i] : Eigen::Vector3f::UnitZ();
      valid[i] = i < count ? -1 : 0;
      rays.ray.org_x[i] = from.x();
      rays.ray.org_y[i] = from.y();
      rays.ray.org_z[i] = from.z();
      rays.ray.dir_x[i] = d.x();
      rays.ray.dir_y[i] = d.y();
      rays.ray.dir_z[i] = d.z();
      rays.ray.tnear[i] = 0.0f;
      rays.ray.tfar[i] = max_range;
      rays.ray.time[i] = 0.0f;
      rays.ray.mask[i] = 0xFFFFFFFFu;
      rays.ray.id[i] = static_cast<unsigned>(i);
      rays.ray.flags[i] = 0;
      rays.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
      rays.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    if (static_scene != nullptr) intersect(static_scene, valid, rays);
    std::array<unsigned, kPacket> static_hit{};
    for (std::size_t i = 0; i < kPacket; ++i) {
      static_hit[i] = rays.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID
                                                                    : rays.hit.primID[i];
      rays.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    if (mover_scene != nullptr) intersect(mover_scene, valid, rays);
    for (std::size_t i = 0; i < count; ++i) {
      const bool on_mover = rays.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
      if (!on_mover && static_hit[i] == RTC_INVALID_GEOMETRY_ID) {
        on_miss(start + i);
        continue;
      }
      const TriangleScene& scene = on_mover ? movers->triangles() : *static_;
      const std::uint32_t triangle = on_mover ? rays.hit.primID[i] : static_hit[i];
      const Eigen::Vector3f normal(rays.hit.Ng_x[i], rays.hit.Ng_y[i], rays.hit.Ng_z[i]);
      on_hit(start + i, scene, triangle, rays.ray.tfar[i], normal);
    }
  }
}

void WorldScene::trace(const Eigen::Vector3d& from_world,
                       std::span<const Eigen::Vector3f> directions, float max_range,
                       const MoverScene* movers, std::span<RayHit> hits) const {
  if (hits.size() != directions.size()) throw std::invalid_argument("trace: sizes differ");
  trace_packets((from_world - origin_).cast<float>(), directions, max_range, movers,
                [&](std::size_t i, const TriangleScene& scene, std::uint32_t triangle, float range,
                    const Eigen::Vector3f& normal) {
                  RayHit& hit = hits[i];
                  hit.range = range;
                  hit.object_id = scene.object(triangle);
                  hit.reflectivity = scene.reflectivity(triangle);
                  hit.cos_incidence =
                      std::abs(normal.dot(directions[i])) / std::max(normal.norm(), 1e-20f);
                },
                [&](std::size_t i) { hits[i] = RayHit{}; });
}

void WorldScene::trace_surfaces(const Eigen::Vector3d& from_world,
                                std::span<const Eigen::Vector3f> directions, float max_range,
                                const MoverScene* movers, std::span<SurfaceHit> hits) const {
  if (hits.size() != directions.size()) throw std::invalid_argument("trace: sizes differ");
  trace_packets((from_world - origin_).cast<float>(), directions, max_range, movers,
                [&](std::size_t i, const TriangleScene& scene, std::uint32_t triangle, float range,
                    const Eigen::Vector3f& normal) {
                  SurfaceHit& hit = hits[i];
                  hit.range = range;
                  hit.object_id = scene.object(triangle);
                  hit.triangle = triangle;
                  hit.surface = scene.surface(triangle);
                  const float norm = std::max(normal.norm(), 1e-20f);
                  // Facing the camera: the side the ray arrives at.
                  hit.normal = normal.dot(directions[i]) > 0.0f ? Eigen::Vector3f(-normal / norm)
                                                                : Eigen::Vector3f(normal / norm);
                },
                [&](std::size_t i) { hits[i] = SurfaceHit{}; });
}

void WorldScene::occluded(std::span<const Eigen::Vector3d> from_world,
                          const Eigen::Vector3f& direction, float max_range,
                          const MoverScene* movers, std::span<std::uint8_t> blocked) const {
  if (blocked.size() != from_world.size()) throw std::invalid_argument("occluded: sizes differ");
  RTCScene scenes[2] = {static_->scene(),
                        movers != nullptr ? movers->triangles().scene() : nullptr};
  for (std::size_t start = 0; start < from_world.size(); start += kPacket) {
    const std::size_t count = std::min(kPacket, from_world.size() - start);
    alignas(64) RTCRay16 rays;
    alignas(64) std::array<int, kPacket> valid{};
    for (std::size_t i = 0; i < kPacket; ++i) {
      const Eigen::Vector3f from =
          i < count ? Eigen::Vector3f((from_world[start + i] - origin_).cast<float>())
                    : Eigen::Vector3f::Zero();
      valid[i] = i < count ? -1 : 0;
      rays.org_x[i] = from.x();
      rays.org_y[i] = from.y();
      rays.org_z[i] = from.z();
      rays.dir_x[i] = direction.x();
      rays.dir_y[i] = direction.y();
      rays.dir_z[i] = direction.z();
      rays.tnear[i] = 0.0f;
      rays.tfar[i] = max_range;
      rays.time[i] = 0.0f;
      rays.mask[i] = 0xFFFFFFFFu;
      rays.id[i] = static_cast<unsigned>(i);
      rays.flags[i] = 0;
    }
    for (RTCScene scene : scenes) {
      if (scene == nullptr) continue;
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcOccluded16(valid.data(), scene, &context, &rays);
      // An occluded ray has tfar = -inf; it need not be cast against the next scene.
      for (std::size_t i = 0; i < count; ++i) {
        if (rays.tfar[i] < 0.0f) valid[i] = 0;
      }
    }
    for (std::size_t i = 0; i < count; ++i) blocked[start + i] = rays.tfar[i] < 0.0f ? 1 : 0;
  }
}

}  // namespace x2car::sim
