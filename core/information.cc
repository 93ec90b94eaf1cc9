#include "core/information.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace slam {

namespace {

// Symmetry and finiteness checks shared by the two functions below.
bool SymmetricAndFinite(const Eigen::MatrixXd& information) {
  if (information.rows() != information.cols() || information.rows() == 0) {
    return false;
  }
  if (!information.allFinite()) return false;
  const double scale = information.cwiseAbs().maxCoeff();
  return (information - information.transpose()).cwiseAbs().maxCoeff() <=
         1e-9 * std::max(scale, 1e-300);
}

}  // namespace

bool IsPositiveDefinite(const Eigen::MatrixXd& information) {
  if (!SymmetricAndFinite(information)) return false;
  Eigen::LLT<Eigen::MatrixXd> llt(information);
  if (llt.info() != Eigen::Success) return false;
  // LLT succeeds on some matrices with a zero pivot that rounding made
  // positive; require a clearly positive diagonal of L.
  const Eigen::VectorXd diag = llt.matrixL().toDenseMatrix().diagonal();
  return (diag.array() > 0.0).all();
}

bool SqrtInformation(const Eigen::MatrixXd& information,
                     Eigen::MatrixXd* sqrt_information) {
  if (!SymmetricAndFinite(information)) return false;
  Eigen::LLT<Eigen::MatrixXd> llt(information);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd l = llt.matrixL();
  if (!(l.diagonal().array() > 0.0).all()) return false;
  *sqrt_information = l.transpose();
  return true;
}

Eigen::MatrixXd NearestPositiveDefinite(const Eigen::MatrixXd& information,
                                        double relative_floor,
                                        double absolute_floor) {
  const Eigen::MatrixXd sym = 0.5 * (information + information.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(sym);
  Eigen::VectorXd values = eig.eigenvalues();
  const double max_value = values.maxCoeff();
  // Nothing positive to keep (zero or negative semidefinite): not a rounding
  // problem; return the symmetrized input, which callers see is not PD.
  if (!(max_value > 0.0)) return sym;
  const double floor_value =
      std::max(relative_floor * max_value, absolute_floor);
  for (int i = 0; i < values.size(); ++i) {
    values[i] = std::max(values[i], floor_value);
  }
  Eigen::MatrixXd repaired =
      eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
  return 0.5 * (repaired + repaired.transpose());
}

}  // namespace slam
