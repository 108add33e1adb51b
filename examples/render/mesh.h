#pragma once
// Triangle meshes: procedural shapes (plane, box, icosphere) and OBJ files through
// tinyobjloader. Object space; the scene applies the transform when it builds.
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <string>
#include <vector>

namespace algray::render {

struct MeshData {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;  // per vertex, empty = flat shading
  std::vector<glm::dvec2> uvs;      // per vertex, may be empty
  std::vector<std::array<unsigned, 3>> triangles;
  // The boundary of a convex solid (box, icosphere; kept by affine transforms): an emissive
  // one hides its far side from points outside it, and its light sampling says so.
  bool convexClosed = false;
  // uv are latitude-longitude coordinates (the icosphere's): rows clamp at the poles.
  bool latLongUv = false;

  // Throws std::runtime_error when an index is out of range or a value is not finite.
  void validate(const std::string& what) const;
  void transform(const glm::dmat4& m);
};

// Square in the z = 0 plane, [-half, half]^2, normal +z, uv = position / uvScale.
MeshData makePlane(double half, double uvScale = 1.0);
// Axis-aligned box [-half, half]^3, flat faces.
MeshData makeBox(glm::dvec3 half);
// Unit sphere from a subdivided icosahedron (smooth normals, spherical uv).
MeshData makeIcosphere(int subdivisions);
// A rectangle corner + s*edge1 + t*edge2, normal along cross(edge1, edge2).
MeshData makeQuad(glm::dvec3 corner, glm::dvec3 edge1, glm::dvec3 edge2);
// Throws std::runtime_error "PATH: message" when the file cannot be read.
MeshData loadObj(const std::string& path);

}  // namespace algray::render
