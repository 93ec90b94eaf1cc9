#include "factors/robust_kernels.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace slam {

void GemanMcClureLoss::Evaluate(double s, double rho[3]) const {
  const double d = a2_ + s;
  rho[0] = a2_ * s / d;
  rho[1] = a2_ * a2_ / (d * d);
  rho[2] = -2.0 * a2_ * a2_ / (d * d * d);
}

void DcsLoss::Evaluate(double s, double rho[3]) const {
  if (s <= phi_) {
    rho[0] = s;
    rho[1] = 1.0;
    rho[2] = 0.0;
    return;
  }
  const double d = phi_ + s;
  rho[0] = 3.0 * phi_ - 4.0 * phi_ * phi_ / d;
  rho[1] = 4.0 * phi_ * phi_ / (d * d);
  rho[2] = -8.0 * phi_ * phi_ / (d * d * d);
}

std::string RobustKernelSpec::ToString() const {
  if (kind == "none") return kind;
  std::ostringstream out;
  out << kind << ":" << width;
  return out.str();
}

bool ParseRobustKernel(const std::string& text, RobustKernelSpec* spec,
                       std::string* error) {
  RobustKernelSpec parsed;
  const size_t colon = text.find(':');
  parsed.kind = text.substr(0, colon);
  if (parsed.kind != "none" && parsed.kind != "huber" &&
      parsed.kind != "cauchy" && parsed.kind != "geman_mcclure" &&
      parsed.kind != "dcs") {
    *error = "unknown robust kernel '" + parsed.kind +
             "' (expected none, huber, cauchy, geman_mcclure or dcs)";
    return false;
  }
  if (colon != std::string::npos) {
    const std::string width = text.substr(colon + 1);
    char* end = nullptr;
    parsed.width = std::strtod(width.c_str(), &end);
    if (width.empty() || *end != '\0' || !std::isfinite(parsed.width) ||
        parsed.width <= 0.0) {
      *error = "robust kernel width '" + width +
               "' is not a positive number (in '" + text + "')";
      return false;
    }
  }
  *spec = parsed;
  return true;
}

std::shared_ptr<ceres::LossFunction> MakeLoss(const RobustKernelSpec& spec) {
  if (spec.kind == "huber") {
    return std::make_shared<ceres::HuberLoss>(spec.width);
  }
  if (spec.kind == "cauchy") {
    return std::make_shared<ceres::CauchyLoss>(spec.width);
  }
  if (spec.kind == "geman_mcclure") {
    return std::make_shared<GemanMcClureLoss>(spec.width);
  }
  if (spec.kind == "dcs") return std::make_shared<DcsLoss>(spec.width);
  return nullptr;
}

}  // namespace slam
