// The shipped per-log laser configs (configs/aces.yaml, intel.yaml,
// mit_csail.yaml) name only the log, the relations and the output: the
// laser pipeline has one set of defaults for the kind of data, no per-file
// tuning. A setting added to one of them fails here.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>
#include <string>

#include "apps/run_config.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

TEST(LaserConfigsTest, PerLogConfigsNameOnlyLogRelationsAndOutput) {
  const std::set<std::string> allowed = {"log", "relations", "output_dir"};
  for (const char* name : {"aces.yaml", "intel.yaml", "mit_csail.yaml"}) {
    SCOPED_TRACE(name);
    const std::string path = testing::ConfigPath(name);
    const YAML::Node root = YAML::LoadFile(path);
    ASSERT_TRUE(root.IsMap());
    ASSERT_EQ(root.size(), 1u) << "only a run: section";
    const YAML::Node run = root["run"];
    ASSERT_TRUE(run.IsMap());
    for (const auto& entry : run) {
      EXPECT_TRUE(allowed.count(entry.first.as<std::string>()))
          << "run." << entry.first.as<std::string>();
    }
    RunConfig config;
    std::string error;
    ASSERT_TRUE(LoadRunConfig(path, &config, &error)) << error;
    EXPECT_FALSE(config.log.empty());
    EXPECT_FALSE(config.relations.empty());
    // Everything else is the default, as --dump_config prints it.
    RunConfig defaults;
    defaults.log = config.log;
    defaults.relations = config.relations;
    defaults.output_dir = config.output_dir;
    EXPECT_EQ(RunConfigToYaml(config), RunConfigToYaml(defaults));
    // The files it names are in the shared laser folder, when present.
    if (std::filesystem::is_directory(testing::DatasetsDir())) {
      EXPECT_TRUE(std::filesystem::exists(testing::DatasetPath(config.log)))
          << config.log;
      EXPECT_TRUE(
          std::filesystem::exists(testing::DatasetPath(config.relations)))
          << config.relations;
    }
  }
}

}  // namespace
}  // namespace slam
