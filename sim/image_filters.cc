#include "sim/image_filters.h"

#include <algorithm>
#include <cmath>

namespace calibench {

// Adds N(0, sigma^2) noise to every pixel. Normals come from a table of kNoiseTable standard
// normals drawn once (Box-Muller from a fixed seed), in kBlocks blocks of kBlockLength entries. A
// row is cut into segments of at most kSegment pixels. The frame takes two draws from `rng`, a
// and b; its segment s reads block (a + s b) mod kBlocks (b odd: a frame's segments read distinct
// blocks, so its noise is iid Gaussian) from an offset in [0, kBlockLength - kSegment] hashed from
// the two draws and s. Frames reuse the table's entries, each time at a pixel of its own. The
// offset keeps frames independent in expectation: read from a block's start, column x would
// always hold entry x of some block, and every frame would share the table's column means (sd
// sigma / sqrt(kBlocks): 0.03 gray levels at sigma = 2 with 4096 blocks), a fixed pattern common
// to all trials. Frames with more segments than blocks (more than 2048 rows of <= 1024 px, 1024
// rows of <= 2048 px) draw every normal from `rng` (Box-Muller: 6x slower).
void AddImageNoise(double sigma, int width, int height, Rng* rng, std::vector<float>* values) {
  constexpr size_t kNoiseTable = size_t{1} << 22, kBlockLength = size_t{1} << 11;
  constexpr size_t kSegment = kBlockLength / 2, kBlocks = kNoiseTable / kBlockLength;
  static const std::vector<float> table = [] {
    std::vector<float> t(kNoiseTable);
    Rng table_rng(0x6e6f697365ULL);  // "noise"
    for (float& v : t) v = static_cast<float>(table_rng.Normal());
    return t;
  }();
  const size_t segments_per_row = (static_cast<size_t>(width) + kSegment - 1) / kSegment;
  if (segments_per_row * height > kBlocks) {
    for (float& v : *values) v += static_cast<float>(sigma * rng->Normal());
    return;
  }
  const uint64_t draw_a = rng->NextU64(), draw_b = rng->NextU64();
  const size_t a = draw_a % kBlocks, b = (draw_b % kBlocks) | 1;
  const uint64_t offset_key = Mix64(draw_a ^ Mix64(draw_b));
  constexpr size_t kOffsets = kBlockLength - kSegment + 1;
  const float s = static_cast<float>(sigma);
  size_t r = 0;
  for (int y = 0; y < height; ++y) {
    float* row = values->data() + static_cast<size_t>(y) * width;
    for (size_t c = 0; c < segments_per_row; ++c, ++r) {
      const float* normals =
          table.data() + ((a + r * b) % kBlocks) * kBlockLength + Mix64(offset_key + r) % kOffsets;
      const size_t from = c * kSegment;
      const size_t to = std::min(static_cast<size_t>(width), from + kSegment);
      for (size_t x = from; x < to; ++x) row[x] += s * normals[x - from];
    }
  }
}

namespace {

// exp(-k^2 / (2 sigma^2)) for k in [-radius, radius] into *g (not normalised); returns their sum.
float SampledGaussian(double sigma, int radius, std::vector<float>* g) {
  g->resize(2 * radius + 1);
  float sum = 0;
  for (int k = -radius; k <= radius; ++k) {
    sum += (*g)[k + radius] = static_cast<float>(std::exp(-0.5 * k * k / (sigma * sigma)));
  }
  return sum;
}

}  // namespace

// Blurs the pixels of [x0, x1) x [y0, y1) (clamped to the image) with a Gaussian of `sigma`,
// edges clamped. Exact for the whole image when everything outside the box is farther than the
// kernel's radius from anything but one constant gray (the background): such pixels keep their
// value under the blur.
void GaussianBlur(double sigma, int width, int height, const PixelBox& box,
                  std::vector<float>* image) {
  int x0 = box.x0, x1 = box.x1, y0 = box.y0, y1 = box.y1;
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  std::vector<float> kernel;
  const float sum = SampledGaussian(sigma, radius, &kernel);
  for (float& k : kernel) k /= sum;
  x0 = std::max(0, x0), y0 = std::max(0, y0);
  x1 = std::min(width, x1), y1 = std::min(height, y1);
  if (x0 >= x1 || y0 >= y1) return;
  // Horizontal pass over the rows the vertical pass reads; columns outside [x0, x1) are read
  // from the image itself (their horizontal blur is their value, see above).
  const int ty0 = std::max(0, y0 - radius), ty1 = std::min(height, y1 + radius);
  thread_local std::vector<float> tmp;
  tmp.resize(static_cast<size_t>(ty1 - ty0) * (x1 - x0));
  auto clamp_index = [](int i, int n) { return std::clamp(i, 0, n - 1); };
  for (int y = ty0; y < ty1; ++y) {
    const float* row = image->data() + static_cast<size_t>(y) * width;
    float* out = tmp.data() + static_cast<size_t>(y - ty0) * (x1 - x0);
    for (int x = x0; x < x1; ++x) {
      float acc = 0;
      if (x >= radius && x + radius < width) {
        for (int k = -radius; k <= radius; ++k) acc += kernel[k + radius] * row[x + k];
      } else {
        for (int k = -radius; k <= radius; ++k)
          acc += kernel[k + radius] * row[clamp_index(x + k, width)];
      }
      out[x - x0] = acc;
    }
  }
  auto tmp_at = [&](int x, int y) {
    return tmp[static_cast<size_t>(y - ty0) * (x1 - x0) + (x - x0)];
  };
  for (int y = y0; y < y1; ++y) {
    float* row = image->data() + static_cast<size_t>(y) * width;
    for (int x = x0; x < x1; ++x) {
      float acc = 0;
      for (int k = -radius; k <= radius; ++k)
        acc += kernel[k + radius] * tmp_at(x, std::clamp(y + k, ty0, ty1 - 1));
      row[x] = acc;
    }
  }
}

// Blurs the pixels within the kernel's reach of the boards' box (x0, x1, y0, y1): the background
// elsewhere is one gray, which the blur keeps.
void BlurNearBoards(double sigma, int width, int height, const std::array<int, 4>& box,
                    std::vector<float>* image) {
  if (box[0] > box[1] || box[2] > box[3]) return;  // No board in view.
  const int margin = 2 * static_cast<int>(std::ceil(3 * sigma)) + 2;
  GaussianBlur(sigma, width, height,
               {box[0] - margin, box[1] + margin, box[2] - margin, box[3] + margin}, image);
}

void BlurNearBoardsAndSumBlocks(double sigma, int width, int height, int m,
                                const std::array<int, 4>& box, const std::vector<float>& fine,
                                std::vector<float>* pixels) {
  const size_t fine_width = static_cast<size_t>(width) * m;
  // The pixels whose blocks meet BlurNearBoards' region; empty without a board in view.
  const int radius = static_cast<int>(std::ceil(3 * sigma)), margin = 2 * radius + 2;
  const int fw = width * m, fh = height * m;
  int px0 = width, px1 = 0, py0 = height, py1 = 0;
  if (box[0] <= box[1] && box[2] <= box[3]) {
    px0 = std::max(0, box[0] - margin) / m;
    px1 = std::min(width, (std::min(fw, box[1] + margin) + m - 1) / m);
    py0 = std::max(0, box[2] - margin) / m;
    py1 = std::min(height, (std::min(fh, box[3] + margin) + m - 1) / m);
  }
  const PixelBox region{px0, px1, py0, py1};
  SumBlocks(fine, width, height, m, pixels, &region);  // Outside it: the plain block means.
  if (px0 >= px1 || py0 >= py1) return;
  // The Gaussian as GaussianBlur samples it, convolved with the m-box and divided by m:
  // pixel i = sum_a kernel[a] fine[m i + a - radius] along each axis.
  std::vector<float> g;
  const float g_sum = SampledGaussian(sigma, radius, &g);
  const int taps = 2 * radius + m;
  std::vector<float> kernel(taps, 0.0f);
  for (int a = 0; a < taps; ++a) {
    for (int s = 0; s < m; ++s) {
      if (a - s >= 0 && a - s <= 2 * radius) kernel[a] += g[a - s] / g_sum;
    }
    kernel[a] /= static_cast<float>(m);
  }
  // Horizontal pass at the pixels' columns, over the sub-pixel rows the vertical pass reads
  // (edges clamped, as GaussianBlur).
  const int nx = px1 - px0;
  const int fy0 = std::max(0, m * py0 - radius), fy1 = std::min(fh, m * py1 + radius);
  thread_local std::vector<float> tmp;
  tmp.resize(static_cast<size_t>(fy1 - fy0) * nx);
  for (int fy = fy0; fy < fy1; ++fy) {
    const float* row = fine.data() + static_cast<size_t>(fy) * fine_width;
    float* out = tmp.data() + static_cast<size_t>(fy - fy0) * nx;
    for (int i = px0; i < px1; ++i) {
      const int first = m * i - radius;
      float acc = 0;
      if (first >= 0 && first + taps <= fw) {
        for (int a = 0; a < taps; ++a) acc += kernel[a] * row[first + a];
      } else {
        for (int a = 0; a < taps; ++a) acc += kernel[a] * row[std::clamp(first + a, 0, fw - 1)];
      }
      out[i - px0] = acc;
    }
  }
  // Vertical pass at the pixels' rows.
  for (int j = py0; j < py1; ++j) {
    float* out = pixels->data() + static_cast<size_t>(j) * width + px0;
    std::fill(out, out + nx, 0.0f);
    for (int a = 0; a < taps; ++a) {
      const int fy = std::clamp(m * j + a - radius, 0, fh - 1);
      const float* row = tmp.data() + static_cast<size_t>(fy - fy0) * nx;
      const float k = kernel[a];
      for (int i = 0; i < nx; ++i) out[i] += k * row[i];
    }
  }
}

// The mean of each m x m block of a (width m) x (height m) image: the pixels of a finer grid.
void SumBlocks(const std::vector<float>& fine, int width, int height, int m,
               std::vector<float>* pixels, const PixelBox* skip) {
  pixels->resize(static_cast<size_t>(width) * height);
  const size_t fine_width = static_cast<size_t>(width) * m;
  const float inv = 1.0f / static_cast<float>(m * m);
  auto sum_columns = [&](int j, int i0, int i1) {
    float* row = pixels->data() + static_cast<size_t>(j) * width;
    std::fill(row + i0, row + i1, 0.0f);
    for (int b = 0; b < m; ++b) {
      const float* fine_row = fine.data() + (static_cast<size_t>(j) * m + b) * fine_width;
      for (int i = i0; i < i1; ++i) {
        for (int a = 0; a < m; ++a) row[i] += fine_row[i * m + a];
      }
    }
    for (int i = i0; i < i1; ++i) row[i] *= inv;
  };
  for (int j = 0; j < height; ++j) {
    if (skip && j >= skip->y0 && j < skip->y1 && skip->x0 < skip->x1) {
      sum_columns(j, 0, std::clamp(skip->x0, 0, width));
      sum_columns(j, std::clamp(skip->x1, 0, width), width);
    } else {
      sum_columns(j, 0, width);
    }
  }
}

}  // namespace calibench
