// A config struct described once as a tree of named fields pointing into it,
// so that loading from YAML, the unknown-key check and printing back
// (--dump_config) share one description:
//
//   Section Schema(MyConfig* c) {
//     return {"run", {S("log", &c->log), D("max_range", &c->max_range)},
//             {{"icp", {I("max_iterations", &c->icp.max_iterations)}, {}}}};
//   }
//   LoadSection(root["run"], Schema(&config), path, &error);
//   PrintSection(Schema(&config), 0, &out);
#ifndef SLAM_APPS_CONFIG_SCHEMA_H_
#define SLAM_APPS_CONFIG_SCHEMA_H_

#include <ostream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "factors/robust_kernels.h"

namespace slam::config_schema {

struct Field {
  enum Kind { kDouble, kInt, kBool, kString, kKernel };
  const char* key;
  Kind kind;
  void* value;
};

struct Section {
  const char* name;
  std::vector<Field> fields;
  std::vector<Section> children;
};

inline Field D(const char* key, double* v) { return {key, Field::kDouble, v}; }
inline Field I(const char* key, int* v) { return {key, Field::kInt, v}; }
inline Field B(const char* key, bool* v) { return {key, Field::kBool, v}; }
inline Field S(const char* key, std::string* v) {
  return {key, Field::kString, v};
}
inline Field K(const char* key, RobustKernelSpec* v) {
  return {key, Field::kKernel, v};
}

// Reads the settings of `node` into the fields; an unknown key is an error
// "WHERE:LINE: unknown key 'x' in SECTION (known: ...)", a value of the
// wrong type too.
bool LoadSection(const YAML::Node& node, const Section& section,
                 const std::string& where, std::string* error);
// Prints the section as YAML, indented by `indent` spaces.
void PrintSection(const Section& section, int indent, std::ostream* out);

}  // namespace slam::config_schema

#endif  // SLAM_APPS_CONFIG_SCHEMA_H_
