// Information-matrix helpers: square roots for whitening and the repair of
// matrices that are not positive definite (published files round their
// information matrices when printing them, which can leave them slightly
// indefinite).
#ifndef SLAM_CORE_INFORMATION_H_
#define SLAM_CORE_INFORMATION_H_

#include <Eigen/Core>

namespace slam {

// Upper-triangular L^T with information = L L^T (so |L^T e|^2 = e^T I e).
// Returns false when the matrix is not symmetric positive definite.
bool SqrtInformation(const Eigen::MatrixXd& information,
                     Eigen::MatrixXd* sqrt_information);

// True if symmetric (to a relative 1e-9) and positive definite.
bool IsPositiveDefinite(const Eigen::MatrixXd& information);

// The nearest (Frobenius) symmetric positive-definite matrix: symmetrize,
// then clamp eigenvalues below `relative_floor * max_eigenvalue` (or
// `absolute_floor` if that is larger) up to that floor. A matrix without a
// positive eigenvalue cannot be repaired and is returned symmetrized (still
// not positive definite).
Eigen::MatrixXd NearestPositiveDefinite(const Eigen::MatrixXd& information,
                                        double relative_floor = 1e-9,
                                        double absolute_floor = 1e-12);

}  // namespace slam

#endif  // SLAM_CORE_INFORMATION_H_
