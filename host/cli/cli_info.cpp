#include <CLI/CLI.hpp>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "io/mesh_io.hpp"
#include "io/mesh_stats.hpp"

namespace fracref::cli {
namespace {

struct InfoOptions {
  std::string file;
  bool json = false;
};

nlohmann::ordered_json stats_json(const std::string& file, const MeshStats& s) {
  nlohmann::ordered_json j;
  j["file"] = file;
  j["vertices"] = s.vertices;
  j["faces"] = s.faces;
  j["polygons_triangulated"] = s.polygons_triangulated;
  j["boundary_edges"] = s.boundary_edges;
  j["non_manifold_edges"] = s.non_manifold_edges;
  j["non_manifold_vertices"] = s.non_manifold_vertices;
  j["components"] = s.components;
  j["closed"] = s.closed;
  j["bbox"] = {{"min", {s.bbox_min.x, s.bbox_min.y, s.bbox_min.z}},
               {"max", {s.bbox_max.x, s.bbox_max.y, s.bbox_max.z}}};
  return j;
}

int run_info(const InfoOptions& o) {
  MeshSoup soup = read_mesh(o.file);
  MeshStats s = mesh_stats(soup);
  if (o.json) {
    std::cout << stats_json(o.file, s).dump(2) << "\n";
    return 0;
  }
  std::cout << o.file << "\n"
            << "  vertices              " << s.vertices << "\n"
            << "  faces                 " << s.faces << " (triangles";
  if (s.polygons_triangulated) std::cout << "; " << s.polygons_triangulated << " polygons fan-triangulated";
  std::cout << ")\n"
            << "  boundary edges        " << s.boundary_edges << "\n"
            << "  non-manifold edges    " << s.non_manifold_edges << "\n"
            << "  non-manifold vertices " << s.non_manifold_vertices << "\n"
            << "  components            " << s.components << "\n"
            << std::setprecision(6) << "  bounding box          (" << s.bbox_min.x << ", " << s.bbox_min.y << ", "
            << s.bbox_min.z << ") - (" << s.bbox_max.x << ", " << s.bbox_max.y << ", " << s.bbox_max.z << ")\n"
            << "  closed                " << (s.closed ? "yes" : "no") << "\n";
  return 0;
}

}  // namespace

void add_info_command(CLI::App& app, Action& action) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand("info", "Print what the strict mesh reader sees in FILE (OBJ, OFF, PLY)");
  sub->add_option("file", opts->file, "mesh file")->required();
  sub->add_flag("--json", opts->json, "print one JSON object");
  add_threads_option(sub);
  sub->callback([opts, &action] { action = [opts] { return run_info(*opts); }; });
}

}  // namespace fracref::cli
