// State and covariance outputs and NEES report of `slam inertial`
// (apps/inertial_command.cc), NEES as frontends/inertial/
// inertial_consistency.h defines it.
//
// Covariance CSV (OUT/covariance_window_filter.csv): one row per keyframe,
// the newest state's 15 x 15 joint marginal covariance right after its
// window update, upper triangle row by row (120 values) after the stamp.
// Tangent order and units: px py pz [m] (body-frame position perturbation),
// thx thy thz [rad] (body-frame rotation, right perturbation), vx vy vz
// [m/s] (world), bgx bgy bgz [rad/s], bax bay baz [m/s^2]; a column is named
// "cov(a,b) [unit a * unit b]", e.g. "cov(px,thz) [m*rad]".
#ifndef SLAM_APPS_INERTIAL_CONSISTENCY_REPORT_H_
#define SLAM_APPS_INERTIAL_CONSISTENCY_REPORT_H_

#include <Eigen/Core>
#include <ostream>
#include <string>
#include <vector>

#include "apps/json.h"
#include "datasets/imu_io.h"
#include "frontends/inertial/inertial_consistency.h"
#include "frontends/inertial/inertial_estimator.h"

namespace slam {

// The covariance CSV text (format above). States and covariances pair up by
// index (their sizes must agree).
std::string CovarianceCsv(const std::vector<InertialState>& states,
                          const std::vector<Eigen::MatrixXd>& covariances);

// The states CSV text: "#timestamp [ns],vx,vy,vz,bgx,bgy,bgz,bax,bay,baz"
// (world velocity, gyro then accel bias), numbers in %.17g.
std::string StatesCsv(const std::vector<InertialState>& states);

// Parses CovarianceCsv's text back (for tests and tools): stamps and full
// symmetric 15 x 15 matrices. False with "line N: problem" on bad text.
bool ParseCovarianceCsv(const std::string& text, std::vector<TimeNs>* stamps,
                        std::vector<Eigen::MatrixXd>* covariances,
                        std::string* error);

// NEES of `states` (with `covariances`) against `reference` after
// options.skip_seconds, raw and after the yaw-only alignment of the
// reference rotation (EstimateYawOffset); prints a short table to `out` and
// returns the report object:
//   {keyframes, skip_seconds,
//    position|pose|velocity|bias|gyro_bias|accel_bias: {mean, median, dof},
//    yaw_aligned: {yaw_offset_deg, position|...: ...},
//    after_yaw: {keyframes, skip_seconds, rotation_rmse_deg, position|...}}
// after_yaw (when yaw_known_seconds >= 0, the seconds after the start at
// which the heading became known) counts only the keyframes from there (and
// after skip_seconds).
bool EvaluateNees(const std::string& name,
                  const std::vector<InertialState>& states,
                  const std::vector<Eigen::MatrixXd>& covariances,
                  const std::vector<InertialGroundTruth>& reference,
                  const NeesOptions& options, double yaw_known_seconds,
                  std::ostream& out, JsonObject* json, std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_INERTIAL_CONSISTENCY_REPORT_H_
