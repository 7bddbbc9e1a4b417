#pragma once
// What a job writes besides the meshes: report.json, the surface PLY with its per-face pieces and
// per-vertex tree data, and the preview picture.
#include <filesystem>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "animate/animate.hpp"
#include "animate/gltf_writer.hpp"
#include "coarse/animation.hpp"
#include "coarse/coarse_model.hpp"
#include "field/grid.hpp"
#include "flow/timed_backend.hpp"
#include "io/mesh_soup.hpp"
#include "pieces/pieces.hpp"
#include "pipeline/quality.hpp"
#include "pipeline/surface_preview.hpp"
#include "preview/raster.hpp"
#include "refine/refine.hpp"
#include "scene/scene.hpp"

namespace fracref {

/// Builds report.json (keys documented in the README, "Outputs").
class JobReport {
 public:
  JobReport(const Scene& scene, const std::string& backend, std::uint64_t seed);
  void coarse(const CoarseModel& model, const CoarseAnimation& animation);
  /// Triangle counts, iterations, mean_strength, and distance_to_coarse (`diagonal`: B's).
  void refined(const FractureSurface& coarse, const FractureSurface& refined, const RefineResult& result,
               const Grid3& zeta, double diagonal);
  /// `quality`: energy_ratio, weak_fraction {coarse, refined, threshold}, displacement {mean, p95, max}.
  void quality(const SurfaceQuality& q);
  void pieces(const PieceSet& pieces, const PieceReport& checked);
  void animated(const AnimationTransfer& transfer, std::size_t frames_written);
  /// `glb`: bytes, frames_kept, frame_step of animation.glb; a note when frames were dropped.
  void gltf(const GltfSummary& summary);
  void seconds(const std::string& key, double value);
  /// `rim_smoothing`: the passes of rim smoothing made, the scene's or its input's default.
  void rim_smoothing(int passes);
  /// seconds.kernels (their sum) and kernel_seconds / kernel_calls per kernel.
  void kernels(const KernelSeconds& k);
  void note(const std::string& text);
  /// Renders the preview (when the scene asks for one), writes report.json, returns the report.
  nlohmann::ordered_json finish(const std::filesystem::path& out, double total_seconds,
                                const std::function<Image()>& preview);

 private:
  const Scene& scene_;
  nlohmann::ordered_json j_;
};

/// S as PLY: face properties `front`, `back` (the pieces), vertex property `flags`, and with a
/// tree, `parent0..2` and `weight0..2` (the refinement tree). \throw RunError on I/O failure.
void write_surface_ply(const std::filesystem::path& path, const FractureSurface& s, const RefinementTree* tree,
                       const Grid3* zeta = nullptr);

/// Area-weighted mean of ζ over S (ζ trilinear at the corners, averaged per face).
double mean_strength(const FractureSurface& s, const Grid3& zeta);

/// How far the refined surface went from the coarse one: the largest and the area-weighted mean
/// distance of its vertices (faces: the mean of their corners) to the coarse surface, in scene units.
struct CoarseDistance {
  double max = 0.0, mean = 0.0;
};
/// \pre `coarse` has at least one face.
CoarseDistance distance_to_coarse(const FractureSurface& coarse, const FractureSurface& refined);

/// The distance the stress weight allows: beyond diagonal · w_ζ · (ζmax − ζmin) / w_d, the distance
/// term alone makes ψ higher than at any point of the coarse surface (ζ's range over its grid),
/// so no material there is weak enough to draw the surface that far. Infinity when w_d is 0.
double allowed_distance(const WeightsSpec& w, const Grid3& zeta, double diagonal);

/// Every piece side by side at one scale, 1600×1000, each turned so that its fracture faces look
/// at the camera (a piece whose fracture faces look both ways is drawn twice, from each side);
/// fracture faces coloured by the material's own colours when `albedo` is given (sample_albedo:
/// its three channels, sampled at each pixel's point of the piece), else by ζ (surface_preview.hpp)
/// when `zeta` is given, else by their piece; exterior faces light. Implemented in
/// pieces_preview.cpp.
Image preview_pieces(const PieceSet& pieces, const Grid3* zeta = nullptr, const std::array<Grid3, 3>* albedo = nullptr);

/// A contact sheet of `count` frames evenly spread over the animation (4 per row), each frame
/// the pieces at their animated positions, each picture framed on its own; the fracture faces
/// coloured by `color_at` at each pixel's material-space point when it is given (the colours of
/// preview.png), else by their piece.
Image preview_frames(const PieceSet& pieces, const AnimationTransfer& transfer, const CoarseAnimation& animation,
                     int count, const FractureColour& color_at = {});

/// PreviewMesh::paint for piece p drawn with its triangles in order: its exterior faces
/// `exterior`, its fracture faces `colour` at each pixel's point of the piece (the pieces' own,
/// material-space positions). Implemented in pieces_preview.cpp; refers to `pieces` and `colour`.
std::function<glm::vec3(std::size_t, const glm::dvec3&)> paint_piece(const PieceSet& pieces, std::size_t p,
                                                                     const FractureColour& colour, glm::vec3 exterior);

/// Two views side by side: the fracture surface coloured by piece, and the exterior.
Image preview_surface(const FractureSurface& s, const MeshSoup& exterior);

}  // namespace fracref
