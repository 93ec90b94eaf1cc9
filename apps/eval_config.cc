#include "apps/eval_config.h"

#include <sstream>

#include "apps/format.h"
#include "apps/yaml_config.h"

namespace slam {

bool LoadEvalSectionOfConfig(const std::string& config_path,
                             EvalSettings* settings, std::string* error) {
  if (config_path.empty()) return true;
  YAML::Node root;
  if (!LoadYamlFile(config_path, &root, error)) return false;
  if (!CheckTopLevelSections(root, config_path, error)) return false;
  if (!root.IsMap() || !root["eval"]) return true;
  bool associate_auto = true;
  return ReadEvalSettingsYaml(root["eval"], config_path + " (eval)", settings,
                              &associate_auto, error);
}

bool ReadEvalSettingsYaml(const YAML::Node& node, const std::string& where,
                          EvalSettings* s, bool* associate_auto,
                          std::string* error) {
  if (!node) return true;
  if (!CheckKnownKeys(
          node,
          {"associate", "t_max_diff", "t_offset", "align", "n_to_align",
           "rpe_delta", "rpe_unit", "rpe_all_pairs", "rpe_pairs_from_reference",
           "rpe_delta_tol", "kitti", "unique_pairs", "relations_t_max_diff",
           "relations_interpolate"},
          where, error)) {
    return false;
  }
  std::string associate = *associate_auto ? "auto"
                          : s->association == AssociationMethod::kIndex
                              ? "index"
                              : "time";
  std::string align = AlignmentMethodName(s->align);
  std::string unit = DeltaUnitName(s->rpe.unit);
  if (!ReadOptional(node, "associate", where, &associate, error) ||
      !ReadOptional(node, "t_max_diff", where, &s->sync.t_max_diff, error) ||
      !ReadOptional(node, "t_offset", where, &s->sync.t_offset, error) ||
      !ReadOptional(node, "unique_pairs", where, &s->sync.unique_pairs,
                    error) ||
      !ReadOptional(node, "align", where, &align, error) ||
      !ReadOptional(node, "n_to_align", where, &s->n_to_align, error) ||
      !ReadOptional(node, "rpe_delta", where, &s->rpe.delta, error) ||
      !ReadOptional(node, "rpe_unit", where, &unit, error) ||
      !ReadOptional(node, "rpe_all_pairs", where, &s->rpe.all_pairs, error) ||
      !ReadOptional(node, "rpe_pairs_from_reference", where,
                    &s->rpe.pairs_from_reference, error) ||
      !ReadOptional(node, "rpe_delta_tol", where, &s->rpe.rel_delta_tol,
                    error) ||
      !ReadOptional(node, "kitti", where, &s->kitti, error) ||
      !ReadOptional(node, "relations_t_max_diff", where,
                    &s->relations.t_max_diff, error) ||
      !ReadOptional(node, "relations_interpolate", where,
                    &s->relations.interpolate, error)) {
    return false;
  }
  if (associate == "auto") {
    *associate_auto = true;
  } else if (associate == "time" || associate == "timestamp") {
    *associate_auto = false;
    s->association = AssociationMethod::kTimestamp;
  } else if (associate == "index") {
    *associate_auto = false;
    s->association = AssociationMethod::kIndex;
  } else {
    *error = where + ": associate must be auto, time or index, not '" +
             associate + "'";
    return false;
  }
  if (!ParseAlignmentMethod(align, &s->align)) {
    *error = where + ": align must be none, se3, sim3, scale or origin, not '" +
             align + "'";
    return false;
  }
  if (!ParseDeltaUnit(unit, &s->rpe.unit)) {
    *error = where + ": rpe_unit must be frames, m or s, not '" + unit + "'";
    return false;
  }
  return true;
}

std::string EvalSettingsYaml(const EvalSettings& s, bool associate_auto,
                             int indent) {
  const std::string pad(indent, ' ');
  std::ostringstream o;
  o << pad << "associate: "
    << (associate_auto                               ? "auto"
        : s.association == AssociationMethod::kIndex ? "index"
                                                     : "time")
    << "            # auto | time | index (auto: index when a file has no "
       "stamps)\n";
  o << pad << "t_max_diff: " << Fmt("%.17g", s.sync.t_max_diff)
    << "          # s, nearest-stamp association\n";
  o << pad << "t_offset: " << Fmt("%.17g", s.sync.t_offset)
    << "               # s, added to the estimate's stamps\n";
  o << pad << "unique_pairs: " << (s.sync.unique_pairs ? "true" : "false")
    << "       # true: one-to-one pairs (not evo's behaviour)\n";
  o << pad << "align: " << AlignmentMethodName(s.align)
    << "                # none | se3 | sim3 | scale | origin\n";
  o << pad << "n_to_align: " << s.n_to_align
    << "            # first N pairs for se3/sim3/scale (-1: all)\n";
  o << pad << "rpe_delta: " << Fmt("%.17g", s.rpe.delta) << "\n";
  o << pad << "rpe_unit: " << DeltaUnitName(s.rpe.unit)
    << "          # frames | m (path length) | s\n";
  o << pad << "rpe_all_pairs: " << (s.rpe.all_pairs ? "true" : "false") << "\n";
  o << pad << "rpe_pairs_from_reference: "
    << (s.rpe.pairs_from_reference ? "true" : "false")
    << "   # false: pairs chosen on the estimate (evo's default)\n";
  o << pad << "rpe_delta_tol: " << Fmt("%.17g", s.rpe.rel_delta_tol)
    << "         # relative, all-pairs mode (m, s)\n";
  o << pad << "kitti: " << (s.kitti ? "true" : "false")
    << "              # KITTI devkit metric\n";
  o << pad << "relations_t_max_diff: " << Fmt("%.17g", s.relations.t_max_diff)
    << "   # s, --relations: stamp match\n";
  o << pad
    << "relations_interpolate: " << (s.relations.interpolate ? "true" : "false")
    << "  # --relations: interpolate poses between stamps\n";
  return o.str();
}

bool CheckEvalSettings(const EvalSettings& s, std::string* error) {
  if (!(s.relations.t_max_diff >= 0.0)) {
    *error = "relations_t_max_diff must be >= 0";
    return false;
  }
  if (!CheckAssociationOptions(s.sync, error)) return false;
  if (!(s.rpe.delta > 0.0)) {
    *error = "rpe_delta must be > 0";
    return false;
  }
  if (!(s.rpe.rel_delta_tol >= 0.0)) {
    *error = "rpe_delta_tol must be >= 0";
    return false;
  }
  return true;
}

}  // namespace slam
