#include "frontends/laser/scan_matcher.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <unordered_map>

namespace slam {
namespace {

// The two 32-bit cell indices packed into one key (unsigned: shifting a
// negative signed value is undefined).
uint64_t CellKey(int ix, int iy) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) |
         static_cast<uint32_t>(iy);
}

// floor(v) as a cell index, saturated at +-2^30 cells (far beyond any grid
// or search window; NaN goes to the low end), so that the conversion to int
// is always defined and index arithmetic near it cannot overflow.
int FloorToCell(double v) {
  constexpr int kLimit = 1 << 30;
  const double f = std::floor(v);
  if (!(f > -kLimit)) return -kLimit;
  if (f > kLimit) return kLimit;
  return static_cast<int>(f);
}

// d/dtheta of R(theta) p, for R = I: (-p.y, p.x).
Eigen::Vector2d Perp(const Eigen::Vector2d& p) {
  return Eigen::Vector2d(-p.y(), p.x());
}

}  // namespace

Points2 TransformPoints(const Pose2& pose, const Points2& points) {
  const Eigen::Matrix2d r = RotationMatrix2D(pose.theta);
  Points2 out;
  out.reserve(points.size());
  for (const Eigen::Vector2d& p : points) out.push_back(r * p + pose.t);
  return out;
}

Points2 RangesToPoints(const std::vector<float>& ranges, double angle_min,
                       double angle_increment, double min_range,
                       double max_range) {
  Points2 points;
  points.reserve(ranges.size());
  for (size_t i = 0; i < ranges.size(); ++i) {
    const double r = ranges[i];
    if (!std::isfinite(r) || r < min_range || r >= max_range) continue;
    const double a = angle_min + static_cast<double>(i) * angle_increment;
    points.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return points;
}

Points2 VoxelFilter(const Points2& points, double cell) {
  std::unordered_map<uint64_t, int> index;
  index.reserve(points.size() * 2);
  Points2 sums;
  std::vector<int> counts;
  for (const Eigen::Vector2d& p : points) {
    const uint64_t key =
        CellKey(FloorToCell(p.x() / cell), FloorToCell(p.y() / cell));
    auto [it, inserted] = index.emplace(key, static_cast<int>(sums.size()));
    if (inserted) {
      sums.push_back(p);
      counts.push_back(1);
    } else {
      sums[it->second] += p;
      ++counts[it->second];
    }
  }
  for (size_t i = 0; i < sums.size(); ++i) sums[i] /= counts[i];
  return sums;
}

void MatchTarget::Build(Points2 points, double cell_size,
                        double normal_radius) {
  points_ = std::move(points);
  cell_size_ = cell_size;
  likelihood_ = LikelihoodGrids();
  normals_.assign(points_.size(), Eigen::Vector2d::Zero());
  has_normal_.assign(points_.size(), 0);
  cell_start_.clear();
  cell_points_.clear();
  grid_width_ = grid_height_ = 0;
  if (points_.empty()) return;
  Eigen::Vector2d lo = points_[0], hi = points_[0];
  for (const Eigen::Vector2d& p : points_) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  origin_ = lo;
  grid_width_ = static_cast<int>((hi.x() - lo.x()) / cell_size_) + 1;
  grid_height_ = static_cast<int>((hi.y() - lo.y()) / cell_size_) + 1;
  const int num_cells = grid_width_ * grid_height_;
  std::vector<int> cell_of(points_.size());
  cell_start_.assign(num_cells + 1, 0);
  for (size_t i = 0; i < points_.size(); ++i) {
    const int ix =
        std::min(grid_width_ - 1,
                 static_cast<int>((points_[i].x() - lo.x()) / cell_size_));
    const int iy =
        std::min(grid_height_ - 1,
                 static_cast<int>((points_[i].y() - lo.y()) / cell_size_));
    cell_of[i] = iy * grid_width_ + ix;
    ++cell_start_[cell_of[i] + 1];
  }
  for (int c = 0; c < num_cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_points_.resize(points_.size());
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i) {
    cell_points_[fill[cell_of[i]]++] = static_cast<int>(i);
  }

  // Normals: principal axes of the neighbourhood.
  const double r2 = normal_radius * normal_radius;
  const int ring = static_cast<int>(std::ceil(normal_radius / cell_size_));
  for (size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector2d& p = points_[i];
    const int cx = cell_of[i] % grid_width_, cy = cell_of[i] / grid_width_;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d outer = Eigen::Matrix2d::Zero();
    int n = 0;
    for (int y = std::max(0, cy - ring);
         y <= std::min(grid_height_ - 1, cy + ring); ++y) {
      for (int x = std::max(0, cx - ring);
           x <= std::min(grid_width_ - 1, cx + ring); ++x) {
        const int c = y * grid_width_ + x;
        for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          const Eigen::Vector2d& q = points_[cell_points_[k]];
          if ((q - p).squaredNorm() > r2) continue;
          sum += q;
          outer += q * q.transpose();
          ++n;
        }
      }
    }
    if (n < 3) {
      // Sparse neighbourhood (far from the sensor): the line through the
      // nearest other point within a wider radius, as in PL-ICP.
      int nearest = -1;
      double best = 16.0 * r2;
      const int wide = 4 * ring;
      for (int y = std::max(0, cy - wide);
           y <= std::min(grid_height_ - 1, cy + wide); ++y) {
        for (int x = std::max(0, cx - wide);
             x <= std::min(grid_width_ - 1, cx + wide); ++x) {
          const int c = y * grid_width_ + x;
          for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
            const int j = cell_points_[k];
            const double d2 = (points_[j] - p).squaredNorm();
            if (j != static_cast<int>(i) && d2 < best && d2 > 1e-12) {
              best = d2;
              nearest = j;
            }
          }
        }
      }
      if (nearest < 0) continue;
      const Eigen::Vector2d dir = (points_[nearest] - p).normalized();
      normals_[i] = Eigen::Vector2d(-dir.y(), dir.x());
      has_normal_[i] = 1;
      continue;
    }
    const Eigen::Vector2d mean = sum / n;
    const Eigen::Matrix2d cov = outer / n - mean * mean.transpose();
    const double a = cov(0, 0), b = cov(0, 1), c = cov(1, 1);
    const double half_diff = 0.5 * (a - c);
    const double root = std::sqrt(half_diff * half_diff + b * b);
    const double l_max = 0.5 * (a + c) + root, l_min = 0.5 * (a + c) - root;
    if (!(l_max > 0) || l_min > 0.1 * l_max) continue;    // No dominant line.
    const double phi = 0.5 * std::atan2(2.0 * b, a - c);  // Line direction.
    normals_[i] = Eigen::Vector2d(-std::sin(phi), std::cos(phi));
    has_normal_[i] = 1;
  }
}

int MatchTarget::Nearest(const Eigen::Vector2d& query,
                         double max_distance) const {
  if (points_.empty()) return -1;
  const int ring = static_cast<int>(std::ceil(max_distance / cell_size_));
  const double fx = (query.x() - origin_.x()) / cell_size_;
  const double fy = (query.y() - origin_.y()) / cell_size_;
  if (fx < -ring - 1 || fy < -ring - 1 || fx > grid_width_ + ring ||
      fy > grid_height_ + ring) {
    return -1;
  }
  const int cx = FloorToCell(fx);
  const int cy = FloorToCell(fy);
  double best = max_distance * max_distance;
  int best_index = -1;
  for (int y = std::max(0, cy - ring);
       y <= std::min(grid_height_ - 1, cy + ring); ++y) {
    for (int x = std::max(0, cx - ring);
         x <= std::min(grid_width_ - 1, cx + ring); ++x) {
      const int c = y * grid_width_ + x;
      for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const double d2 = (points_[cell_points_[k]] - query).squaredNorm();
        if (d2 < best) {
          best = d2;
          best_index = cell_points_[k];
        }
      }
    }
  }
  return best_index;
}

MatchResult MatchTarget::Icp(const Points2& source, const Pose2& initial,
                             const IcpOptions& options,
                             const IcpPrior* prior) const {
  MatchResult result;
  result.pose = initial;
  result.num_points = static_cast<int>(source.size());
  if (points_.empty() || source.size() < 3) return result;
  Pose2 x = initial;
  Eigen::Matrix3d h;
  double weighted_r2 = 0.0;
  int n = 0;
  // One association + linearization at x; fills h, g and the statistics.
  auto linearize = [&](Eigen::Vector3d* g, bool stats) {
    h.setZero();
    g->setZero();
    weighted_r2 = 0.0;
    n = 0;
    double inlier_r2 = 0.0;
    int inliers = 0;
    const Eigen::Matrix2d r = RotationMatrix2D(x.theta);
    for (const Eigen::Vector2d& p : source) {
      const Eigen::Vector2d q = r * p + x.t;
      const int k = Nearest(q, options.max_correspondence_distance);
      if (k < 0) continue;
      if (!has_normal_[k]) continue;
      const Eigen::Vector2d& normal = normals_[k];
      const double res = normal.dot(q - points_[k]);
      // Right perturbation: q(delta) = R Exp(dtheta) p + t + R dt.
      const Eigen::Vector2d nr = r.transpose() * normal;
      const Eigen::Vector3d j(nr.x(), nr.y(), nr.dot(Perp(p)));
      const double abs_res = std::abs(res);
      const double w =
          abs_res <= options.huber_width ? 1.0 : options.huber_width / abs_res;
      h += w * j * j.transpose();
      *g += w * j * res;
      weighted_r2 += w * res * res;
      ++n;
      if (stats && abs_res < options.inlier_distance) {
        ++inliers;
        inlier_r2 += res * res;
      }
    }
    if (stats) {
      result.num_correspondences = n;
      result.num_inliers = inliers;
      result.rmse = inliers > 0 ? std::sqrt(inlier_r2 / inliers) : 0.0;
    }
  };
  Eigen::Vector3d g;
  int iteration = 0;
  for (; iteration < options.max_iterations; ++iteration) {
    linearize(&g, false);
    if (n < 3) break;
    Eigen::Matrix3d h_total = h;
    if (prior != nullptr) {
      const Eigen::Matrix2d rp = RotationMatrix2D(prior->pose.theta);
      const Eigen::Vector3d e((rp.transpose() * (x.t - prior->pose.t)).x(),
                              (rp.transpose() * (x.t - prior->pose.t)).y(),
                              NormalizeAngle(x.theta - prior->pose.theta));
      Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
      j.topLeftCorner<2, 2>() = rp.transpose() * RotationMatrix2D(x.theta);
      h_total += j.transpose() * prior->information * j;
      g += j.transpose() * prior->information * e;
    }
    const double damping = 1e-9 * (h_total.trace() + 1e-12);
    Eigen::Vector3d delta =
        -(h_total + damping * Eigen::Matrix3d::Identity()).ldlt().solve(g);
    if (!delta.allFinite()) break;
    // A step along a direction the points barely constrain (a corridor)
    // can be huge; the correspondences are only valid nearby.
    const double step = delta.head<2>().norm();
    const double scale = std::min(
        {1.0, options.max_step_translation / std::max(step, 1e-12),
         options.max_step_rotation / std::max(std::abs(delta[2]), 1e-12)});
    delta *= scale;
    x.t += RotationMatrix2D(x.theta) * delta.head<2>();
    x.theta = NormalizeAngle(x.theta + delta[2]);
    if (delta.head<2>().norm() < options.translation_tolerance &&
        std::abs(delta[2]) < options.rotation_tolerance) {
      ++iteration;
      break;
    }
  }
  result.iterations = iteration;
  result.pose = x;
  linearize(&g, true);
  result.fitness =
      result.num_points > 0
          ? static_cast<double>(result.num_inliers) / result.num_points
          : 0.0;
  if (n < 10) return result;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(h);
  if (!(eig.eigenvalues()[0] > 1e-9 * eig.eigenvalues()[2])) return result;
  const double sigma2 = std::max(options.sigma_min * options.sigma_min,
                                 weighted_r2 / std::max(1, n - 3));
  result.covariance = options.covariance_scale * sigma2 * h.inverse();
  result.covariance = 0.5 * (result.covariance + result.covariance.transpose());
  result.success = true;
  return result;
}

void MatchTarget::BuildLikelihood(const CorrelativeOptions& options,
                                  const Eigen::Vector2d& want_lo,
                                  const Eigen::Vector2d& want_hi) const {
  LikelihoodGrids& l = likelihood_;
  const double res = options.resolution;
  const int kernel = static_cast<int>(std::ceil(3.0 * options.sigma / res));
  const double reach = (kernel + 1) * res;
  Eigen::Vector2d target_lo = points_[0], target_hi = points_[0];
  for (const Eigen::Vector2d& p : points_) {
    target_lo = target_lo.cwiseMin(p);
    target_hi = target_hi.cwiseMax(p);
  }
  target_lo.array() -= reach;
  target_hi.array() += reach;
  // Only the part of the request where the likelihood can be non-zero.
  const Eigen::Vector2d need_lo = want_lo.cwiseMax(target_lo);
  const Eigen::Vector2d need_hi = want_hi.cwiseMin(target_hi);
  if (l.resolution == options.resolution && l.sigma == options.sigma &&
      l.levels == std::max(0, options.levels) && !l.pyramid.empty() &&
      (need_lo.array() >= l.valid_lo.array()).all() &&
      (need_hi.array() <= l.valid_hi.array()).all()) {
    return;
  }
  l.resolution = options.resolution;
  l.sigma = options.sigma;
  l.levels = std::max(0, options.levels);
  // Some slack so that nearby queries (tracking) reuse the grids.
  const double margin = std::max(0.0, options.grid_margin);
  l.valid_lo = (want_lo.array() - margin).matrix().cwiseMax(target_lo);
  l.valid_hi = (want_hi.array() + margin).matrix().cwiseMin(target_hi);
  l.valid_hi = l.valid_hi.cwiseMax(l.valid_lo);
  // Level l bounds the offsets [d, d + 2^l) by the block of cells starting
  // at a point's cell for offset d: a point below or left of the valid part
  // for offset d can land in it for a larger offset of the block, so the
  // grids start 2^levels - 1 cells lower (zero there), else the block's
  // bound would drop that point and prune poses scoring more than it.
  l.origin = (l.valid_lo.array() - ((1 << l.levels) - 1) * res).matrix();
  l.width = static_cast<int>((l.valid_hi.x() - l.origin.x()) / res) + 2;
  l.height = static_cast<int>((l.valid_hi.y() - l.origin.y()) / res) + 2;
  const size_t cells = static_cast<size_t>(l.width) * l.height;
  l.pyramid.assign(l.levels + 1, std::vector<float>());
  l.pyramid[0].assign(cells, 0.0f);
  std::vector<float>& fine = l.pyramid[0];
  const double inv_two_sigma2 = 1.0 / (2.0 * options.sigma * options.sigma);
  // exp(-(dx^2 + dy^2) / 2 sigma^2) = exp(-dx^2 / ..) exp(-dy^2 / ..): one
  // exponential per row and column of a point's kernel, not per cell.
  std::vector<double> gx(2 * kernel + 1), gy(2 * kernel + 1);
  for (const Eigen::Vector2d& p : points_) {
    if ((p.array() < l.valid_lo.array() - reach).any() ||
        (p.array() > l.valid_hi.array() + reach).any()) {
      continue;
    }
    const int cx = FloorToCell((p.x() - l.origin.x()) / res);
    const int cy = FloorToCell((p.y() - l.origin.y()) / res);
    const int x0 = std::max(0, cx - kernel);
    const int x1 = std::min(l.width - 1, cx + kernel);
    const int y0 = std::max(0, cy - kernel);
    const int y1 = std::min(l.height - 1, cy + kernel);
    for (int x = x0; x <= x1; ++x) {
      const double d = l.origin.x() + res * (x + 0.5) - p.x();
      gx[x - x0] = std::exp(-d * d * inv_two_sigma2);
    }
    for (int y = y0; y <= y1; ++y) {
      const double d = l.origin.y() + res * (y + 0.5) - p.y();
      gy[y - y0] = std::exp(-d * d * inv_two_sigma2);
    }
    for (int y = y0; y <= y1; ++y) {
      float* row = &fine[static_cast<size_t>(y) * l.width];
      for (int x = x0; x <= x1; ++x) {
        row[x] = std::max(row[x], static_cast<float>(gy[y - y0] * gx[x - x0]));
      }
    }
  }
  // Level l from level l-1: the max of four blocks of side 2^(l-1),
  // clipped at the grid's edge; first over y (rows y and y + step), then
  // over x. Two branch-free passes over contiguous rows in Eigen's packets
  // (the scalar loop with its edge tests was 90 % of building the grids);
  // max is exact, so the grids are the same bit for bit.
  using RowMap = Eigen::Map<Eigen::ArrayXf>;
  using ConstRowMap = Eigen::Map<const Eigen::ArrayXf>;
  Eigen::ArrayXf rows(l.width);
  for (int level = 1; level <= l.levels; ++level) {
    const int step = 1 << (level - 1);
    const std::vector<float>& below = l.pyramid[level - 1];
    std::vector<float>& up = l.pyramid[level];
    up.resize(cells);
    const int inner = std::max(0, l.width - step);
    for (int y = 0; y < l.height; ++y) {
      const ConstRowMap a(&below[static_cast<size_t>(y) * l.width], l.width);
      RowMap out(&up[static_cast<size_t>(y) * l.width], l.width);
      if (y + step < l.height) {
        const ConstRowMap b(&below[static_cast<size_t>(y + step) * l.width],
                            l.width);
        rows = a.max(b);
      } else {
        rows = a;
      }
      out.head(inner) = rows.head(inner).max(rows.segment(step, inner));
      out.tail(l.width - inner) = rows.tail(l.width - inner);
    }
  }
}

Pose2 MatchTarget::Correlative(const Points2& source, const Pose2& initial,
                               const CorrelativeOptions& options, double* score,
                               CorrelativeWork* work,
                               const Verifier* verify) const {
  *score = 0.0;
  if (work != nullptr) *work = CorrelativeWork();
  if (points_.empty() || source.empty()) return initial;
  const int ntheta = options.step_theta > 0
                         ? static_cast<int>(std::ceil(options.window_theta /
                                                      options.step_theta))
                         : 0;
  const int num_angles = 2 * ntheta + 1;
  // The grids need to cover where the source can land: the box of its
  // points at the search's angles, widened by the window (the grids' cost
  // grows with their area).
  Eigen::Vector2d lo = initial.t, hi = initial.t;
  for (int a = 0; a < num_angles; ++a) {
    const Eigen::Matrix2d r =
        RotationMatrix2D(initial.theta + (a - ntheta) * options.step_theta);
    for (const Eigen::Vector2d& p : source) {
      const Eigen::Vector2d q = r * p + initial.t;
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  }
  const double pad = options.window_xy + 2.0 * options.resolution;
  BuildLikelihood(options, lo.array() - pad, hi.array() + pad);
  const LikelihoodGrids& l = likelihood_;
  const double res = l.resolution;
  const int nxy = static_cast<int>(std::ceil(options.window_xy / res));
  const size_t n = source.size();
  // Cell indices of the rotated (untranslated-offset) points per angle.
  std::vector<int> cx(num_angles * n), cy(num_angles * n);
  for (int a = 0; a < num_angles; ++a) {
    const double theta = initial.theta + (a - ntheta) * options.step_theta;
    const Eigen::Matrix2d r = RotationMatrix2D(theta);
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d q = r * source[i] + initial.t - l.origin;
      cx[a * n + i] = FloorToCell(q.x() / res);
      cy[a * n + i] = FloorToCell(q.y() / res);
    }
  }
  double evaluations = 0.0;
  const double budget = options.max_evaluations > 0
                            ? options.max_evaluations
                            : std::numeric_limits<double>::infinity();
  const double probe = options.probe_evaluations > 0 && options.min_score > 0
                           ? options.probe_evaluations
                           : std::numeric_limits<double>::infinity();
  bool found = false;  // A pose reaching min_score has been scored.
  bool probe_stopped = false;
  bool verify_stopped = false;
  int verified = 0;
  auto pose_of = [&](int a, int dx, int dy) {
    return Pose2(initial.t.x() + dx * res, initial.t.y() + dy * res,
                 initial.theta + (a - ntheta) * options.step_theta);
  };
  // Per angle, the points split by where the window's offsets take them:
  // on the grids for every offset (cell indices, looked up without a bounds
  // test), off them for every offset (never looked up: they score 0), and
  // the rest (cells, tested per look-up).
  const int width = l.width, height = l.height;
  std::vector<std::ptrdiff_t> index(num_angles * n);
  std::vector<int> edge_x(num_angles * n), edge_y(num_angles * n);
  std::vector<int> num_inside(num_angles), num_edge(num_angles);
  for (int a = 0; a < num_angles; ++a) {
    int inside = 0, edge = 0;
    for (size_t i = 0; i < n; ++i) {
      const int x = cx[a * n + i], y = cy[a * n + i];
      if (x - nxy >= 0 && y - nxy >= 0 && x + nxy < width && y + nxy < height) {
        index[a * n + inside++] = static_cast<std::ptrdiff_t>(y) * width + x;
      } else if (x + nxy >= 0 && y + nxy >= 0 && x - nxy < width &&
                 y - nxy < height) {
        edge_x[a * n + edge] = x;
        edge_y[a * n + edge++] = y;
      }
    }
    num_inside[a] = inside;
    num_edge[a] = edge;
  }
  // The grid values are floats of at least exp(-2 x 3.5^2 / 2) (a kernel of
  // 3 sigma in cells of at most sigma), i.e. multiples of 2^-41, and a sum
  // of fewer than 4096 of them is exact in double whatever the order: four
  // partial sums (independent additions) over the points in any order give
  // the same score as one sum in the source's order.
  auto sum = [&](const std::vector<float>& grid, int a, int dx, int dy) {
    evaluations += static_cast<double>(n);
    const float* g = grid.data();
    const std::ptrdiff_t* idx = &index[a * n];
    const std::ptrdiff_t offset = static_cast<std::ptrdiff_t>(dy) * width + dx;
    const int inside = num_inside[a];
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int i = 0;
    for (; i + 4 <= inside; i += 4) {
      s0 += g[idx[i] + offset];
      s1 += g[idx[i + 1] + offset];
      s2 += g[idx[i + 2] + offset];
      s3 += g[idx[i + 3] + offset];
    }
    for (; i < inside; ++i) s0 += g[idx[i] + offset];
    const int* px = &edge_x[a * n];
    const int* py = &edge_y[a * n];
    for (int e = 0; e < num_edge[a]; ++e) {
      const int x = px[e] + dx, y = py[e] + dy;
      if (x < 0 || y < 0 || x >= width || y >= height) continue;
      s1 += g[static_cast<size_t>(y) * width + x];
    }
    return (s0 + s1) + (s2 + s3);
  };
  // Depth-first branch and bound: a candidate (angle, dx, dy) at level l
  // stands for the offsets [dx, dx + 2^l) x [dy, dy + 2^l); its score on
  // pyramid[l] bounds the fine score of every one of them.
  struct Candidate {
    double upper;
    int angle, dx, dy;
  };
  const double min_sum = options.min_score * static_cast<double>(n);
  double best = options.min_score > 0 ? min_sum : -1.0;
  int best_a = ntheta, best_dx = 0, best_dy = 0;
  auto by_score = [](const Candidate& u, const Candidate& v) {
    return u.upper > v.upper;
  };
  std::function<void(std::vector<Candidate>&, int)> search =
      [&](std::vector<Candidate>& candidates, int level) {
        std::sort(candidates.begin(), candidates.end(), by_score);
        for (const Candidate& c : candidates) {
          if (c.upper <= best || evaluations > budget) break;
          if (level == 0) {
            if (!found && work != nullptr) {
              work->first_found_evaluations = evaluations;
            }
            found = true;
            best = c.upper;
            best_a = c.angle;
            best_dx = c.dx;
            best_dy = c.dy;
            if (verify != nullptr && *verify) {
              ++verified;
              if (!(*verify)(pose_of(c.angle, c.dx, c.dy),
                             c.upper / static_cast<double>(n))) {
                verify_stopped = true;
                break;
              }
            }
            continue;
          }
          if (!found && evaluations > probe) {
            probe_stopped = true;
            break;
          }
          const int half = 1 << (level - 1);
          std::vector<Candidate> children;
          for (int oy = 0; oy <= half; oy += half) {
            for (int ox = 0; ox <= half; ox += half) {
              const int dx = c.dx + ox, dy = c.dy + oy;
              if (dx > nxy || dy > nxy) continue;
              children.push_back({sum(l.pyramid[level - 1], c.angle, dx, dy),
                                  c.angle, dx, dy});
            }
          }
          search(children, level - 1);
          if (verify_stopped) break;
        }
      };
  const int top = l.levels;
  std::vector<Candidate> roots;
  for (int a = 0; a < num_angles; ++a) {
    for (int dy = -nxy; dy <= nxy; dy += 1 << top) {
      for (int dx = -nxy; dx <= nxy; dx += 1 << top) {
        roots.push_back({sum(l.pyramid[top], a, dx, dy), a, dx, dy});
      }
    }
  }
  search(roots, top);
  if (work != nullptr) {
    work->evaluations = evaluations;
    work->probe_stopped = probe_stopped;
    work->budget_stopped = evaluations > budget;
    work->verified = verified;
    work->verify_stopped = verify_stopped;
  }
  if (verify_stopped || (options.min_score > 0 && !(best > min_sum))) {
    return initial;
  }
  *score = std::max(0.0, best) / static_cast<double>(n);
  return pose_of(best_a, best_dx, best_dy);
}

MatchResult MatchTarget::Match(const Points2& source, const Pose2& initial,
                               const CorrelativeOptions& correlative,
                               const IcpOptions& icp) const {
  double score = 0.0;
  const Pose2 coarse = Correlative(source, initial, correlative, &score);
  MatchResult result = Icp(source, coarse, icp);
  result.score = score;
  return result;
}

}  // namespace slam
