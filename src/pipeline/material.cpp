#include "pipeline/material.hpp"

#include "scene/json_strict.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// Every key defaults to the struct's own default, so the field room stays the one place that
// documents defaults; its validate_field_spec() then checks the ranges.
void read_fbm(ObjectReader& r, FbmParams& p) {
  p.octaves = int(r.integer("octaves", p.octaves));
  p.lacunarity = r.number("lacunarity", p.lacunarity);
  p.gain = r.number("gain", p.gain);
  p.contrast = r.number("contrast", p.contrast);
}

void read_marble(ObjectReader& r, MarbleParams& p) {
  p.vein_direction = r.vec3("vein_direction", p.vein_direction);
  p.distortion = r.number("distortion", p.distortion);
  p.turbulence_octaves = int(r.integer("turbulence_octaves", p.turbulence_octaves));
  p.threshold = r.number("threshold", p.threshold);
  p.edge = r.number("edge", p.edge);
  p.white_min = r.number("white_min", p.white_min);
  p.white_max = r.number("white_max", p.white_max);
  p.blue_min = r.number("blue_min", p.blue_min);
  p.blue_max = r.number("blue_max", p.blue_max);
  p.white_frequency = r.number("white_frequency", p.white_frequency);
  p.grain_frequency = r.number("grain_frequency", p.grain_frequency);
}

void read_wood(ObjectReader& r, WoodParams& p) {
  p.axis = r.vec3("axis", p.axis);
  if (r.has("axis_point")) p.axis_point = r.vec3_required("axis_point");
  p.radius = r.number("radius", p.radius);
  p.core_strength = r.number("core_strength", p.core_strength);
  p.surface_strength = r.number("surface_strength", p.surface_strength);
  p.radial_exponent = r.number("radial_exponent", p.radial_exponent);
  p.elongation = r.number("elongation", p.elongation);
  p.noise_amplitude = r.number("noise_amplitude", p.noise_amplitude);
  p.noise_octaves = int(r.integer("noise_octaves", p.noise_octaves));
  p.ring_amplitude = r.number("ring_amplitude", p.ring_amplitude);
  p.ring_count = r.number("ring_count", p.ring_count);
  p.ring_wobble = r.number("ring_wobble", p.ring_wobble);
}

void read_brick(ObjectReader& r, BrickParams& p) {
  p.brick_size = r.vec3("brick_size", p.brick_size);
  p.mortar = r.number("mortar", p.mortar);
  p.bond_offset = r.number("bond_offset", p.bond_offset);
  p.brick_strength = r.number("brick_strength", p.brick_strength);
  p.mortar_strength = r.number("mortar_strength", p.mortar_strength);
  p.interface_strength = r.number("interface_strength", p.interface_strength);
  p.band = r.number("band", p.band);
  p.noise_amplitude = r.number("noise_amplitude", p.noise_amplitude);
}

void read_inclusions(ObjectReader& r, InclusionParams& p) {
  p.count = int(r.integer("count", p.count));
  p.size_min = r.number("size_min", p.size_min);
  p.size_max = r.number("size_max", p.size_max);
  p.rotate = r.boolean("rotate", p.rotate);
  p.matrix_strength = r.number("matrix_strength", p.matrix_strength);
  p.inclusion_strength = r.number("inclusion_strength", p.inclusion_strength);
  p.edge = r.number("edge", p.edge);
  p.noise_amplitude = r.number("noise_amplitude", p.noise_amplitude);
}

}  // namespace

FieldSpec material_from_scene(const FieldSettings& settings, const std::filesystem::path& scene_file,
                              glm::dvec3 lo, glm::dvec3 hi) {
  const std::string file = scene_file.string();
  if (settings.type == FieldType::grid)
    throw InputError(file + ": key 'field.type': a grid field is not procedural");
  FieldSpec spec;
  spec.type = to_string(settings.type);
  spec.seed = settings.seed;
  spec.object_min = lo;
  spec.object_max = hi;
  ObjectReader r(settings.params, file, "field.params");
  spec.scale = r.number("scale", spec.scale, Range::at_least(0.0));
  switch (settings.type) {
    case FieldType::constant: spec.value = r.number("value", spec.value); break;
    case FieldType::perlin:
    case FieldType::fbm: read_fbm(r, spec.fbm); break;
    case FieldType::marble: read_marble(r, spec.marble); break;
    case FieldType::wood:
    case FieldType::branch: read_wood(r, spec.wood); break;
    case FieldType::brick: read_brick(r, spec.brick); break;
    case FieldType::inclusions: read_inclusions(r, spec.inclusions); break;
    case FieldType::grid: break;
  }
  r.finish();
  try {
    validate_field_spec(spec);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
  return spec;
}

}  // namespace fracref
