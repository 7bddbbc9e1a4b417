#pragma once
// The scene's `field` section turned into the procedural material of the field room, with the
// type-specific `field.params` object validated key by key.
#include <filesystem>

#include <glm/glm.hpp>

#include "field/procedural.hpp"
#include "scene/scene.hpp"

namespace fracref {

/// The material described by `settings` for an object whose bounding box is [lo, hi].
/// `params` keys are the member names of the material's parameter struct (scenes/SCHEMA.md),
/// plus `scale` (all types) and `value` (constant).
/// \throw InputError naming `scene_file` and the key (`field.params.distortion`) on an unknown
///        key, a wrong type or an out-of-range value; or the type when it is not procedural.
FieldSpec material_from_scene(const FieldSettings& settings, const std::filesystem::path& scene_file,
                              glm::dvec3 lo, glm::dvec3 hi);

}  // namespace fracref
