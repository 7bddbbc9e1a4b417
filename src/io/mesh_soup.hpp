#pragma once
// A triangle soup exactly as a mesh file says it: what the strict readers return and the
// writers take.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// The scalar types of PLY properties (PLY names: char/int8 ... double/float64).
enum class PropertyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

/// The canonical PLY name of `type` ("char", "uchar", "short", "ushort", "int", "uint",
/// "float", "double").
std::string_view property_type_name(PropertyType type);

/// One extra per-vertex or per-face property. Every value of every type is exact in a double.
struct PropertyColumn {
  std::string name;
  PropertyType type = PropertyType::Float64;
  std::vector<double> values;
};

/// A triangle soup exactly as the file says: no vertex merged, no face dropped, no face reoriented.
struct MeshSoup {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< 0-based vertex indices
  std::vector<std::uint32_t> triangle_polygon;          ///< source polygon index per triangle
  std::size_t polygons = 0;               ///< faces in the file
  std::size_t polygons_triangulated = 0;  ///< of them, faces with > 3 vertices (triangulated)
  std::vector<std::string> groups;            ///< OBJ `o`/`g` names in order of first use; empty if none
  std::vector<std::uint32_t> triangle_group;  ///< per triangle, index into groups (empty if none)
  std::vector<PropertyColumn> vertex_properties;  ///< PLY extra per-vertex properties
  std::vector<PropertyColumn> face_properties;    ///< PLY extra per-face properties, one value per TRIANGLE
};

}  // namespace fracref
