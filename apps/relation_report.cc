#include "apps/relation_report.h"

#include <string>

#include "apps/format.h"

namespace slam {
namespace {

struct Row {
  const char* name;
  const MeanStd* value;
  const char* unit;
};

}  // namespace

void PrintRelationError(const RelationErrorResult& r,
                        const RelationErrorOptions& options,
                        std::ostream& out) {
  out << "relation error (Kuemmerle et al. 2009): " << r.used.size() << " of "
      << r.relations << " relations used, " << r.unmatched
      << " unmatched (no pose within " << Fmt("%g", options.t_max_diff) << " s"
      << (options.interpolate ? " nor between two poses" : "") << "), "
      << r.interpolated << " with interpolated poses\n";
  out << "                        mean            std\n";
  const Row rows[] = {
      {"translation abs", &r.translation_abs, "m"},
      {"translation sq ", &r.translation_sq, "m^2"},
      {"rotation abs   ", &r.rotation_abs, "deg"},
      {"rotation sq    ", &r.rotation_sq, "deg^2"},
  };
  for (const Row& row : rows) {
    out << "  " << row.name << Fmt("  %11.6f", row.value->mean) << " +- "
        << Fmt("%11.6f", row.value->std) << "  " << row.unit << "\n";
  }
}

JsonObject RelationErrorJson(const RelationErrorResult& r,
                             const RelationErrorOptions& options) {
  JsonObject o;
  o.Add("relations", r.relations)
      .Add("used", r.used.size())
      .Add("unmatched", r.unmatched)
      .Add("interpolated", r.interpolated)
      .Add("t_max_diff", options.t_max_diff)
      .Add("interpolate", options.interpolate);
  const auto stats = [](const MeanStd& v, const char* unit) {
    JsonObject s;
    s.Add("mean", v.mean).Add("std", v.std).Add("unit", unit);
    return s;
  };
  o.Add("translation_abs", stats(r.translation_abs, "m"))
      .Add("translation_sq", stats(r.translation_sq, "m^2"))
      .Add("rotation_abs", stats(r.rotation_abs, "deg"))
      .Add("rotation_sq", stats(r.rotation_sq, "deg^2"));
  return o;
}

}  // namespace slam
