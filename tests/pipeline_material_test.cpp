// The scene's field.params mapped onto the procedural materials, every error naming the key.
#include <gtest/gtest.h>

#include <string>

#include "pipeline/material.hpp"
#include "util/error.hpp"

using namespace fracref;

namespace {

FieldSettings settings(FieldType type, const char* params) {
  FieldSettings f;
  f.type = type;
  f.resolution = {8, 8, 8};
  f.params = nlohmann::json::parse(params);
  return f;
}

std::string error_of(FieldType type, const char* params) {
  try {
    material_from_scene(settings(type, params), "scene.json", glm::dvec3(0.0), glm::dvec3(1.0));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PipelineMaterial, ParamsReachTheMaterial) {
  FieldSpec m = material_from_scene(settings(FieldType::marble, R"({"distortion": 3.5, "scale": 0.3})"), "scene.json",
                                    glm::dvec3(0.0), glm::dvec3(2.0));
  EXPECT_EQ(m.type, "marble");
  EXPECT_DOUBLE_EQ(m.marble.distortion, 3.5);
  EXPECT_DOUBLE_EQ(m.scale, 0.3);
  EXPECT_EQ(m.object_max, glm::dvec3(2.0));
  FieldSpec w = material_from_scene(settings(FieldType::branch, R"({"axis": [0, 1, 0]})"), "s.json", glm::dvec3(0.0),
                                    glm::dvec3(1.0));
  EXPECT_EQ(w.wood.axis, glm::dvec3(0.0, 1.0, 0.0));
}

TEST(PipelineMaterial, ErrorsNameTheFileAndKey) {
  std::string e = error_of(FieldType::marble, R"({"distorsion": 1})");
  EXPECT_NE(e.find("scene.json"), std::string::npos) << e;
  EXPECT_NE(e.find("field.params.distorsion"), std::string::npos) << e;
  e = error_of(FieldType::brick, R"({"mortar": "thin"})");
  EXPECT_NE(e.find("field.params.mortar"), std::string::npos) << e;
  e = error_of(FieldType::marble, R"({"edge": -1})");
  EXPECT_NE(e.find("scene.json"), std::string::npos) << e;
  EXPECT_NE(e.find("edge"), std::string::npos) << e;
  e = error_of(FieldType::wood, R"({"grain_frequency": 2})");  // a marble key on wood
  EXPECT_NE(e.find("field.params.grain_frequency"), std::string::npos) << e;
  e = error_of(FieldType::grid, "{}");
  EXPECT_NE(e.find("field.type"), std::string::npos) << e;
}
