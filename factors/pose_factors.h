// Builders that turn a measurement and its information matrix into a graph
// Factor (cost function, measurement and information kept together). The
// autodiff cost functions of the pose factors are instantiated in
// pose_factors.cc only, to keep the autodiff-heavy translation units few.
#ifndef SLAM_FACTORS_POSE_FACTORS_H_
#define SLAM_FACTORS_POSE_FACTORS_H_

#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/graph.h"
#include "core/keys.h"
#include "core/lie.h"

namespace slam {

// Each builder fails (returns false, sets *error) when the information matrix
// is not symmetric positive definite.
bool MakeBetweenSE2(const Key& i, const Key& j, const Pose2& z_ij,
                    const Eigen::Matrix3d& information, Factor* factor,
                    std::string* error);
bool MakePriorSE2(const Key& i, const Pose2& z,
                  const Eigen::Matrix3d& information, Factor* factor,
                  std::string* error);
bool MakeBetweenSE3(const Key& i, const Key& j, const Pose3& z_ij,
                    const Eigen::Matrix<double, 6, 6>& information,
                    Factor* factor, std::string* error);
bool MakePriorSE3(const Key& i, const Pose3& z,
                  const Eigen::Matrix<double, 6, 6>& information,
                  Factor* factor, std::string* error);

}  // namespace slam

#endif  // SLAM_FACTORS_POSE_FACTORS_H_
