// animation.glb evaluated at its keys (node transforms and morph weights applied), and the
// glb_frames check: those positions against frames/.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/quaternion.hpp>

#include "check/check_glb_internal.hpp"

namespace fracref::check_detail {
namespace {

using Json = nlohmann::json;

// The output of node `node`'s channel `path` at key `key` (`width` floats), or empty.
std::vector<double> channel_value(const GlbFile& g, std::size_t node, const char* path, std::size_t key, std::size_t width) {
  const Json& animations = array_of(g.j, "animations", "gltf");
  if (animations.empty()) return {};
  for (const Json& c : animations[0]["channels"]) {
    if (c["target"]["node"] != node || c["target"]["path"] != path) continue;
    const Json& sampler = animations[0]["samplers"][c["sampler"].get<std::size_t>()];
    const std::size_t output = sampler["output"].get<std::size_t>();
    const std::vector<double> all = float_values(g, output, g.acc[output].type == "VEC4" ? 4 : g.acc[output].type == "VEC3" ? 3 : 1, path);
    return std::vector<double>(all.begin() + std::ptrdiff_t(key * width), all.begin() + std::ptrdiff_t((key + 1) * width));
  }
  return {};
}

std::vector<double> static_value(const Json& node, const char* key, std::vector<double> fallback) {
  if (!node.contains(key)) return fallback;
  return node[key].get<std::vector<double>>();
}

}  // namespace

std::vector<glm::dvec3> glb_positions(const GlbFile& g, std::size_t p, std::size_t n, std::size_t key) {
  const Json& node = g.j["nodes"][p];
  const Json& prim = g.j["meshes"][node["mesh"].get<std::size_t>()]["primitives"][0];
  std::vector<double> x = float_values(g, prim["attributes"]["POSITION"].get<std::size_t>(), 3, "POSITION");
  const std::size_t targets = prim.contains("targets") ? prim["targets"].size() : 0;
  std::vector<double> weights = channel_value(g, p, "weights", key, targets);
  for (std::size_t t = 0; t < weights.size(); ++t) {
    if (weights[t] == 0.0) continue;
    const std::vector<double> d = float_values(g, prim["targets"][t]["POSITION"].get<std::size_t>(), 3, "target");
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += weights[t] * d[i];
  }
  std::vector<double> t = channel_value(g, p, "translation", key, 3), r = channel_value(g, p, "rotation", key, 4);
  if (t.empty()) t = static_value(node, "translation", {0, 0, 0});
  if (r.empty()) r = static_value(node, "rotation", {0, 0, 0, 1});
  const std::vector<double> s = static_value(node, "scale", {1, 1, 1});
  const glm::dmat3 rot = glm::mat3_cast(glm::dquat(r[3], r[0], r[1], r[2]));
  std::vector<glm::dvec3> out;
  for (std::size_t i = 0; i < n; ++i)
    out.push_back(glm::dvec3(t[0], t[1], t[2]) + rot * (glm::dvec3(s[0], s[1], s[2]) * glm::dvec3(x[3 * i], x[3 * i + 1], x[3 * i + 2])));
  return out;
}

void check_glb_frames(const GlbFile& g, const std::vector<PieceFile>& pieces, std::size_t frames, const FrameReader& frame,
                      CheckReport& report) {
  glm::dvec3 lo(1e300), hi(-1e300);
  std::size_t slots = 0;
  for (const PieceFile& f : pieces) {
    for (const glm::dvec3& x : f.mesh.positions) lo = glm::min(lo, x), hi = glm::max(hi, x);
    slots += f.mesh.positions.size();
  }
  const double diagonal = glm::length(hi - lo), allowed = 1e-6 * diagonal;
  double worst = 0.0;
  std::string where;
  const std::vector<std::size_t> kept = glb_kept_frames(g, frames);
  for (std::size_t j = 0; j < kept.size(); ++j) {
    const std::vector<glm::dvec3> x = frame(kept[j]);
    if (x.size() != slots) throw Problem("frame " + std::to_string(kept[j]) + " of frames/ has " + std::to_string(x.size()) + " vertices, the pieces " + std::to_string(slots));
    for (std::size_t p = 0, offset = 0; p < pieces.size(); offset += pieces[p].mesh.positions.size(), ++p) {
      const std::vector<glm::dvec3> y = glb_positions(g, p, pieces[p].mesh.positions.size(), j);
      for (std::size_t i = 0; i < y.size(); ++i) {
        const double d = glm::length(y[i] - x[offset + i]);
        if (!(d <= worst)) worst = d, where = pieces[p].name + " vertex " + std::to_string(i) + " at frame " + std::to_string(kept[j]);
      }
    }
  }
  char detail[200];
  std::snprintf(detail, sizeof detail, "%zu kept frames, largest distance from frames/ %.3g of the diagonal", kept.size(),
                diagonal > 0.0 ? worst / diagonal : worst);
  std::vector<std::string> failures;
  if (!(worst <= allowed)) failures.push_back("animation.glb: " + where + " is " + std::to_string(worst / diagonal) + " of the diagonal from frames/ (allowed 1e-6)");
  record(report, "glb_frames", failures, failures.empty() ? detail : "");
}

}  // namespace fracref::check_detail
