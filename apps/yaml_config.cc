#include "apps/yaml_config.h"

#include <exception>
#include <filesystem>
#include <system_error>

#include "datasets/text_util.h"

namespace slam {

bool CheckKnownKeys(const YAML::Node& node,
                    std::initializer_list<const char*> known,
                    const std::string& where, std::string* error) {
  if (!node) return true;
  if (!node.IsMap()) {
    *error = where + ": expected a mapping of settings";
    return false;
  }
  for (const auto& entry : node) {
    // A mapping or a sequence as a key ("{a: 1}: x") is no setting name;
    // as<std::string>() would throw (found by fuzz_config).
    if (!entry.first.IsScalar()) {
      *error = where + ":" + std::to_string(entry.first.Mark().line + 1) +
               ": a key must be a plain name";
      return false;
    }
    const std::string key = entry.first.as<std::string>();
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found) {
      std::string list;
      for (const char* k : known)
        list += (list.empty() ? "" : ", ") + std::string(k);
      *error = where + ":" + std::to_string(entry.first.Mark().line + 1) +
               ": unknown key '" + text::Printable(key) + "' (known: " + list +
               ")";
      return false;
    }
  }
  return true;
}

bool CheckTopLevelSections(const YAML::Node& root, const std::string& where,
                           std::string* error) {
  return CheckKnownKeys(
      root, {"optimize", "simulate", "eval", "run", "inertial", "loops"}, where,
      error);
}

bool LoadYamlFile(const std::string& path, YAML::Node* root,
                  std::string* error) {
  // Read first (a directory, a missing or unreadable file: "PATH: cannot
  // open: reason"), then parse: YAML::LoadFile reports these as "bad file"
  // at line 0, or throws std::ios_failure past its own exception type.
  constexpr size_t kMaxConfigBytes = 16 << 20;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    *error = path + ": no such file";
    return false;
  }
  std::string text;
  if (!text::ReadWholeFile(path, &text, error, kMaxConfigBytes)) return false;
  try {
    *root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    *error = path +
             (e.mark.is_null() ? std::string()
                               : ":" + std::to_string(e.mark.line + 1)) +
             ": " + e.msg;
    return false;
  } catch (const std::exception& e) {
    *error = path + ": cannot read: " + e.what();
    return false;
  }
  return true;
}

}  // namespace slam
