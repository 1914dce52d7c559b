// What the camera sees of a surface (camera_render.hpp): the materials' colours and textures, the
// sky, and the light (a sun and the sky's ambient light). Colours are linear RGB, 1 = a white
// Lambertian surface facing the sun without ambient light; the sensor (camera_sensor_effects.hpp)
// turns them into 8-bit sRGB.
//
// The textures are procedural, from the hit point, so that they stay put as the camera moves and
// give the image the edges of a real street: asphalt with a mild grain and patches, paving slabs,
// concrete curbs, grass, facades with a grid of windows by floor (from the point in the
// building's own frame), signs with a white rim, bark, foliage, car paint and glass that mirror
// the sky. Lane paint has the colour the world gives it (white, or yellow for a centre line).
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "x2car/sim/world.hpp"
#include "x2car/sim/world_scene.hpp"

namespace x2car::sim {

struct Lighting {
  Eigen::Vector3f sun_enu = Eigen::Vector3f(0.0f, 0.0f, 1.0f);  // unit, towards the sun
  float sun = 1.0f;                // irradiance on a surface facing the sun
  float ambient = 0.45f;           // the sky's irradiance on a surface facing up
  float haze_distance_m = 900.0f;  // distance at which haze veils 63 % of a surface [m]
};

// The sun at compass bearing `azimuth` (clockwise from north) and `elevation` above the horizon
// [rad].
Eigen::Vector3f sun_direction_enu(double azimuth, double elevation);

// How a surface reflects: its diffuse colour (linear RGB, 0..1) and how much of the sky it
// mirrors (glass, car paint).
struct SurfaceLook {
  Eigen::Vector3f albedo = Eigen::Vector3f::Constant(0.5f);
  float gloss = 0.0f;
};

// The look of the surface `hit` at `point_world` (ENU [m]). Movers are looked up by id in the
// world; their textures do not depend on their pose.
SurfaceLook surface_look(const World& world, const SurfaceHit& hit,
                         const Eigen::Vector3d& point_world);

// The sky seen along `direction_enu` (unit): a gradient from a pale horizon to a deeper blue at
// the zenith, and the ground's haze below the horizon.
Eigen::Vector3f sky_radiance(const Eigen::Vector3f& direction_enu);

// The light leaving a surface towards the camera: look x (sun x cos x sunlit + ambient, the
// ambient less on surfaces facing down), the sky mirrored by its gloss, veiled by haze over
// `range` [m]. `direction_enu` is the camera ray's (unit), `normal_enu` faces the camera.
Eigen::Vector3f shade(const Lighting& lighting, const SurfaceLook& look,
                      const Eigen::Vector3f& normal_enu, const Eigen::Vector3f& direction_enu,
                      float range, bool sunlit);

// What a ray that misses the world sees: the sky above the horizon; below it, the world's
// terrain ends (RoadsideOptions::terrain_half_width_m), so a grass plain `height_m` below the
// camera continues it to the horizon, under haze.
Eigen::Vector3f background_radiance(const Lighting& lighting, const Eigen::Vector3f& direction_enu,
                                    float height_m);

// Linear value of an 8-bit sRGB channel (the materials' 0xRRGGBB colours).
float linear_from_srgb8(std::uint8_t value);
Eigen::Vector3f linear_rgb(std::uint32_t rgb);

}  // namespace x2car::sim
