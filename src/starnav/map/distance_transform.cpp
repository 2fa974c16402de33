#include "starnav/map/distance_transform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

// Column distance of a column without any obstacle. Real column distances are < height <= 2^31 - 1.
constexpr std::int32_t kNoColumnObstacle = std::numeric_limits<std::int32_t>::max();

// floor(num / (2 d)) for num >= 0, d > 0, given inv_2d = 1 / (2 d). A 64-bit integer division
// costs tens of cycles and sits on the envelope's critical path; a multiplication by a tabled
// reciprocal is off by at most one (rounding, and num may exceed 2^53), which integer
// multiplications then correct exactly.
inline std::int64_t floor_div_2d(std::int64_t num, std::int64_t d, double inv_2d) {
  const std::int64_t den = 2 * d;
  auto q = static_cast<std::int64_t>(static_cast<double>(num) * inv_2d);
  while (q * den > num) --q;
  while ((q + 1) * den <= num) ++q;
  return q;
}

// Runs job(part) for part = 0..parts-1, on `parts` threads (the calling thread takes part 0).
template <class Job>
void run_parts(int parts, const Job& job) {
  if (parts <= 1) {
    job(0);
    return;
  }
  std::vector<std::thread> workers;
  workers.reserve(static_cast<std::size_t>(parts - 1));
  for (int i = 1; i < parts; ++i) workers.emplace_back([&job, i] { job(i); });
  job(0);
  for (auto& t : workers) t.join();
}

}  // namespace

void DistanceTransform::compute(std::span<const std::uint8_t> mask, int width, int height, bool with_nearest,
                                int threads) {
  if (width <= 0 || height <= 0)
    throw Error("distance transform size must be positive, got " + std::to_string(width) + " x " +
                    std::to_string(height),
                {}, 0, "mask");
  if (static_cast<double>(width) * static_cast<double>(height) > 2147483647.0)
    throw Error("distance transform mask has too many cells (" + std::to_string(width) + " x " +
                    std::to_string(height) + ", at most 2^31 - 1)",
                {}, 0, "mask");
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (mask.size() != n)
    throw Error("distance transform mask has " + std::to_string(mask.size()) + " cells, expected " +
                    std::to_string(width) + " x " + std::to_string(height),
                {}, 0, "mask");
  if (threads < 0) throw Error("thread count must be >= 0, got " + std::to_string(threads), {}, 0, "threads");
  if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  // Not more threads than there is work for (a few hundred thousand cells per thread at least).
  threads = static_cast<int>(std::clamp<std::size_t>(n / 262144, 1, static_cast<std::size_t>(threads)));

  width_ = width;
  height_ = height;
  squared_.resize(n);
  if (with_nearest) nearest_.resize(n);
  else nearest_.clear();
  column_dist_.resize(n);

  // Column pass, in bands of whole cache lines of columns.
  {
    const std::size_t w = static_cast<std::size_t>(width_);
    const std::size_t band = ((w + static_cast<std::size_t>(threads) - 1) / static_cast<std::size_t>(threads) + 15) / 16 * 16;
    const int parts = static_cast<int>((w + band - 1) / band);
    run_parts(parts, [&](int part) {
      const std::size_t x0 = static_cast<std::size_t>(part) * band;
      column_pass(mask, x0, std::min(w, x0 + band));
    });
  }

  columns_.clear();
  for (int x = 0; x < width_; ++x)
    if (column_dist_[static_cast<std::size_t>(x)] != kNoColumnObstacle) columns_.push_back(x);
  has_obstacle_ = !columns_.empty();
  if (!has_obstacle_) {
    std::fill(squared_.begin(), squared_.end(), std::numeric_limits<double>::infinity());
    if (with_nearest) std::fill(nearest_.begin(), nearest_.end(), kNoObstacle);
    return;
  }

  inv_2d_.resize(static_cast<std::size_t>(width_));
  inv_2d_[0] = 0.0;
  for (std::size_t d = 1; d < inv_2d_.size(); ++d) inv_2d_[d] = 0.5 / static_cast<double>(d);

  // Row pass, in bands of rows, each band with its own envelope buffers.
  const int parts = std::min(threads, height_);
  if (scratch_.size() < static_cast<std::size_t>(parts)) scratch_.resize(static_cast<std::size_t>(parts));
  run_parts(parts, [&](int part) {
    const int y0 = static_cast<int>(static_cast<std::int64_t>(height_) * part / parts);
    const int y1 = static_cast<int>(static_cast<std::int64_t>(height_) * (part + 1) / parts);
    Envelope& env = scratch_[static_cast<std::size_t>(part)];
    if (with_nearest) row_pass<true>(mask, y0, y1, env);
    else row_pass<false>(mask, y0, y1, env);
  });
}

// Distance to the nearest obstacle in the same column, for columns [x0, x1), by a sweep up and a
// sweep down; both sweeps walk along rows, so every access is sequential (and vectorised).
void DistanceTransform::column_pass(std::span<const std::uint8_t> mask, std::size_t x0, std::size_t x1) {
  const std::size_t w = static_cast<std::size_t>(width_);
  std::int32_t* g = column_dist_.data();
  const std::uint8_t* m = mask.data();
  for (std::size_t x = x0; x < x1; ++x) g[x] = m[x] ? 0 : kNoColumnObstacle;
  for (int y = 1; y < height_; ++y) {
    std::int32_t* row = g + static_cast<std::size_t>(y) * w;
    const std::int32_t* below = row - w;
    const std::uint8_t* mrow = m + static_cast<std::size_t>(y) * w;
    for (std::size_t x = x0; x < x1; ++x) {
      const std::int32_t b = below[x];
      const std::int32_t up = b + (b != kNoColumnObstacle ? 1 : 0);
      row[x] = mrow[x] ? 0 : up;
    }
  }
  for (int y = height_ - 2; y >= 0; --y) {
    std::int32_t* row = g + static_cast<std::size_t>(y) * w;
    const std::int32_t* above = row + w;
    for (std::size_t x = x0; x < x1; ++x) {
      const std::int32_t a = above[x];
      const std::int32_t down = a + (a != kNoColumnObstacle ? 1 : 0);
      row[x] = std::min(row[x], down);
    }
  }
}

// Rows [y0, y1): along every row, the lower envelope of the parabolas (p - q)^2 + g(q)^2 over the
// columns q that hold an obstacle (FH's DT(f) with f = g^2), its breakpoints kept as the integer
// first cell where each parabola is the lowest, so all arithmetic is exact.
template <bool kWithNearest>
void DistanceTransform::row_pass(std::span<const std::uint8_t> mask, int y0, int y1, Envelope& env) {
  const std::size_t w = static_cast<std::size_t>(width_);
  const std::size_t ncols = columns_.size();
  env.site.resize(ncols);
  env.value.resize(ncols);
  env.start.resize(ncols);
  std::int64_t* site = env.site.data();
  std::int64_t* value = env.value.data();
  std::int64_t* start = env.start.data();
  const std::int32_t* cols = columns_.data();
  const double* inv_2d = inv_2d_.data();
  const std::int64_t width64 = width_;
  // Rows [y0, y1) of the results belong to this call alone (bands run on separate threads).
  double* const squared = squared_.data();
  std::int32_t* const nearest_all = kWithNearest ? nearest_.data() : nullptr;

  for (int y = y0; y < y1; ++y) {
    const std::size_t row_offset = static_cast<std::size_t>(y) * w;
    const std::int32_t* g = column_dist_.data() + row_offset;

    // Build the envelope. Entries 0..k-1 live in the arrays, the top one (tv, tf, tt) in
    // registers, since every new column is compared against it.
    std::int64_t tv = cols[0];
    std::int64_t tf = static_cast<std::int64_t>(g[tv]) * g[tv];
    std::int64_t tt = 0;
    std::ptrdiff_t k = 0;
    for (std::size_t c = 1; c < ncols; ++c) {
      const std::int64_t q = cols[c];
      const std::int64_t gq = g[q];
      const std::int64_t fq = gq * gq;
      // Drop the top parabola while q is strictly lower where the top starts being the lowest:
      // then the top is lowest nowhere (q stays lower from there on, earlier parabolas win
      // before). When q beats even the first parabola at cell 0, q becomes the first.
      bool replaced_all = false;
      for (;;) {
        const std::int64_t dv = tt - tv, dq = tt - q;
        if (dv * dv + tf <= dq * dq + fq) break;
        if (k == 0) {
          tv = q;
          tf = fq;
          tt = 0;
          replaced_all = true;
          break;
        }
        --k;
        tv = site[k];
        tf = value[k];
        tt = start[k];
      }
      if (replaced_all) continue;
      // First cell p where q is strictly lower than the top parabola (v, fv):
      //   (p - q)^2 + fq < (p - v)^2 + fv  <=>  2p(q - v) > q^2 - v^2 + fq - fv.
      // The numerator is >= 0 because q is not lower at tt >= 0. Ties stay with the lower column.
      const std::int64_t num = q * q - tv * tv + fq - tf;
      const std::int64_t p = floor_div_2d(num, q - tv, inv_2d[q - tv]) + 1;
      if (p < width64) {
        site[k] = tv;
        value[k] = tf;
        start[k] = tt;
        ++k;
        tv = q;
        tf = fq;
        tt = p;
      }
    }
    site[k] = tv;
    value[k] = tf;
    start[k] = tt;

    // Read the envelope out, one parabola's run of cells at a time.
    double* out = squared + row_offset;
    for (std::ptrdiff_t j = 0; j <= k; ++j) {
      const std::int64_t vx = site[j];
      const std::int64_t fv = value[j];
      const std::int64_t begin = start[j];
      const std::int64_t end = j < k ? start[j + 1] : width64;
      for (std::int64_t p = begin; p < end; ++p) out[p] = static_cast<double>((p - vx) * (p - vx) + fv);
      if constexpr (kWithNearest) {
        // The obstacle is g rows below or above (or both; then the lower row is taken).
        const std::int64_t gy = g[vx];
        const std::int64_t below = static_cast<std::int64_t>(y) - gy;
        const bool use_below =
            below >= 0 && mask[static_cast<std::size_t>(below) * w + static_cast<std::size_t>(vx)] != 0;
        const std::int64_t ry = use_below ? below : static_cast<std::int64_t>(y) + gy;
        const auto index = static_cast<std::int32_t>(ry * width64 + vx);
        std::fill(nearest_all + row_offset + begin, nearest_all + row_offset + end, index);
      }
    }
  }
}

std::vector<double> squared_distance_transform(std::span<const std::uint8_t> mask, int width, int height,
                                               std::vector<std::int32_t>* nearest, int threads) {
  DistanceTransform dt;
  dt.compute(mask, width, height, nearest != nullptr, threads);
  if (nearest) *nearest = dt.take_nearest();
  return dt.take_squared_cells();
}

std::vector<double> obstacle_distance_m(const OccupancyGrid& grid, const OccupancyThresholds& thresholds,
                                        bool unknown_is_obstacle, std::vector<std::int32_t>* nearest, int threads) {
  if (grid.cell_count() == 0) throw Error("distance transform of an empty occupancy grid", {}, 0, "map");
  const std::vector<std::uint8_t> mask = grid.blocked_mask(thresholds, !unknown_is_obstacle);
  std::vector<double> d = squared_distance_transform(mask, grid.width(), grid.height(), nearest, threads);
  const double res = grid.resolution();
  for (double& v : d) v = std::sqrt(v) * res;  // sqrt(+inf) = +inf
  return d;
}

}  // namespace starnav
