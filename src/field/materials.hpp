#pragma once
// Internal to src/field: the compiled form of a FieldSpec, shared by procedural.cpp (the public
// entry points and validation) and materials.cpp (one evaluator per material type).
#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "field/noise.hpp"
#include "field/procedural.hpp"

namespace fracref::detail {

/// The object's box and the lengths derived from it (see procedural.hpp, "Coordinates").
struct MaterialFrame {
  glm::dvec3 min{0.0}, max{0.0}, centre{0.0};
  double diagonal = 0.0;  ///< > 0
  double feature = 0.0;   ///< scale · diagonal: one noise lattice cell, in scene units
  glm::dvec3 offset{0.0}; ///< o(seed), in lattice units

  /// Noise coordinates of a material-space point.
  glm::dvec3 noise_coords(glm::dvec3 p) const { return (p - centre) / feature + offset; }
};

/// \throw InputError when the box is not finite, inverted, or a single point.
MaterialFrame make_frame(const FieldSpec& spec, glm::dvec3 box_min, glm::dvec3 box_max);

/// A material ready to evaluate: immutable, thread-safe, refers to the noise it was built with.
class Material {
 public:
  virtual ~Material() = default;
  virtual double strength(glm::dvec3 p) const = 0;
  /// The material's own colour at p, linear RGB in [0, 1], where it has colours of its own
  /// (sample_albedo() in procedural.hpp).
  virtual std::optional<glm::vec3> albedo(glm::dvec3) const { return std::nullopt; }
};

/// \pre validate_field_spec(spec) passed; `noise` outlives the material.
std::unique_ptr<Material> make_material(const FieldSpec& spec, const PerlinNoise& noise,
                                        const MaterialFrame& frame);

/// The cubes of an inclusions material in the given frame. \pre spec validated.
std::vector<InclusionCube> make_inclusion_cubes(const FieldSpec& spec, const MaterialFrame& frame);

/// The blue-vein weight of a marble material. \pre spec validated.
double marble_weight(const MarbleParams& params, const PerlinNoise& noise,
                     const MaterialFrame& frame, glm::dvec3 p);

}  // namespace fracref::detail
