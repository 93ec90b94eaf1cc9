#include "apps/certificate_report.h"

#include <cstdio>
#include <vector>

#include <gflags/gflags.h>

#include "core/certificate.h"

DEFINE_bool(certify, false,
            "optimize: certify the solution's global optimality for the "
            "isotropic approximation of the pose graph (SE-Sync)");
DEFINE_string(global, "auto",
              "optimize --certify: auto (when the certificate fails, the "
              "Riemannian staircase, rounding and LM again) or off");

namespace slam {
namespace {

void PrintCertificate(const CertificateResult& c) {
  std::printf(
      "certificate (isotropic objective, not the g2o chi2): %s, lambda_min "
      "%.6g (delta %.3g, rank %d), isotropic objective %.10g, lower bound "
      "%.10g, suboptimality bound %.3g (%.3f s: refining %d iterations "
      "%.3f s, lambda_min %.3f s, %d factorizations)\n",
      c.certified ? "CERTIFIED globally optimal" : "NOT certified",
      c.lambda_min, c.delta, c.rank, c.objective, c.lower_bound,
      c.suboptimality_bound, c.seconds, c.refine_iterations, c.refine_seconds,
      c.eigen_seconds, c.factorizations);
}

}  // namespace

bool CertifyIfAsked(Graph* graph, const OptimizerOptions& options,
                    OptimizerSummary* summary, JsonObject* json,
                    std::string* error) {
  if (!FLAGS_certify) return true;
  if (FLAGS_global != "auto" && FLAGS_global != "off") {
    *error = "--global '" + FLAGS_global + "' is not auto or off";
    return false;
  }
  CertificateOptions certificate_options;
  certificate_options.progress = [](const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  };
  CertificateResult c;
  if (!CertifyGraph(*graph, certificate_options, &c, error)) {
    // Graphs the certificate does not cover (landmarks, priors, ...) keep
    // their solution; the report says why there is no certificate.
    std::printf("certificate: not available: %s\n", error->c_str());
    json->Add("certified", false).Add("not_available", *error);
    error->clear();
    return true;
  }
  double seconds = c.seconds;
  bool escaped = false;
  double escape_chi2 = 0.0;
  int escape_iterations = 0;
  if (!c.certified) PrintCertificate(c);
  if (!c.certified && FLAGS_global == "auto") {
    std::vector<std::vector<double>> saved;
    for (const auto& [key, node] : graph->nodes()) saved.push_back(node->value);
    const double chi2_before = graph->Chi2();
    CertificateResult global;
    std::string why;
    const bool relaxation_certified =
        SolveIsotropicGlobally(graph, certificate_options, &global, &why);
    if (!relaxation_certified && !global.rounded_uncertified) {
      std::printf("staircase: %s; keeping the LM solution\n", why.c_str());
    } else {
      seconds += global.seconds;
      if (relaxation_certified) {
        std::printf(
            "staircase: relaxation certified at rank %d (isotropic optimum "
            "%.10g) in %.3f s; rounded, then LM on the full objective\n",
            global.rank, global.objective, global.seconds);
      } else {
        std::printf(
            "staircase: %s (%.3f s); its last iterate rounded all the same, "
            "then LM on the full objective, kept only if lower\n",
            why.c_str(), global.seconds);
      }
      OptimizerOptions quiet = options;
      quiet.verbose = false;
      const OptimizerSummary again = Optimize(graph, quiet, nullptr);
      escape_iterations = again.iterations;
      escape_chi2 = again.final_chi2;
      summary->iterations += again.iterations;
      summary->solve_seconds += again.solve_seconds;
      std::printf(
          "LM from the rounded solution: chi2 %.10g in %d iterations "
          "(LM from the start had %.10g)\n",
          again.final_chi2, again.iterations, chi2_before);
      if (again.usable && again.final_chi2 < chi2_before) {
        escaped = true;
        summary->final_chi2 = again.final_chi2;
        summary->final_robust_chi2 = again.final_robust_chi2;
        summary->converged = again.converged;
      } else {
        size_t k = 0;
        for (const auto& [key, node] : graph->nodes()) {
          std::copy(saved[k].begin(), saved[k].end(), node->value.begin());
          ++k;
        }
      }
      if (!CertifyGraph(*graph, certificate_options, &c, error)) {
        *error = "certificate: " + *error;
        return false;
      }
      seconds += c.seconds;
    }
  }
  PrintCertificate(c);
  std::printf(
      "the certificate is for the isotropic objective (SE-Sync's kappa, tau "
      "per factor); the g2o objective's LM solution is %.6g above its "
      "certified critical point in that objective (%.6g vs %.6g), rotations "
      "up to %.3g deg and translations %.3g RMS from it\n",
      c.start_objective - c.objective, c.start_objective, c.objective,
      c.max_rotation_difference * 180.0 / M_PI, c.rms_translation_difference);
  json->Add("certified", c.certified)
      .Add("lambda_min", c.lambda_min)
      .Add("delta", c.delta)
      .Add("lower_bound", c.lower_bound)
      .Add("suboptimality_bound", c.suboptimality_bound)
      .Add("isotropic_objective", c.objective)
      .Add("lm_isotropic_objective", c.start_objective)
      .Add("max_rotation_difference_rad", c.max_rotation_difference)
      .Add("rms_translation_difference", c.rms_translation_difference)
      .Add("rank", c.rank)
      .Add("refine_iterations", c.refine_iterations)
      .Add("refine_seconds", c.refine_seconds)
      .Add("eigen_seconds", c.eigen_seconds)
      .Add("escaped", escaped)
      .Add("seconds", seconds);
  JsonObject phases;
  for (const auto& [name, s] : c.phase_seconds) phases.Add(name, s);
  json->Add("phase_seconds", phases);
  if (escaped) {
    json->Add("escape_chi2", escape_chi2)
        .Add("escape_iterations", escape_iterations);
  }
  return true;
}

}  // namespace slam
