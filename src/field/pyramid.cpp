#include "field/pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

// Below this many outputs a pass is cheaper than starting a thread.
constexpr std::size_t kMinOutputsPerThread = 8192;

// One 1D pass along `axis`. Output coordinate c along the axis reads source coordinate
// step*c (step 2 decimates, step 1 blurs in place); the other coordinates are shared.
struct Pass {
  const float* src;
  glm::uvec3 src_dims;
  float* dst;
  glm::uvec3 dst_dims;
  int axis;
  unsigned step;
  const std::vector<float>* weights;
};

// The x pass reads along a row; the interior skips the clamp, which changes no value.
void run_pass_x(const Pass& p, unsigned z0, unsigned z1) {
  const float* w = p.weights->data();
  const int r = int(p.weights->size() / 2);
  const int n = int(p.src_dims.x);
  for (unsigned z = z0; z < z1; ++z) {
    for (unsigned y = 0; y < p.dst_dims.y; ++y) {
      const float* src = p.src + std::size_t(n) * (y + std::size_t(p.src_dims.y) * z);
      float* dst = p.dst + std::size_t(p.dst_dims.x) * (y + std::size_t(p.dst_dims.y) * z);
      for (unsigned x = 0; x < p.dst_dims.x; ++x) {
        const int c = int(p.step * x);
        float acc = 0.0f;
        if (c - r >= 0 && c + r < n) {
          for (int k = -r; k <= r; ++k) acc += w[k + r] * src[c + k];
        } else {
          for (int k = -r; k <= r; ++k) acc += w[k + r] * src[std::clamp(c + k, 0, n - 1)];
        }
        dst[x] = acc;
      }
    }
  }
}

// The y and z passes accumulate whole rows (y) or planes (z) at once: the same per-node order
// of operations as the x pass, in a loop the compiler vectorises.
void accumulate_line(const Pass& p, const float* src, std::size_t src_stride, int c, float* dst,
                     std::size_t len) {
  const float* w = p.weights->data();
  const int r = int(p.weights->size() / 2);
  const int n = int(p.src_dims[p.axis]);
  std::fill(dst, dst + len, 0.0f);
  for (int k = -r; k <= r; ++k) {
    const float wk = w[k + r];
    const float* s = src + src_stride * std::size_t(std::clamp(c + k, 0, n - 1));
    for (std::size_t i = 0; i < len; ++i) dst[i] += wk * s[i];
  }
}

void run_pass_yz(const Pass& p, unsigned z0, unsigned z1) {
  const std::size_t nx = p.dst_dims.x;  // the x extent is shared by source and destination
  const std::size_t row_stride = p.src_dims.x;
  const std::size_t plane = std::size_t(p.src_dims.x) * p.src_dims.y;
  for (unsigned z = z0; z < z1; ++z) {
    if (p.axis == 1) {
      for (unsigned y = 0; y < p.dst_dims.y; ++y) {
        accumulate_line(p, p.src + plane * z, row_stride, int(p.step * y),
                        p.dst + nx * (y + std::size_t(p.dst_dims.y) * z), nx);
      }
    } else {
      accumulate_line(p, p.src, plane, int(p.step * z), p.dst + plane * z, plane);
    }
  }
}

void run_pass_range(const Pass& p, unsigned z0, unsigned z1) {
  if (p.axis == 0) {
    run_pass_x(p, z0, z1);
  } else {
    run_pass_yz(p, z0, z1);
  }
}

// Splits the output's z range into slabs; each node is computed by exactly one thread with the
// same operations, so the result does not depend on the thread count.
void run_pass(const Pass& p, int threads) {
  const unsigned nz = p.dst_dims.z;
  const std::size_t outputs = std::size_t(p.dst_dims.x) * p.dst_dims.y * nz;
  if (threads < 2 || nz < 2 || outputs < 2 * kMinOutputsPerThread) {
    run_pass_range(p, 0, nz);
    return;
  }
  const std::size_t slabs = std::min<std::size_t>({nz, 64, outputs / kMinOutputsPerThread});
  parallel_chunks(nz, slabs, threads,
                  [&](std::size_t, std::size_t z0, std::size_t z1) { run_pass_range(p, unsigned(z0), unsigned(z1)); });
}

glm::uvec3 pass_dims(glm::uvec3 dims, int axis, unsigned step) {
  if (step == 2) dims[axis] = (dims[axis] + 1) / 2;
  return dims;
}

// Three passes x, y, z; step 2 keeps only the nodes the downsample keeps.
std::vector<float> blur3(const std::vector<float>& src, glm::uvec3 dims, const std::vector<float>& weights,
                         unsigned step, int threads, glm::uvec3* out_dims) {
  std::vector<float> a, b;
  const float* in = src.data();
  for (int axis = 0; axis < 3; ++axis) {
    const glm::uvec3 next = pass_dims(dims, axis, step);
    b.resize(std::size_t(next.x) * next.y * next.z);
    run_pass(Pass{in, dims, b.data(), next, axis, step, &weights}, threads);
    std::swap(a, b);
    in = a.data();
    dims = next;
  }
  *out_dims = dims;
  return a;
}

void check_sigma(float sigma) {
  if (!(sigma > 0.0f) || !std::isfinite(sigma)) {
    throw InputError("pyramid: sigma " + std::to_string(sigma) + " must be positive and finite");
  }
  if (std::ceil(3.0f * sigma) > float(kMaxBlurRadius)) {
    throw InputError("pyramid: sigma " + std::to_string(sigma) + " gives a blur radius above " +
                     std::to_string(kMaxBlurRadius) + " cells");
  }
}

void check_grid(const Grid3& grid) {
  if (grid.dims.x < 1 || grid.dims.y < 1 || grid.dims.z < 1) {
    throw InputError("pyramid: grid dims " + std::to_string(grid.dims.x) + "x" + std::to_string(grid.dims.y) +
                     "x" + std::to_string(grid.dims.z) + " must all be >= 1");
  }
  if (grid.values.size() != grid.size()) {
    throw InputError("pyramid: grid holds " + std::to_string(grid.values.size()) + " values, dims need " +
                     std::to_string(grid.size()));
  }
}

void check_threads(int threads) {
  if (threads < 1) {
    throw InputError("pyramid: threads " + std::to_string(threads) + " must be at least 1");
  }
}

}  // namespace

std::vector<float> gaussian_weights(float sigma) {
  check_sigma(sigma);
  const int r = int(std::ceil(3.0f * sigma));
  std::vector<double> w(2 * r + 1);
  double sum = 0.0;
  for (int k = -r; k <= r; ++k) {
    w[k + r] = std::exp(-double(k) * k / (2.0 * double(sigma) * sigma));
    sum += w[k + r];
  }
  std::vector<float> out(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) out[i] = float(w[i] / sum);
  return out;
}

void check_pyramid_input(const Grid3& base, const PyramidOptions& options) {
  if (options.levels < 1 || options.levels > 8) {
    throw InputError("pyramid: levels " + std::to_string(options.levels) + " outside [1, 8]");
  }
  check_sigma(options.sigma);
  check_threads(options.threads);
  check_grid(base);
}

std::vector<glm::uvec3> pyramid_level_dims(glm::uvec3 base_dims, int levels) {
  std::vector<glm::uvec3> dims{base_dims};
  for (int l = 1; l < levels; ++l) dims.push_back((dims.back() + 1u) / 2u);
  return dims;
}

std::vector<Grid3> build_pyramid_cpu(const Grid3& base, const PyramidOptions& options) {
  check_pyramid_input(base, options);
  const std::vector<float> weights = gaussian_weights(options.sigma);
  std::vector<Grid3> levels{base};
  levels.reserve(options.levels);
  for (int l = 1; l < options.levels; ++l) {
    const Grid3& fine = levels.back();
    Grid3 coarse;
    coarse.origin = base.origin;
    coarse.cell = fine.cell * 2.0;
    coarse.values = blur3(fine.values, fine.dims, weights, 2, options.threads, &coarse.dims);
    levels.push_back(std::move(coarse));
  }
  return levels;
}

Grid3 blur_cpu(const Grid3& grid, float sigma, int threads) {
  check_grid(grid);
  check_threads(threads);
  const std::vector<float> weights = gaussian_weights(sigma);
  Grid3 out;
  out.origin = grid.origin;
  out.cell = grid.cell;
  out.values = blur3(grid.values, grid.dims, weights, 1, threads, &out.dims);
  return out;
}

}  // namespace fracref
