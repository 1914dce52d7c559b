#include "x2car/sim/camera_shading.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace x2car::sim {
namespace {

// A well-mixed 32-bit hash of a lattice cell (and a salt, one per texture).
std::uint32_t hash_cell(std::int32_t x, std::int32_t y, std::uint32_t salt) {
  std::uint32_t h = static_cast<std::uint32_t>(x) * 0x8da6b343u ^
                    static_cast<std::uint32_t>(y) * 0xd8163841u ^ salt * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

float hash01(std::int32_t x, std::int32_t y, std::uint32_t salt) {
  return static_cast<float>(hash_cell(x, y, salt) >> 8) * (1.0f / 16777216.0f);
}

std::int32_t cell(double coordinate) { return static_cast<std::int32_t>(std::floor(coordinate)); }

// Smooth value noise in [0, 1) with features of about one unit.
float value_noise(double x, double y, std::uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int32_t>(fx), iy = static_cast<std::int32_t>(fy);
  const auto tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
  const float sx = tx * tx * (3.0f - 2.0f * tx), sy = ty * ty * (3.0f - 2.0f * ty);
  const float a = hash01(ix, iy, salt), b = hash01(ix + 1, iy, salt);
  const float c = hash01(ix, iy + 1, salt), d = hash01(ix + 1, iy + 1, salt);
  return (a + (b - a) * sx) * (1.0f - sy) + (c + (d - c) * sx) * sy;
}

// Fine grain: one value per `size` [m] square.
float grain(const Eigen::Vector3d& p, double size, std::uint32_t salt) {
  return hash01(cell(p.x() / size), cell(p.y() / size), salt);
}

// The world's horizon haze (linear RGB).
const Eigen::Vector3f kHaze(0.60f, 0.66f, 0.74f);
const Eigen::Vector3f kZenith(0.13f, 0.27f, 0.62f);
const Eigen::Vector3f kGroundHaze(0.40f, 0.41f, 0.40f);

// The colour of an object's part: the object's own on its main surface, the standard one on the
// others (as world_mesh.hpp gives their LiDAR reflectivity).
std::uint32_t part_colour(const Material& material, Surface surface) {
  return surface == material.surface ? material.colour_rgb : standard_material(surface).colour_rgb;
}

// A building's facade: floors 3.2 m high, windows in columns about 2.6 m apart centred on each
// face, shop windows on the ground floor, a grey flat roof. From the point and normal in the
// building's frame (x along its length, y its depth, z up from the ground).
SurfaceLook facade_look(const WorldObject& building, const Eigen::Vector3f& base,
                        const Eigen::Vector3d& point_world, const Eigen::Vector3f& normal_enu) {
  const Eigen::Isometry3d object_from_world = building.world_from_object.inverse();
  const Eigen::Vector3d local = object_from_world * point_world;
  const Eigen::Vector3d normal = object_from_world.linear() * normal_enu.cast<double>();
  if (normal.z() > 0.7) return {Eigen::Vector3f(0.16f, 0.16f, 0.17f), 0.0f};  // roof
  const bool across_x = std::abs(normal.x()) > std::abs(normal.y());
  const double face_length = across_x ? building.size.y() : building.size.x();
  const double along = (across_x ? local.y() : local.x()) + 0.5 * face_length;
  const double z = local.z();
  constexpr double kFloor = 3.2;
  const int floor = static_cast<int>(std::floor(z / kFloor));
  const double in_floor = z - floor * kFloor;
  const int columns = std::max(1, static_cast<int>(face_length / 2.6));
  const double spacing = face_length / columns;
  const int column = std::clamp(static_cast<int>(along / spacing), 0, columns - 1);
  const double in_column = along - (column + 0.5) * spacing;  // from the column's middle
  const bool ground = floor == 0;
  const double half_width = ground ? 0.4 * spacing : std::min(0.65, 0.3 * spacing);
  const bool window = z < building.size.z() - 0.8 && std::abs(in_column) < half_width &&
                      in_floor > (ground ? 0.5 : 0.9) && in_floor < (ground ? 2.7 : 2.4);
  const float wall_grain = 0.92f + 0.08f * grain(local, 0.2, 11u);
  if (!window) {
    // A slightly darker band at each floor's slab.
    const float band = in_floor < 0.25 && floor > 0 ? 0.85f : 1.0f;
    return {base * (wall_grain * band), 0.0f};
  }
  // Some windows have their blinds down.
  const float blind = hash01(column, floor, building.id * 7u + (across_x ? 1u : 0u));
  if (blind < 0.2f) return {Eigen::Vector3f(0.45f, 0.43f, 0.40f), 0.05f};
  return {Eigen::Vector3f(0.03f, 0.035f, 0.045f), 0.35f};
}

// A sign's plate: its colour with a white rim on the face (+x), bare metal at the back.
SurfaceLook sign_look(const WorldObject& sign, const Eigen::Vector3f& base,
                      const Eigen::Vector3d& point_world, const Eigen::Vector3f& normal_enu) {
  const Eigen::Isometry3d object_from_world = sign.world_from_object.inverse();
  const Eigen::Vector3d local = object_from_world * point_world;
  const Eigen::Vector3d normal = object_from_world.linear() * normal_enu.cast<double>();
  if (normal.x() < -0.5) return {linear_rgb(0x8a8d91), 0.05f};
  const double half_width = 0.5 * sign.size.y();
  const double plate_height = std::min(sign.size.y(), 0.75 * sign.size.y() + 0.2);
  const double rim = 0.08 * sign.size.y();
  const bool on_rim = std::abs(local.y()) > half_width - rim || local.z() > sign.size.z() - rim ||
                      local.z() < sign.size.z() - plate_height + rim;
  if (on_rim) return {Eigen::Vector3f::Constant(0.85f), 0.0f};
  return {base, 0.0f};
}

}  // namespace

float linear_from_srgb8(std::uint8_t value) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[i] = static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table[value];
}

Eigen::Vector3f linear_rgb(std::uint32_t rgb) {
  return {linear_from_srgb8(static_cast<std::uint8_t>(rgb >> 16)),
          linear_from_srgb8(static_cast<std::uint8_t>(rgb >> 8)),
          linear_from_srgb8(static_cast<std::uint8_t>(rgb))};
}

Eigen::Vector3f sun_direction_enu(double azimuth, double elevation) {
  return Eigen::Vector3d(std::sin(azimuth) * std::cos(elevation),
                         std::cos(azimuth) * std::cos(elevation), std::sin(elevation))
      .cast<float>();
}

SurfaceLook surface_look(const World& world, const SurfaceHit& hit,
                         const Eigen::Vector3d& point_world) {
  const bool mover = hit.object_id >= world.objects.size();
  const Material& material = mover ? world.movers[hit.object_id - world.objects.size()].material
                                   : world.objects[hit.object_id].material;
  const Eigen::Vector3f base = linear_rgb(part_colour(material, hit.surface));
  const Eigen::Vector3d& p = point_world;
  switch (hit.surface) {
    case Surface::kAsphalt: {
      // Texture at every scale, as real asphalt has: patches of a few metres (repairs, wear),
      // stains and ruts of decimetres, clusters of stones of a few centimetres, and the grain.
      // The middle scales are what a feature tracker follows on a real road (road_plane_motion).
      const float patches = 0.8f + 0.4f * value_noise(p.x() / 3.0, p.y() / 3.0, 1u);
      const float stains = 0.8f + 0.4f * value_noise(p.x() / 0.6, p.y() / 0.6, 8u);
      const float stones = 0.8f + 0.4f * value_noise(p.x() / 0.12, p.y() / 0.12, 9u);
      return {base * (patches * stains * stones * (0.9f + 0.2f * grain(p, 0.04, 2u))), 0.0f};
    }
    case Surface::kLanePaint:
      return {base * (0.9f + 0.1f * grain(p, 0.05, 3u)), 0.0f};
    case Surface::kConcrete:
      return {base * (0.85f + 0.15f * value_noise(p.x() / 0.4, p.y() / 0.4, 4u)), 0.0f};
    case Surface::kPaving: {
      // Slabs of 0.6 m with darker joints, in the world's axes.
      const double u = p.x() / 0.6 - std::floor(p.x() / 0.6);
      const double v = p.y() / 0.6 - std::floor(p.y() / 0.6);
      const bool joint = u < 0.04 || v < 0.04;
      const float slab = 0.9f + 0.2f * hash01(cell(p.x() / 0.6), cell(p.y() / 0.6), 5u);
      return {base * (joint ? 0.75f : slab), 0.0f};
    }
    case Surface::kGrass:
      return {base * ((0.7f + 0.5f * value_noise(p.x() / 2.0, p.y() / 2.0, 6u)) *
                      (0.85f + 0.3f * grain(p, 0.1, 7u))),
              0.0f};
    case Surface::kFacade:
      if (mover) return {base, 0.0f};
      return facade_look(world.objects[hit.object_id], base, p, hit.normal);
    case Surface::kSignFace:
      if (mover) return {base, 0.0f};
      return sign_look(world.objects[hit.object_id], base, p, hit.normal);
    case Surface::kMetal:
      return {base, 0.08f};
    case Surface::kBark:
      return {base * (0.75f + 0.4f * value_noise(std::atan2(p.y(), p.x()) * 30.0, p.z() * 2.0, 8u)),
              0.0f};
    case Surface::kFoliage:
      return {base * (0.55f +
                      0.7f * value_noise(p.x() * 2.5 + p.z() * 1.7, p.y() * 2.5 - p.z() * 1.3, 9u)),
              0.0f};
    case Surface::kCarPaint:
      return {base, 0.12f};
    case Surface::kGlass:
      return {base, 0.4f};
    case Surface::kTyre:
    case Surface::kClothing:
      return {base, 0.0f};
  }
  return {base, 0.0f};
}

Eigen::Vector3f sky_radiance(const Eigen::Vector3f& direction_enu) {
  const float up = direction_enu.z();
  if (up < 0.0f) {
    const float t = std::min(1.0f, -up * 8.0f);
    return kHaze + (kGroundHaze - kHaze) * t;
  }
  const float t = std::sqrt(std::min(1.0f, up));
  return kHaze + (kZenith - kHaze) * t;
}

Eigen::Vector3f background_radiance(const Lighting& lighting, const Eigen::Vector3f& direction_enu,
                                    float height_m) {
  if (direction_enu.z() >= 0.0f) return sky_radiance(direction_enu);
  const float range = height_m / -direction_enu.z();
  const SurfaceLook grass{linear_rgb(standard_material(Surface::kGrass).colour_rgb) * 0.9f, 0.0f};
  return shade(lighting, grass, Eigen::Vector3f::UnitZ(), direction_enu, range, true);
}

Eigen::Vector3f shade(const Lighting& lighting, const SurfaceLook& look,
                      const Eigen::Vector3f& normal_enu, const Eigen::Vector3f& direction_enu,
                      float range, bool sunlit) {
  const float cos_sun = std::max(0.0f, normal_enu.dot(lighting.sun_enu));
  const float irradiance = (sunlit ? lighting.sun * cos_sun : 0.0f) +
                           lighting.ambient * (0.75f + 0.25f * normal_enu.z());
  Eigen::Vector3f colour = look.albedo * irradiance;
  if (look.gloss > 0.0f) {
    const Eigen::Vector3f mirrored =
        direction_enu - 2.0f * direction_enu.dot(normal_enu) * normal_enu;
    colour += look.gloss * sky_radiance(mirrored);
  }
  const float veil = 1.0f - std::exp(-range / lighting.haze_distance_m);
  return colour + (kHaze - colour) * veil;
}

}  // namespace x2car::sim
