// Triangle meshes of the world (world.hpp), independent of the ray tracer that uses them.
//
// Shapes: strips follow the road's stations (flat strips and vertical bands; on the inside of a
// tight curve they are kept short of the curve's centre so that they never fold); buildings are
// boxes reaching 1 m into the ground; poles and tree trunks octagonal prisms; tree crowns
// icosahedra; signs a square post and a 3 cm plate; guard-rail posts boxes; cars a body, a glass
// cabin and four wheels (trucks a single box on wheels); cyclists a bike and a rider. The terrain
// is a height field on a square grid (RoadsideOptions::terrain_cell_m) around the road: 0.3 m
// below the road within 1.5 cells of the asphalt's edge (hidden under the road), and 5 cm below
// the sidewalk (urban) or the shoulder's edge (highway) further out, flat sideways there.
//
// Vertices are float, relative to an origin the caller picks near the scene (float keeps ~1 mm
// within 10 km of it).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "x2car/sim/world.hpp"

namespace x2car::sim {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;                // relative to the origin [m]
  std::vector<std::array<std::uint32_t, 3>> triangles;  // vertex indices
  // Per triangle: the id of the object or mover it belongs to, the surface of its part and that
  // part's LiDAR reflectivity (the object's own on its main surface, the standard one elsewhere).
  std::vector<std::uint32_t> triangle_object;
  std::vector<Surface> triangle_surface;
  std::vector<float> triangle_reflectivity;
};

// Every static object of the world. `origin` is the ENU point vertices count from [m].
TriangleMesh mesh_static_world(const World& world, const Eigen::Vector3d& origin);

// Appends one static object.
void append_object_mesh(const World& world, const WorldObject& object,
                        const Eigen::Vector3d& origin, TriangleMesh& mesh);

// Appends a mover at its pose at `time` [s].
void append_mover_mesh(const World& world, const MovingObject& mover, double time,
                       const Eigen::Vector3d& origin, TriangleMesh& mesh);

}  // namespace x2car::sim
