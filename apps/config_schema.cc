#include "apps/config_schema.h"

#include "apps/yaml_config.h"

namespace slam::config_schema {
namespace {

bool ReadField(const YAML::Node& node, const Field& f, const std::string& where,
               std::string* error) {
  switch (f.kind) {
    case Field::kDouble:
      return ReadOptional(node, f.key, where, static_cast<double*>(f.value),
                          error);
    case Field::kInt:
      return ReadOptional(node, f.key, where, static_cast<int*>(f.value),
                          error);
    case Field::kBool:
      return ReadOptional(node, f.key, where, static_cast<bool*>(f.value),
                          error);
    case Field::kString:
      return ReadOptional(node, f.key, where,
                          static_cast<std::string*>(f.value), error);
    case Field::kKernel: {
      auto* spec = static_cast<RobustKernelSpec*>(f.value);
      std::string text = spec->ToString();
      if (!ReadOptional(node, f.key, where, &text, error)) return false;
      std::string parse_error;
      if (!ParseRobustKernel(text, spec, &parse_error)) {
        *error = where + ": " + f.key + ": " + parse_error;
        return false;
      }
      return true;
    }
  }
  return true;
}

}  // namespace

bool LoadSection(const YAML::Node& node, const Section& section,
                 const std::string& where, std::string* error) {
  if (!node.IsMap()) {
    *error = where + ":" + std::to_string(node.Mark().line + 1) + ": '" +
             section.name + "' must be a mapping of settings";
    return false;
  }
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) {  // as<std::string>() would throw.
      *error = where + ":" + std::to_string(entry.first.Mark().line + 1) +
               ": a key must be a plain name";
      return false;
    }
    const std::string key = entry.first.as<std::string>();
    bool known = false;
    std::string list;
    for (const Field& f : section.fields) {
      known |= key == f.key;
      list += (list.empty() ? "" : ", ") + std::string(f.key);
    }
    for (const Section& c : section.children) {
      known |= key == c.name;
      list += (list.empty() ? "" : ", ") + std::string(c.name);
    }
    if (!known) {
      *error = where + ":" + std::to_string(entry.first.Mark().line + 1) +
               ": unknown key '" + key + "' in " + section.name +
               " (known: " + list + ")";
      return false;
    }
  }
  for (const Field& f : section.fields) {
    if (!ReadField(node, f, where, error)) return false;
  }
  for (const Section& c : section.children) {
    const YAML::Node child = node[c.name];
    if (child && !LoadSection(child, c, where, error)) return false;
  }
  return true;
}

void PrintSection(const Section& section, int indent, std::ostream* out) {
  const std::string pad(indent, ' ');
  *out << pad << section.name << ":\n";
  for (const Field& f : section.fields) {
    *out << pad << "  " << f.key << ": ";
    switch (f.kind) {
      case Field::kDouble:
        *out << *static_cast<double*>(f.value);
        break;
      case Field::kInt:
        *out << *static_cast<int*>(f.value);
        break;
      case Field::kBool:
        *out << (*static_cast<bool*>(f.value) ? "true" : "false");
        break;
      case Field::kString:
        *out << "\"" << *static_cast<std::string*>(f.value) << "\"";
        break;
      case Field::kKernel:
        *out << static_cast<RobustKernelSpec*>(f.value)->ToString();
        break;
    }
    *out << "\n";
  }
  for (const Section& c : section.children) PrintSection(c, indent + 2, out);
}

}  // namespace slam::config_schema
