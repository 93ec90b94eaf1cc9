#include "frontends/inertial/inertial_initializer.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <vector>

namespace slam {
namespace {

constexpr double kBlockSeconds = 0.5;
constexpr double kStillAccelNormTolerance = 0.5;  // m/s^2
constexpr double kStillMaxAccelStd = 1.0;         // m/s^2
constexpr double kStillMaxGyroStd = 0.1;          // rad/s
constexpr double kStillFixSigmas = 4.0;
constexpr double kStillMaxGyroMeanChange = 0.005;  // rad/s
constexpr double kStillMaxAccelMeanChange = 0.2;   // m/s^2
// The fixes confirm a still start once a straight-line fit through them
// bounds the velocity to this (1 sigma per axis, from the fix noise): a body
// moving steadily at more than kStillFixSigmas times this is then seen to
// move, whatever the IMU says (an IMU cannot tell a steady turn from a gyro
// bias, nor a steady velocity from rest). With 0.1 m fixes at 10 Hz this
// takes 1 s of fixes (0.6 m/s is rejected), at 1 Hz two.
constexpr double kStillMaxVelocitySigma = 0.15;  // m/s
constexpr double kStillMaxLookAheadSeconds = 1.0;
constexpr int kMinAlignmentFixes = 5;
// The generalised alignment's cost grows with the cube of its fixes (the
// Cholesky factor of their covariance) and its memory with the square: it
// stops after this many (100 s of 10 Hz fixes: 8 MB, about a second per
// run on a loaded machine). Later fixes add little about the start anyway:
// the integrated IMU noise from the start is hundreds of metres after 100 s
// with the EuRoC config.
constexpr size_t kMaxAlignmentFixes = 1000;
// A moving start's alignment re-integrates the readings with its gyro bias
// estimate when that moves by more than this (a heading drift of 0.6 deg
// in 10 s, small against kMaxYawSigma), at most kMaxRelinearizations times
// per fix, kMaxReintegrations times in all and only over the first
// kMaxReintegrationSeconds (each re-integration reads the log from its start
// to the fix: the bounds keep a long log whose yaw never becomes observable
// linear in its length; later fixes keep the last bias linearization). The
// moving starts of tests/inertial_initializer_test.cc re-integrate 80-171
// times before their yaw is known, 12-15 s in.
constexpr double kRelinearizeGyroBias = 1e-3;  // rad/s
constexpr int kMaxRelinearizations = 3;
constexpr int kMaxReintegrations = 300;
constexpr double kMaxReintegrationSeconds = 60.0;
// The alignment estimates (c, s) = (cos, sin) of the yaw as two free
// unknowns; their norm tells whether the model fits. A norm further from 1
// than this many of its own sigmas (the fit's covariance along (c, s),
// scaled as the yaw's), or outside kUnitNormBand at all, is a fit that does
// not hold. Before, a fixed band of 0.8-1.25 rejected fits whose norm was
// within 2-3 of its sigmas of 1: 2 of 20 simulated gentle flights (the
// benchmark's gentle entry, seeds 11-30) had norms of 1.28-1.43 with sigmas
// of 0.10-0.15 from 12 s on and knew their yaw only after 16.2 and 25.3 s,
// with bias NEES 13.8 and 14.9 (issue 25); with the test, after 11.8 and
// 12.1 s, bias NEES 6.0 and 6.0.
constexpr double kUnitNormSigmas = 3.0;
constexpr double kUnitNormBand[2] = {0.5, 2.0};
// The gyro bias sigma handed on: the gyroscope noise does not average out
// as white noise in flight (vibration), as at a still start.
constexpr double kMinGyroBiasSigma = 2e-3;  // rad/s

struct Moments {
  Eigen::Vector3d accel_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_sq = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_sq = Eigen::Vector3d::Zero();
  int n = 0;
  void Add(const ImuSample& s) {
    accel_sum += s.accel;
    accel_sq += s.accel.cwiseProduct(s.accel);
    gyro_sum += s.gyro;
    gyro_sq += s.gyro.cwiseProduct(s.gyro);
    ++n;
  }
  Eigen::Vector3d AccelMean() const { return accel_sum / n; }
  Eigen::Vector3d GyroMean() const { return gyro_sum / n; }
  double MaxStd(const Eigen::Vector3d& sum, const Eigen::Vector3d& sq) const {
    const Eigen::Vector3d mean = sum / n;
    const Eigen::Vector3d var = sq / n - mean.cwiseProduct(mean);
    return std::sqrt(std::max(0.0, var.maxCoeff()));
  }
};

// A straight-line fit p(t) = mean + velocity (t - mean t) through fixes
// (least squares per axis); time_spread = sum (t - mean t)^2 in s^2, so the
// velocity's sigma per axis is the fix sigma / sqrt(time_spread).
struct StillFixFit {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double time_spread = 0.0;
};

StillFixFit FitStillFixes(const std::vector<PositionFix>& fixes, TimeNs t0) {
  StillFixFit fit;
  if (fixes.empty()) return fit;
  double mean_t = 0.0;
  for (const PositionFix& p : fixes) {
    fit.mean += p.position;
    mean_t += NsToSeconds(p.stamp - t0);
  }
  fit.mean /= static_cast<double>(fixes.size());
  mean_t /= static_cast<double>(fixes.size());
  Eigen::Vector3d cross = Eigen::Vector3d::Zero();
  for (const PositionFix& p : fixes) {
    const double dt = NsToSeconds(p.stamp - t0) - mean_t;
    fit.time_spread += dt * dt;
    cross += dt * (p.position - fit.mean);
  }
  if (fit.time_spread > 0.0) fit.velocity = cross / fit.time_spread;
  return fit;
}

// The sigma of the fit's velocity per axis under fixes of sigma
// position_sigma (infinite with fewer than two distinct stamps).
double VelocitySigma(const StillFixFit& fit, double position_sigma) {
  return fit.time_spread > 0.0 ? position_sigma / std::sqrt(fit.time_spread)
                               : std::numeric_limits<double>::infinity();
}

// The fixes show motion: a velocity beyond kStillFixSigmas of its sigma.
bool ShowsMotion(const StillFixFit& fit, double position_sigma) {
  return fit.time_spread > 0.0 &&
         fit.velocity.cwiseAbs().maxCoeff() >
             kStillFixSigmas * VelocitySigma(fit, position_sigma);
}

// End (exclusive sample index) of the still prefix, 0 when there is none.
size_t StillPrefix(const InertialData& data, const InertialOptions& options,
                   double* seconds) {
  const TimeNs t0 = data.imu.front().stamp;
  const TimeNs block = static_cast<TimeNs>(kBlockSeconds * 1e9);
  const double g = options.gravity.norm();
  size_t end = 0;
  size_t s = 0;
  std::vector<PositionFix> fixes;
  size_t f = 0;
  while (f < data.positions.size() && data.positions[f].stamp < t0) ++f;
  Moments all;
  for (int b = 0;; ++b) {
    const TimeNs block_end = t0 + (b + 1) * block;
    Moments m;
    while (s < data.imu.size() && data.imu[s].stamp < block_end) {
      m.Add(data.imu[s++]);
    }
    if (m.n < 2 || data.imu[s - 1].stamp - t0 < (b + 1) * block - block / 2) {
      break;  // The log ended within the block.
    }
    if (std::abs(m.AccelMean().norm() - g) > kStillAccelNormTolerance ||
        m.MaxStd(m.accel_sum, m.accel_sq) > kStillMaxAccelStd ||
        m.MaxStd(m.gyro_sum, m.gyro_sq) > kStillMaxGyroStd) {
      break;
    }
    // At rest the block means stay those of the blocks before (vibration
    // averages out; a slow start of the motion does not).
    if (all.n > 0 && ((m.GyroMean() - all.GyroMean()).cwiseAbs().maxCoeff() >
                          kStillMaxGyroMeanChange ||
                      (m.AccelMean() - all.AccelMean()).cwiseAbs().maxCoeff() >
                          kStillMaxAccelMeanChange)) {
      break;
    }
    all.accel_sum += m.accel_sum;
    all.gyro_sum += m.gyro_sum;
    all.n += m.n;
    std::vector<PositionFix> candidate = fixes;
    size_t next = f;
    while (next < data.positions.size() &&
           data.positions[next].stamp < block_end) {
      candidate.push_back(data.positions[next++]);
    }
    const StillFixFit fit = FitStillFixes(candidate, t0);
    bool spread_ok = true;
    for (const PositionFix& p : candidate) {
      spread_ok = spread_ok && (p.position - fit.mean).cwiseAbs().maxCoeff() <=
                                   kStillFixSigmas * options.position_sigma;
    }
    if (!spread_ok || ShowsMotion(fit, options.position_sigma)) break;
    fixes = candidate;
    f = next;
    if (fixes.size() >= 2) end = s;  // Confirmed by the fixes so far.
  }
  // The fixes must also bound the velocity over the still interval (a short
  // one holds too few of them to see a steady motion): when they do not yet,
  // the fixes that follow it join the fit until they do (a start from rest
  // moves little in the first second; a steady motion shows), within
  // kStillMaxLookAheadSeconds.
  if (end > 0) {
    const TimeNs look_ahead_end =
        data.imu[end - 1].stamp +
        static_cast<TimeNs>(kStillMaxLookAheadSeconds * 1e9);
    StillFixFit fit = FitStillFixes(fixes, t0);
    while (VelocitySigma(fit, options.position_sigma) >
               kStillMaxVelocitySigma &&
           f < data.positions.size() &&
           data.positions[f].stamp <= look_ahead_end) {
      fixes.push_back(data.positions[f++]);
      fit = FitStillFixes(fixes, t0);
    }
    if (ShowsMotion(fit, options.position_sigma) ||
        VelocitySigma(fit, options.position_sigma) > kStillMaxVelocitySigma) {
      end = 0;  // Moving, or not confirmed.
    }
  }
  *seconds = end == 0 ? 0.0 : NsToSeconds(data.imu[end - 1].stamp - t0);
  return end;
}

// The covariance across the alignment's fixes of their error: the fix noise
// plus the position error of the integrated IMU noise, which starts at zero
// at t0 (the preintegration's start) and is strongly correlated across
// fixes. The gyroscope's white noise random-walks the tilt (the same in
// every horizontal direction: the body turns isotropic noise into isotropic
// noise), and gravity turns the tilt into a horizontal acceleration error:
// a triple integral of white noise, g sigma_g sqrt(t^5 / 20) in position
// (4 m after 14 s with the EuRoC config's gyro density, against a fix noise
// of 0.1 m); the gyroscope's random walk adds a fourfold one. The
// accelerometer's white noise (double integral) and random walk (triple)
// act in every direction. (The yaw's random walk turns the integrated
// displacement, metres, not the integrated gravity: centimetres, left out.)
// A generalised least squares: the alignment whitens each fix's design row
// and residual with the Cholesky factor L of this covariance (row k of L^-1
// A from the rows before: causal and incremental) and adds the whitened
// rows as independent observations, so its normal matrix, yaw and bias
// sigmas and chi2 are those of the correlated noise.
class FixNoiseFactor {
 public:
  // horizontal: with the tilt terms (else the vertical axis).
  FixNoiseFactor(const ImuNoise& noise, double gravity, double fix_sigma,
                 bool horizontal)
      : fix_variance_(fix_sigma * fix_sigma) {
    const double g2 = horizontal ? gravity * gravity : 0.0;
    // Intensities of the 1-, 2-, 3- and 4-fold integrals of white noise
    // that the position error is made of.
    intensity_[1] = noise.accel_noise_density * noise.accel_noise_density;
    intensity_[2] = noise.accel_random_walk * noise.accel_random_walk +
                    g2 * noise.gyro_noise_density * noise.gyro_noise_density;
    intensity_[3] = g2 * noise.gyro_random_walk * noise.gyro_random_walk;
  }

  // Row k of L (k entries and the diagonal last) for the fix at tau; the
  // rows come in the order of the fixes, computed once (an alignment
  // rebuilt over the same fixes reuses them).
  const std::vector<double>& Row(size_t k, double tau) {
    if (k < rows_.size()) return rows_[k];
    std::vector<double> row(k + 1, 0.0);
    double rest = Kernel(tau, tau) + fix_variance_;
    for (size_t j = 0; j < k; ++j) {
      double c = Kernel(taus_[j], tau);
      for (size_t i = 0; i < j; ++i) c -= rows_[j][i] * row[i];
      row[j] = c / rows_[j][j];
      rest -= row[j] * row[j];
    }
    // Rounding in a strongly correlated covariance: never below a small
    // part of the fix noise.
    row[k] = std::sqrt(std::max(rest, 1e-6 * fix_variance_));
    taus_.push_back(tau);
    rows_.push_back(std::move(row));
    return rows_.back();
  }

 private:
  // Cov(x(s), x(t)) of the n-fold integrals of white noise (n = 1..4 in
  // intensity_[n - 1]) from 0: int_0^s (s-u)^(n-1) (t-u)^(n-1) du /
  // ((n-1)!)^2 for s <= t, in closed form (binomial in d = t - s).
  double Kernel(double s, double t) const {
    if (s > t) std::swap(s, t);
    const double d = t - s;
    double total = 0.0;
    double factorial = 1.0;  // a!
    for (int a = 0; a < 4; ++a) {
      if (a > 0) factorial *= a;
      if (intensity_[a] == 0.0) continue;
      double sum = 0.0, binomial = 1.0;
      for (int k = 0; k <= a; ++k) {
        sum += binomial * std::pow(d, a - k) * std::pow(s, a + k + 1) /
               (a + k + 1);
        binomial = binomial * (a - k) / (k + 1);
      }
      total += intensity_[a] * sum / (factorial * factorial);
    }
    return total;
  }

  double fix_variance_;
  double intensity_[4] = {0.0, 0.0, 0.0, 0.0};  // [a]: the (a+1)-fold one
  std::vector<double> taus_;
  std::vector<std::vector<double>> rows_;
};

// Normal equations of the alignment with roll and pitch known: u = R_tilt
// (dp + dR lever_arm) rotated by the yaw psi about the vertical,
// (c, s) = (cos psi, sin psi), and the readings' bias error db (gyro, accel;
// against the bias the readings were integrated with) acting through the
// preintegration's bias Jacobians, M = R_tilt [dp_dbg dp_dba] (3 x 6). The
// world-frame effect Rz(psi) M db is bilinear in (c, s) and db; with
// q = c db and r = s db it is linear:
//   horizontal: y_x = p0x + v0x t + c u_x - s u_y + e_x u_z + M_x q - M_y r,
//               y_y = p0y + v0y t + s u_x + c u_y + e_y u_z + M_y q + M_x r
//               (20 unknowns; e: a small tilt error (or constant horizontal
//               accelerometer error in the world frame) acting on the large
//               vertical u_z; q, r: a bias in the body frame, which turns in
//               the world frame as the body turns),
//   vertical:   y_z = p0z + v0z t + u_z + 1/2 b t^2  (3 unknowns; b absorbs
//               the accelerometer's error along the vertical).
// Each fix's rows are whitened by the correlated noise of FixNoiseFactor
// (generalised least squares) before they enter the normal equations.
// e, q and r have zero-mean priors (the tilt and bias sigmas; |q|, |r| <=
// |db|): without turning, a body-frame bias and the tilt error look alike,
// and the priors say how much of the motion either may explain. The yaw
// sigma is the marginal of (c, s) across their direction under that
// information (the inverse of the normal matrix with the priors), so it
// counts what the bias and tilt may take away from the yaw.
struct Alignment {
  static constexpr int kH = 20;
  using VecH = Eigen::Matrix<double, kH, 1>;
  using MatH = Eigen::Matrix<double, kH, kH>;
  MatH normal = MatH::Zero();
  MatH prior = MatH::Zero();
  // The priors' mean: zero but for q and r after a relinearization of the
  // gyroscope bias (they pull the bias towards the configured one).
  VecH prior_mean = VecH::Zero();
  VecH rhs = VecH::Zero();
  Eigen::Matrix3d normal_z = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs_z = Eigen::Vector3d::Zero();
  double yy = 0.0;
  int fixes = 0;
  // The fix noise's factors (shared by the rebuilt alignments) and the
  // whitened rows so far: [design row, observation] per fix, x and y
  // (the same horizontal covariance), z.
  FixNoiseFactor* horizontal_noise;
  FixNoiseFactor* vertical_noise;
  std::vector<Eigen::Matrix<double, kH + 1, 1>> wx, wy;
  std::vector<Eigen::Vector4d> wz;

  Alignment(double tilt_sigma, double gyro_bias_sigma, double accel_bias_sigma,
            FixNoiseFactor* horizontal, FixNoiseFactor* vertical)
      : horizontal_noise(horizontal), vertical_noise(vertical) {
    prior.diagonal().segment<2>(6).setConstant(1.0 / (tilt_sigma * tilt_sigma));
    for (int block : {8, 14}) {
      prior.diagonal().segment<3>(block).setConstant(
          1.0 / (gyro_bias_sigma * gyro_bias_sigma));
      prior.diagonal().segment<3>(block + 3).setConstant(
          1.0 / (accel_bias_sigma * accel_bias_sigma));
    }
  }

  void Add(double tau, const Eigen::Vector3d& y, const Eigen::Vector3d& u,
           const Eigen::Matrix<double, 3, 6>& m) {
    Eigen::Matrix<double, kH + 1, 1> ax, ay;
    ax << 1.0, 0.0, tau, 0.0, u.x(), -u.y(), u.z(), 0.0, m.row(0).transpose(),
        -m.row(1).transpose(), y.x();
    ay << 0.0, 1.0, 0.0, tau, u.y(), u.x(), 0.0, u.z(), m.row(1).transpose(),
        m.row(0).transpose(), y.y();
    Eigen::Vector4d az(1.0, tau, 0.5 * tau * tau, y.z() - u.z());
    // Row k of L^-1 [A y] = (row k - sum_j L_kj (whitened row j)) / L_kk.
    const size_t k = wx.size();
    const std::vector<double>& lh = horizontal_noise->Row(k, tau);
    const std::vector<double>& lz = vertical_noise->Row(k, tau);
    for (size_t j = 0; j < k; ++j) {
      ax -= lh[j] * wx[j];
      ay -= lh[j] * wy[j];
      az -= lz[j] * wz[j];
    }
    ax /= lh[k];
    ay /= lh[k];
    az /= lz[k];
    wx.push_back(ax);
    wy.push_back(ay);
    wz.push_back(az);
    const VecH hx = ax.head<kH>(), hy = ay.head<kH>();
    normal += hx * hx.transpose() + hy * hy.transpose();
    rhs += hx * ax[kH] + hy * ay[kH];
    yy += ax[kH] * ax[kH] + ay[kH] * ay[kH];
    const Eigen::Vector3d hz = az.head<3>();
    normal_z += hz * hz.transpose();
    rhs_z += hz * az[3];
    ++fixes;
  }

  struct Result {
    double yaw = 0.0, yaw_sigma = M_PI;
    Eigen::Vector2d tilt_error = Eigen::Vector2d::Zero();  // e (see above)
    // The bias error db = (c q + s r) / (c^2 + s^2) against the bias the
    // readings were integrated with, and the largest sigma of its gyro part.
    Eigen::Matrix<double, 6, 1> bias_error =
        Eigen::Matrix<double, 6, 1>::Zero();
    double gyro_bias_sigma = 1.0;
    Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), v0 = Eigen::Vector3d::Zero();
    double position_sigma = 1.0, velocity_sigma = 1.0, tilt_sigma = 1.0;
    bool ok = false;
  };
  Result Solve() const {
    Result r;
    if (fixes < kMinAlignmentFixes) return r;
    Eigen::LDLT<MatH> ldlt(normal + prior);
    Eigen::LDLT<Eigen::Matrix3d> ldlt_z(normal_z);
    if (ldlt.info() != Eigen::Success || ldlt_z.info() != Eigen::Success) {
      return r;
    }
    const VecH x = ldlt.solve(rhs + prior * prior_mean);
    const Eigen::Vector3d xz = ldlt_z.solve(rhs_z);
    const MatH cov = ldlt.solve(MatH::Identity());
    if (!x.allFinite() || !xz.allFinite() || !cov.allFinite()) return r;
    const int dof = 2 * fixes - 8;
    // The cost at the solution, priors included.
    const VecH dx = x - prior_mean;
    const double chi2 =
        yy - 2.0 * x.dot(rhs) + x.dot(normal * x) + dx.dot(prior * dx);
    const double scale = dof > 0 ? std::max(1.0, chi2 / dof) : 1.0;
    const Eigen::Vector2d cs = x.segment<2>(4);
    const double norm = cs.norm();
    // (c, s) should be a unit vector; far from it, beyond its uncertainty,
    // the model does not fit (kUnitNormSigmas).
    const Eigen::Vector2d along = cs / norm;
    const double norm_sigma =
        std::sqrt(scale * along.dot(cov.block<2, 2>(4, 4) * along));
    if (!(norm > kUnitNormBand[0] && norm < kUnitNormBand[1]) ||
        !(std::abs(norm - 1.0) <= kUnitNormSigmas * norm_sigma)) {
      return r;
    }
    const Eigen::Vector2d across(-cs.y() / norm, cs.x() / norm);
    r.yaw = std::atan2(cs.y(), cs.x());
    r.yaw_sigma =
        std::sqrt(scale * across.dot(cov.block<2, 2>(4, 4) * across)) / norm;
    r.tilt_error = x.segment<2>(6);
    const double norm2 = norm * norm;
    r.bias_error =
        (cs.x() * x.segment<6>(8) + cs.y() * x.segment<6>(14)) / norm2;
    Eigen::Matrix<double, 6, 12> jb;
    jb << cs.x() / norm2 * Eigen::Matrix<double, 6, 6>::Identity(),
        cs.y() / norm2 * Eigen::Matrix<double, 6, 6>::Identity();
    const Eigen::Matrix<double, 12, 12> cov_qr = cov.block<12, 12>(8, 8);
    const Eigen::Matrix<double, 6, 6> cov_b = jb * cov_qr * jb.transpose();
    r.gyro_bias_sigma =
        std::sqrt(scale * cov_b.diagonal().head<3>().maxCoeff());
    r.p0 = Eigen::Vector3d(x[0], x[1], xz[0]);
    r.v0 = Eigen::Vector3d(x[2], x[3], xz[1]);
    const Eigen::Matrix3d cov_z = ldlt_z.solve(Eigen::Matrix3d::Identity());
    r.position_sigma =
        std::sqrt(scale * std::max({cov(0, 0), cov(1, 1), cov_z(0, 0)}));
    r.velocity_sigma =
        std::sqrt(scale * std::max({cov(2, 2), cov(3, 3), cov_z(1, 1)}));
    r.tilt_sigma = std::sqrt(scale * std::max(cov(6, 6), cov(7, 7)));
    r.ok = std::isfinite(r.yaw_sigma) && r.tilt_error.norm() < 0.5;
    return r;
  }
};

double YawOf(const Eigen::Matrix3d& r) {
  // Heading of the body x axis projected on the horizontal plane (or of
  // the body y axis when x is near vertical).
  Eigen::Vector3d x = r.col(0);
  if (std::hypot(x.x(), x.y()) < 0.1) x = r.col(1);
  return std::atan2(x.y(), x.x());
}

}  // namespace

bool InitializeInertial(const InertialData& data,
                        const InertialOptions& options,
                        InertialInitialization* init, std::string* error) {
  *init = InertialInitialization();
  if (data.imu.empty()) {
    *error = "no IMU readings";
    return false;
  }
  const TimeNs t0 = data.imu.front().stamp;
  init->state.stamp = t0;
  init->state.bias = options.initial_bias;
  init->gyro_bias_sigma = options.prior_gyro_bias_sigma;
  init->accel_bias_sigma = options.prior_accel_bias_sigma;

  // Still start.
  Eigen::Vector3d up = -options.gravity;
  if (up.norm() < 1e-9) up = Eigen::Vector3d::UnitZ();
  const size_t still_end = StillPrefix(data, options, &init->still_seconds);
  Moments first;
  const TimeNs first_end = t0 + static_cast<TimeNs>(kBlockSeconds * 1e9);
  for (size_t s = 0; s < data.imu.size() &&
                     (s == 0 || s < still_end || data.imu[s].stamp < first_end);
       ++s) {
    first.Add(data.imu[s]);
  }
  init->still_start = still_end > 0;
  if (init->still_start) {
    init->state.bias.head<3>() = first.GyroMean();
    // The spread of the mean under the gyroscope's white noise (vibration
    // is not white: a floor).
    init->gyro_bias_sigma = std::max(
        kMinGyroBiasSigma, options.noise.gyro_noise_density /
                               std::sqrt(std::max(init->still_seconds, 0.1)));
    init->tilt_sigma = 0.02;  // An accelerometer bias of 0.2 m/s^2.
    init->velocity_sigma = 0.05;
  } else {
    init->tilt_sigma = 0.1;  // Mean reading of the first block, in motion.
    init->gyro_bias_sigma = options.moving_start_gyro_bias_sigma;
  }
  init->unaligned_velocity_sigma = init->velocity_sigma;
  init->unaligned_tilt_sigma = init->tilt_sigma;
  init->unaligned_gyro_bias_sigma = init->gyro_bias_sigma;
  // Roll and pitch from the mean accelerometer reading (R^T up ~ accel).
  Eigen::Matrix3d r_tilt =
      Eigen::Quaterniond::FromTwoVectors(first.AccelMean(), up)
          .toRotationMatrix();
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero();
  size_t f = 0;
  while (f < data.positions.size() && data.positions[f].stamp < t0) ++f;
  if (f < data.positions.size()) {
    p0 = data.positions[f].position;
    init->position_sigma = std::max(options.position_sigma, 1e-3);
  }
  init->state.state.pose = Pose3(p0, Eigen::Quaterniond(r_tilt));
  // The alignment works in a levelled frame whose z is up.
  const Eigen::Matrix3d level =
      Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  const Eigen::Matrix3d r_level = level * r_tilt;
  init->yaw_observable_stamp = data.imu.back().stamp;
  init->yaw_hint_stamp = std::numeric_limits<TimeNs>::max();

  // In-motion alignment over the fixes, in time order.
  ImuBias lin_bias = init->state.bias;  // The readings' integration bias.
  PreintegratedImu pim(options.noise, lin_bias, options.gravity);
  TimeNs integrated_to = t0;
  double best_sigma = M_PI;  // The smallest yaw sigma of the fit so far.
  const double fix_sigma = std::max(options.position_sigma, 1e-3);
  FixNoiseFactor horizontal_noise(options.noise, options.gravity.norm(),
                                  fix_sigma, true);
  FixNoiseFactor vertical_noise(options.noise, options.gravity.norm(),
                                fix_sigma, false);
  Alignment alignment(init->tilt_sigma, init->gyro_bias_sigma,
                      init->accel_bias_sigma, &horizontal_noise,
                      &vertical_noise);
  // Integrates the readings up to fix g and adds it to the fit (false on a
  // non-finite reading: the estimators report it).
  auto add_fix = [&](size_t g) {
    const PositionFix& fix = data.positions[g];
    if (fix.stamp > integrated_to) {
      if (!IntegrateImuSamples(data.imu, integrated_to, fix.stamp, &pim,
                               data.interpolation)) {
        return false;
      }
      integrated_to = fix.stamp;
    }
    const double tau = NsToSeconds(fix.stamp - t0);
    const Eigen::Vector3d y =
        level * (fix.position - 0.5 * options.gravity * tau * tau);
    const Eigen::Vector3d u =
        r_level * (pim.delta_p() + pim.delta_q() * options.lever_arm);
    Eigen::Matrix<double, 3, 6> m;
    m << r_level * pim.dp_dbg(), r_level * pim.dp_dba();
    alignment.Add(tau, y, u, m);
    return true;
  };
  // The start the fit `r` gives (gyro bias integrated with `bias`).
  auto aligned_start = [&](const Alignment::Result& r, const ImuBias& bias,
                           InertialInitialization* out) {
    if (!out->still_start) {
      // The fit's gyro bias, with twice its sigma (as the yaw's), within
      // the prior's.
      out->state.bias.head<3>() = bias.head<3>() + r.bias_error.head<3>();
      out->gyro_bias_sigma = std::min(
          out->gyro_bias_sigma, std::max(r.gyro_bias_sigma, kMinGyroBiasSigma));
    }
    Eigen::Matrix3d r_yaw =
        Eigen::AngleAxisd(r.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    if (!out->still_start) {
      // Without a still start the tilt came from a moving accelerometer:
      // correct it by the fit's horizontal term, a small world rotation
      // omega with omega x (u_z z) = u_z (e_x, e_y, 0).
      const Eigen::Vector3d omega(-r.tilt_error.y(), r.tilt_error.x(), 0.0);
      r_yaw = QuaternionExp<double>(omega).toRotationMatrix() * r_yaw;
      // e also holds any horizontal accelerometer bias (0.1 m/s^2 is
      // 0.01 rad): a floor.
      out->tilt_sigma = std::max(2.0 * r.tilt_sigma, 0.01);
    }
    const Eigen::Matrix3d r0 = level.transpose() * r_yaw * r_level;
    out->state.state.pose =
        Pose3(level.transpose() * r.p0, Eigen::Quaterniond(r0));
    if (!out->still_start) {
      out->state.state.velocity = level.transpose() * r.v0;
    }
    out->position_sigma = std::max(r.position_sigma, 1e-3);
    if (!out->still_start) {
      out->velocity_sigma = std::max(r.velocity_sigma, 0.01);
    }
    // Model errors (accelerometer bias, tilt) are not in the fit: keep
    // some yaw uncertainty.
    out->yaw_sigma = std::max(2.0 * r.yaw_sigma, 1.0 * M_PI / 180.0);
  };
  const size_t f_first = f;
  bool readable = true;
  int reintegrations = 0;
  for (; readable && f < data.positions.size() &&
         f - f_first < kMaxAlignmentFixes;
       ++f) {
    const PositionFix& fix = data.positions[f];
    if (fix.stamp > data.imu.back().stamp || !add_fix(f)) break;
    Alignment::Result r = alignment.Solve();
    // A moving start's gyro bias is known only to its prior, the sensor's
    // turn-on bias (several 0.01 rad/s on an ADIS16448): a bias error of
    // 0.05 rad/s turns the integrated heading by 29 deg in 10 s, far
    // outside the fit's first-order bias terms. Re-integrate with the
    // fit's gyro bias (Gauss-Newton on it) while it moves by more than
    // kRelinearizeGyroBias; the priors stay on the configured bias.
    for (int it = 0;
         !init->still_start && r.ok && it < kMaxRelinearizations &&
         reintegrations < kMaxReintegrations &&
         NsToSeconds(fix.stamp - t0) <= kMaxReintegrationSeconds &&
         r.bias_error.head<3>().cwiseAbs().maxCoeff() > kRelinearizeGyroBias;
         ++it, ++reintegrations) {
      lin_bias.head<3>() += r.bias_error.head<3>();
      const Eigen::Vector3d offset =
          init->state.bias.head<3>() - lin_bias.head<3>();
      alignment =
          Alignment(init->tilt_sigma, init->gyro_bias_sigma,
                    init->accel_bias_sigma, &horizontal_noise, &vertical_noise);
      alignment.prior_mean.segment<3>(8) = std::cos(r.yaw) * offset;
      alignment.prior_mean.segment<3>(14) = std::sin(r.yaw) * offset;
      pim = PreintegratedImu(options.noise, lin_bias, options.gravity);
      integrated_to = t0;
      for (size_t g = f_first; readable && g <= f; ++g) readable = add_fix(g);
      if (!readable) break;
      r = alignment.Solve();
    }
    if (!readable) break;
    if (r.ok) best_sigma = std::min(best_sigma, r.yaw_sigma);
    if (r.ok && r.yaw_sigma < kYawHintSigma &&
        init->yaw_hint_stamp > fix.stamp) {
      init->yaw_hint_stamp = fix.stamp;
    }
    if (r.ok && r.yaw_sigma < kYawHintSigma && init->rough == nullptr) {
      // The first rough alignment: the pass without yaw information
      // restarts from it (inertial_estimator.h).
      auto rough = std::make_shared<InertialInitialization>(*init);
      aligned_start(r, lin_bias, rough.get());
      init->rough = rough;
    }
    if (!r.ok || r.yaw_sigma > kAlignmentMaxYawSigma) continue;
    init->yaw_observable = true;
    init->yaw_observable_stamp = fix.stamp;
    init->alignment_fixes = alignment.fixes;
    aligned_start(r, lin_bias, init);
    break;
  }

  char line[500];
  char still[80];
  if (init->still_start) {
    std::snprintf(still, sizeof(still), "still start of %.1f s",
                  init->still_seconds);
  } else {
    std::snprintf(still, sizeof(still),
                  "no still start (moving, or the fixes do not confirm it)");
  }
  const double t_obs = NsToSeconds(init->yaw_observable_stamp - t0);
  if (init->yaw_observable) {
    std::snprintf(
        line, sizeof(line),
        "initializer: %s; yaw observable after %.2f s (%d fixes): yaw %.1f "
        "deg +- %.1f, tilt +- %.2f deg, gyro bias (%.4f, %.4f, %.4f) rad/s",
        still, t_obs, init->alignment_fixes,
        YawOf(init->state.state.pose.q.toRotationMatrix()) * 180.0 / M_PI,
        init->yaw_sigma * 180.0 / M_PI, init->tilt_sigma * 180.0 / M_PI,
        init->state.bias[0], init->state.bias[1], init->state.bias[2]);
  } else {
    std::snprintf(
        line, sizeof(line),
        "initializer: %s; yaw NOT observable from the %zu fixes "
        "(the alignment's yaw sigma never fell below %.0f deg, "
        "smallest %.1f deg: too little horizontal acceleration "
        "to tell the heading from the biases and the tilt, or too "
        "few fixes): the heading of every estimate is unknown",
        still, std::min(data.positions.size() - f_first, kMaxAlignmentFixes),
        kAlignmentMaxYawSigma * 180.0 / M_PI, best_sigma * 180.0 / M_PI);
  }
  init->summary = line;
  return true;
}

std::vector<std::string> InertialDataWarnings(const InertialData& data) {
  std::vector<std::string> out;
  if (data.imu.size() < 2) return out;
  std::vector<int64_t> dts;
  for (size_t s = 1; s < data.imu.size(); ++s) {
    dts.push_back(data.imu[s].stamp - data.imu[s - 1].stamp);
  }
  std::vector<int64_t> sorted = dts;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2,
                   sorted.end());
  const double period = static_cast<double>(sorted[sorted.size() / 2]);
  char text[400];
  for (size_t s = 1; s < data.imu.size(); ++s) {
    const double periods = static_cast<double>(dts[s - 1]) / period;
    if (periods <= kMaxImuGapPeriods) continue;
    std::string where = "IMU reading " + std::to_string(s);
    if (data.imu_lines.size() == data.imu.size()) {
      where = data.imu_path + ":" + std::to_string(data.imu_lines[s]);
    }
    std::snprintf(text, sizeof(text),
                  "%s: IMU gap of %.1f ms (%.1f sample periods of %.2f ms) "
                  "before this reading: the motion in it is interpolated",
                  where.c_str(), 1e-6 * static_cast<double>(dts[s - 1]),
                  periods, 1e-6 * period);
    out.push_back(text);
  }
  if (data.positions.empty()) return out;
  const TimeNs begin = data.imu.front().stamp, end = data.imu.back().stamp;
  TimeNs last = begin;
  auto check = [&](TimeNs from, TimeNs to, const char* what) {
    const double gap = NsToSeconds(to - from);
    if (gap <= kMaxFixGapSeconds) return;
    std::snprintf(text, sizeof(text),
                  "fixes too sparse: %.1f s without a position fix %s "
                  "(t = %.1f .. %.1f s; more than %.0f s of IMU alone drifts "
                  "by metres)",
                  gap, what, NsToSeconds(from - begin), NsToSeconds(to - begin),
                  kMaxFixGapSeconds);
    out.push_back(text);
  };
  for (const PositionFix& p : data.positions) {
    if (p.stamp < begin || p.stamp > end) continue;
    check(last, p.stamp, last == begin ? "at the start" : "between fixes");
    last = p.stamp;
  }
  check(last, end, last == begin ? "at all within the IMU log" : "at the end");
  return out;
}

bool StartAtGroundTruth(InertialData* data, ImuBias* bias, std::string* error) {
  if (data->ground_truth.empty()) {
    *error = "initial_state ground_truth: the input has no ground truth";
    return false;
  }
  const InertialGroundTruth& first = data->ground_truth.front();
  size_t s = 0;
  while (s < data->imu.size() && data->imu[s].stamp < first.stamp) ++s;
  if (s == data->imu.size()) {
    *error =
        "initial_state ground_truth: no IMU reading after the first "
        "ground-truth state";
    return false;
  }
  data->imu.erase(data->imu.begin(), data->imu.begin() + s);
  if (data->imu_lines.size() >= s) {
    data->imu_lines.erase(data->imu_lines.begin(), data->imu_lines.begin() + s);
  }
  // The ground-truth state at (or just before) the first kept reading.
  const InertialGroundTruth* start = &first;
  for (const InertialGroundTruth& g : data->ground_truth) {
    if (g.stamp > data->imu.front().stamp) break;
    start = &g;
  }
  data->has_initial_state = true;
  data->initial_state.pose = start->pose;
  data->initial_state.velocity = start->velocity;
  *bias = start->bias;
  return true;
}

}  // namespace slam
