// Tests of the robust kernels (factors/robust_kernels.h): rho and its first
// two derivatives for every kernel at several widths and s values, the
// small-s behaviour rho(s) ~ s, the DCS kernel's documented shape, and the
// parsing of "kind:width" specifications.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "ceres/loss_function.h"
#include "factors/robust_kernels.h"
#include "gtest/gtest.h"

namespace slam {
namespace {

std::shared_ptr<ceres::LossFunction> Loss(const std::string& text) {
  RobustKernelSpec spec;
  std::string error;
  EXPECT_TRUE(ParseRobustKernel(text, &spec, &error)) << text << ": " << error;
  return MakeLoss(spec);
}

struct Rho {
  double v[3];
};

Rho Eval(const ceres::LossFunction& loss, double s) {
  Rho r;
  loss.Evaluate(s, r.v);
  return r;
}

const std::vector<std::string>& Kinds() {
  static const std::vector<std::string> kinds = {"huber", "cauchy",
                                                 "geman_mcclure", "dcs"};
  return kinds;
}

const std::vector<double>& Widths() {
  static const std::vector<double> widths = {0.3, 1.0, 2.5, 10.0};
  return widths;
}

// The kernel's kink (where rho'' jumps), if any: Huber at s = a^2, DCS at
// s = phi. Finite differences of rho' must not straddle it.
double Kink(const std::string& kind, double width) {
  if (kind == "huber") return width * width;
  if (kind == "dcs") return width;
  return -1.0;
}

TEST(RobustKernelsTest, DerivativesMatchCentralDifferences) {
  const std::vector<double> s_values = {1e-4, 0.01, 0.07, 0.3,   0.8,   1.7,
                                        4.0,  9.5,  30.0, 150.0, 2000.0};
  for (const std::string& kind : Kinds()) {
    for (double width : Widths()) {
      std::ostringstream name;
      name << kind << ":" << width;
      const auto loss = Loss(name.str());
      ASSERT_NE(loss, nullptr);
      for (double s : s_values) {
        const double h = 1e-5 * std::max(s, 1e-3);
        const double kink = Kink(kind, width);
        if (kink > 0.0 && std::abs(s - kink) < 4.0 * h) continue;
        const Rho r = Eval(*loss, s);
        const Rho rp = Eval(*loss, s + h);
        const Rho rm = Eval(*loss, s - h);
        const double d1 = (rp.v[0] - rm.v[0]) / (2.0 * h);
        const double d2 = (rp.v[1] - rm.v[1]) / (2.0 * h);
        EXPECT_NEAR(r.v[1], d1, 1e-6 * std::max(1.0, std::abs(d1)))
            << name.str() << " s=" << s;
        EXPECT_NEAR(r.v[2], d2,
                    1e-6 * std::max(std::abs(d2), std::abs(r.v[1]) / s))
            << name.str() << " s=" << s;
        // Kernels are non-decreasing and never exceed the plain square.
        EXPECT_GT(r.v[1], 0.0) << name.str() << " s=" << s;
        EXPECT_LE(r.v[1], 1.0 + 1e-15) << name.str() << " s=" << s;
        EXPECT_LE(r.v[0], s * (1.0 + 1e-15)) << name.str() << " s=" << s;
        EXPECT_GT(r.v[0], 0.0) << name.str() << " s=" << s;
      }
    }
  }
}

TEST(RobustKernelsTest, BehaveLikeSquaredNormNearZero) {
  for (const std::string& kind : Kinds()) {
    for (double width : Widths()) {
      std::ostringstream name;
      name << kind << ":" << width;
      const auto loss = Loss(name.str());
      for (double s : {0.0, 1e-12, 1e-9, 1e-7}) {
        const Rho r = Eval(*loss, s);
        // Ceres' CauchyLoss computes b log(1 + s / b), not log1p: absolute
        // rounding of about b * eps, irrelevant next to any real chi2.
        const double rounding = 4e-16 * std::max(1.0, width * width);
        EXPECT_NEAR(r.v[0], s, 1e-5 * s + rounding) << name.str() << " s=" << s;
        EXPECT_NEAR(r.v[1], 1.0, 1e-5) << name.str() << " s=" << s;
      }
    }
  }
}

TEST(RobustKernelsTest, GemanMcClureClosedForm) {
  for (double a : Widths()) {
    GemanMcClureLoss loss(a);
    for (double s : {0.0, 0.5, 3.0, 1e4}) {
      const Rho r = Eval(loss, s);
      EXPECT_NEAR(r.v[0], a * a * s / (a * a + s), 1e-12 * (1.0 + s));
    }
    // Bounded by a^2.
    EXPECT_LT(Eval(loss, 1e12).v[0], a * a);
    EXPECT_NEAR(Eval(loss, 1e12).v[0], a * a, 1e-9 * a * a);
  }
}

TEST(RobustKernelsTest, HuberAndCauchyAreCeresKernels) {
  for (double a : Widths()) {
    const ceres::HuberLoss huber(a);
    const ceres::CauchyLoss cauchy(a);
    const auto h = Loss("huber:" + std::to_string(a));
    const auto c = Loss("cauchy:" + std::to_string(a));
    for (double s : {0.01, 0.5, 3.0, 100.0}) {
      const Rho expected_h = Eval(huber, s), got_h = Eval(*h, s);
      const Rho expected_c = Eval(cauchy, s), got_c = Eval(*c, s);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(got_h.v[k], expected_h.v[k],
                    1e-9 * (1 + std::abs(expected_h.v[k])));
        EXPECT_NEAR(got_c.v[k], expected_c.v[k],
                    1e-9 * (1 + std::abs(expected_c.v[k])));
      }
    }
    // Huber: quadratic up to a^2 (width in whitened-residual units).
    EXPECT_DOUBLE_EQ(Eval(*h, 0.99 * a * a).v[0], 0.99 * a * a);
    EXPECT_LT(Eval(*h, 4.0 * a * a).v[0], 4.0 * a * a);
  }
}

TEST(DcsLossTest, DocumentedShape) {
  for (double phi : {0.1, 1.0, 5.0, 40.0}) {
    const DcsLoss loss(phi);
    // Plain least squares up to phi.
    for (double s : {0.0, 0.25 * phi, 0.5 * phi, 0.999 * phi, phi}) {
      const Rho r = Eval(loss, s);
      EXPECT_DOUBLE_EQ(r.v[0], s) << "phi=" << phi << " s=" << s;
      EXPECT_DOUBLE_EQ(r.v[1], 1.0);
      EXPECT_DOUBLE_EQ(r.v[2], 0.0);
    }
    // Continuous, with a continuous first derivative, at phi.
    const double eps = 1e-9 * phi;
    const Rho below = Eval(loss, phi - eps), above = Eval(loss, phi + eps);
    EXPECT_NEAR(below.v[0], above.v[0], 1e-8 * phi);
    EXPECT_NEAR(above.v[0], phi, 1e-8 * phi);
    EXPECT_NEAR(below.v[1], above.v[1], 1e-8);
    // Bounded above by 3 phi, approaching it, increasing.
    double previous = 0.0;
    for (double s : {1.5 * phi, 3.0 * phi, 10.0 * phi, 1e3 * phi, 1e9 * phi}) {
      const Rho r = Eval(loss, s);
      EXPECT_LT(r.v[0], 3.0 * phi);
      EXPECT_GT(r.v[0], previous);
      previous = r.v[0];
    }
    EXPECT_NEAR(Eval(loss, 1e12 * phi).v[0], 3.0 * phi, 1e-9 * phi);
    // IRLS weight rho'(s) = min(1, 2 phi / (phi + s))^2 (the DCS scale
    // squared).
    for (double s :
         {0.0, 0.3 * phi, phi, 1.01 * phi, 2.0 * phi, 7.0 * phi, 123.0 * phi}) {
      const double scale = std::min(1.0, 2.0 * phi / (phi + s));
      EXPECT_NEAR(Eval(loss, s).v[1], scale * scale, 1e-14)
          << "phi=" << phi << " s=" << s;
    }
  }
}

TEST(RobustKernelSpecTest, ParsesValidSpecifications) {
  RobustKernelSpec spec;
  std::string error;
  ASSERT_TRUE(ParseRobustKernel("huber:1.5", &spec, &error)) << error;
  EXPECT_EQ(spec.kind, "huber");
  EXPECT_DOUBLE_EQ(spec.width, 1.5);
  EXPECT_EQ(spec.ToString(), "huber:1.5");

  ASSERT_TRUE(ParseRobustKernel("dcs", &spec, &error)) << error;
  EXPECT_EQ(spec.kind, "dcs");
  EXPECT_DOUBLE_EQ(spec.width, 1.0);
  EXPECT_NE(std::dynamic_pointer_cast<DcsLoss>(MakeLoss(spec)), nullptr);

  ASSERT_TRUE(ParseRobustKernel("cauchy:0.25", &spec, &error)) << error;
  EXPECT_NE(std::dynamic_pointer_cast<ceres::CauchyLoss>(MakeLoss(spec)),
            nullptr);
  ASSERT_TRUE(ParseRobustKernel("geman_mcclure:3e1", &spec, &error)) << error;
  EXPECT_DOUBLE_EQ(spec.width, 30.0);
  EXPECT_NE(std::dynamic_pointer_cast<GemanMcClureLoss>(MakeLoss(spec)),
            nullptr);
  ASSERT_TRUE(ParseRobustKernel("huber", &spec, &error)) << error;
  EXPECT_NE(std::dynamic_pointer_cast<ceres::HuberLoss>(MakeLoss(spec)),
            nullptr);

  ASSERT_TRUE(ParseRobustKernel("none", &spec, &error)) << error;
  EXPECT_EQ(spec.kind, "none");
  EXPECT_EQ(spec.ToString(), "none");
  EXPECT_EQ(MakeLoss(spec), nullptr);

  // ToString round-trips.
  for (const std::string text :
       {"huber:1.5", "dcs:2", "cauchy:0.25", "geman_mcclure:7"}) {
    ASSERT_TRUE(ParseRobustKernel(text, &spec, &error)) << error;
    RobustKernelSpec again;
    ASSERT_TRUE(ParseRobustKernel(spec.ToString(), &again, &error)) << error;
    EXPECT_EQ(again.kind, spec.kind);
    EXPECT_DOUBLE_EQ(again.width, spec.width);
  }
}

TEST(RobustKernelSpecTest, RejectsInvalidSpecifications) {
  for (const std::string text :
       {"foo:1", "foo", "huber:-1", "huber:x", "huber:", "huber:0",
        "huber:1.5x", "huber:nan", "huber:inf", "huber:1e400", "Huber:1", "",
        ":1", "dcs:-0.5", "cauchy: "}) {
    RobustKernelSpec spec;
    spec.kind = "sentinel";
    std::string error;
    EXPECT_FALSE(ParseRobustKernel(text, &spec, &error)) << "'" << text << "'";
    EXPECT_FALSE(error.empty()) << "'" << text << "'";
    EXPECT_EQ(spec.kind, "sentinel")
        << "spec modified on failure: '" << text << "'";
  }
  // The messages say what is wrong.
  RobustKernelSpec spec;
  std::string error;
  EXPECT_FALSE(ParseRobustKernel("foo:1", &spec, &error));
  EXPECT_NE(error.find("foo"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(ParseRobustKernel("huber:x", &spec, &error));
  EXPECT_NE(error.find("'x'"), std::string::npos) << error;
}

}  // namespace
}  // namespace slam
