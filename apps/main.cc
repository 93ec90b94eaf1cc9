// slam: the command-line front of the backend.
//
//   slam optimize -i IN.g2o -o OUT.g2o [flags]   optimize a pose graph
//   slam info FILE                               counts, components, chi2
//   slam simulate -o DIR [flags]                 synthetic data with truth
//   slam run --config configs/aces.yaml          2D laser SLAM on a CARMEN log
//   slam inertial -i IN -o DIR [flags]           IMU window / batch
//
// `slam <command> --help` lists the flags. Every setting also has a YAML
// form (--config FILE); --dump_config prints the effective configuration.
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/commands.h"
#include "apps/process_heap.h"
#include "apps/safe_stderr.h"
#include "datasets/atomic_file.h"

namespace {

struct Command {
  std::function<int(const std::vector<std::string>&)> run;
  const char* summary;
};

const std::map<std::string, Command>& Commands() {
  static const auto* commands = new std::map<std::string, Command>{
      {"optimize",
       {slam::RunOptimizeCommand,
        "optimize a pose graph: slam optimize -i IN -o OUT [--init ...]"}},
      {"info", {slam::RunInfoCommand, "describe a graph file: slam info FILE"}},
      {"eval",
       {slam::RunEvalCommand,
        "ATE/RPE of a trajectory: slam eval --ref GT --est EST [--plot DIR]"}},
      {"run",
       {slam::RunRunCommand,
        "2D laser SLAM on a CARMEN log: slam run --config configs/aces.yaml"}},
      {"inertial",
       {slam::RunInertialCommand,
        "IMU + position fixes: slam inertial -i EUROC_DIR|GTSAM.csv -o DIR"}},
      {"simulate",
       {slam::RunSimulateCommand,
        "write a synthetic dataset with ground truth: slam simulate -o DIR"}},
  };
  return *commands;
}

void PrintUsage() {
  std::fprintf(stderr, "usage: slam <command> [flags] [args]\n\ncommands:\n");
  for (const auto& [name, command] : Commands()) {
    std::fprintf(stderr, "  %-10s %s\n", name.c_str(), command.summary);
  }
  std::fprintf(stderr,
               "\n'slam <command> --helpon=<file>' or '--help' lists flags.\n");
}

}  // namespace

int main(int argc, char** argv) {
  slam::ConfigureProcessHeap();  // See apps/process_heap.h.
  slam::FilterControlBytesOnStderr();
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 ||
      std::strcmp(argv[1], "-h") == 0 || std::strcmp(argv[1], "help") == 0) {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  const std::string name = argv[1];
  auto it = Commands().find(name);
  if (it == Commands().end()) {
    std::fprintf(stderr, "slam: unknown command '%s'\n\n", name.c_str());
    PrintUsage();
    return 2;
  }
  // Drop the command name and let gflags parse the rest.
  std::vector<char*> rest = {argv[0]};
  for (int i = 2; i < argc; ++i) rest.push_back(argv[i]);
  int rest_argc = static_cast<int>(rest.size());
  char** rest_argv = rest.data();
  gflags::SetUsageMessage("slam " + name + ": " + it->second.summary);
  gflags::ParseCommandLineFlags(&rest_argc, &rest_argv, true);
  std::vector<std::string> args(rest_argv + 1, rest_argv + rest_argc);
  // The outputs of a command are published only when it succeeds: a failed
  // command leaves none of them behind (datasets/atomic_file.h).
  slam::OutputStage outputs;
  const int code = it->second.run(args);
  std::string error;
  if (code == 0 && !outputs.Commit(&error)) {
    std::fprintf(stderr, "slam %s: %s\n", name.c_str(), error.c_str());
    return 1;
  }
  return code;
}
