// slam: the command-line front of the backend.
//
//   slam optimize -i IN.g2o -o OUT.g2o [flags]   optimize a pose graph
//   slam info FILE                               counts, components, chi2
//   slam simulate -o DIR [flags]                 synthetic data with truth
//   slam run --config configs/aces.yaml          2D laser SLAM on a CARMEN log
//   slam inertial -i IN -o DIR [flags]           IMU window / batch
//   slam eval --ref GT --est EST [flags]         APE / RPE / KITTI metric
//   slam run --config configs/kitti_stereo.yaml  stereo visual odometry
//   slam vocabulary --images DIR -o VOC          bag-of-words vocabulary
//   slam loops --images DIR --gt GT.bmp          visual loop detection
//
// Two binaries are built from this file. `slam-visual` (SLAM_VISUAL_COMMANDS)
// has every command, including those that read images (run, which also runs
// the stereo pipeline, and the place-recognition commands); `slam` has the
// rest and hands the image commands to slam-visual with the same arguments
// (apps/visual_forward.h) before parsing any flag, so that pose-graph and
// evaluation runs do not load OpenCV's image libraries.
//
// Every setting also has a YAML form (--config FILE); --dump_config prints
// the effective configuration.
//
// Flags belong to commands. Each entry of the command table (Commands()
// below) names
//   - flag_files: the source files whose DEFINE_* flags the command owns
//     (matched by file name, e.g. "eval_command.cc": every flag defined in
//     that file), and
//   - flags: single flags defined elsewhere that it also takes (the shared
//     ones of apps/common_flags.cc such as config, dump_config, report, plot,
//     gt, or e.g. "i"/"o" of optimize_command.cc).
// `slam <command> --help` prints exactly those flags, grouped by the file
// that defines them, with their defaults. A flag the command does not own is
// refused ("slam inertial: --align is not a flag of this command"), so no
// flag is silently ignored. Adding a command: write its Run function
// (apps/commands.h), define its flags in its own file, and add one table
// entry listing that file and the shared flags it reads.
#include <algorithm>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/commands.h"
#include "apps/process_heap.h"
#include "apps/safe_stderr.h"
#include "apps/visual_forward.h"
#include "datasets/atomic_file.h"
#ifdef SLAM_VISUAL_COMMANDS
#include "apps/visual/visual_commands.h"
#endif

namespace {

struct Command {
  std::function<int(const std::vector<std::string>&)> run;
  const char* summary;
  std::vector<std::string> flag_files;  // Owns every flag defined in these.
  std::vector<std::string> flags;       // And these, defined elsewhere.
};

// The image commands: run in-process by slam-visual; `slam` forwards them
// before they could be looked up here (IsVisualCommand), so its entries
// only serve the usage text.
#ifdef SLAM_VISUAL_COMMANDS
constexpr auto kRun = &slam::RunRunOrStereoCommand;
constexpr auto kVocabulary = &slam::RunVocabularyCommand;
constexpr auto kLoops = &slam::RunLoopsCommand;
#else
constexpr auto kRun = &slam::RunForwardedCommand;
constexpr auto kVocabulary = &slam::RunForwardedCommand;
constexpr auto kLoops = &slam::RunForwardedCommand;
#endif

const std::map<std::string, Command>& Commands() {
  static const auto* commands = new std::map<std::string, Command>{
      {"optimize",
       {slam::RunOptimizeCommand,
        "optimize a pose graph: slam optimize -i IN -o OUT [--init ...]",
        {"optimize_command.cc", "certificate_report.cc"},
        {"config", "dump_config", "report", "plot", "gt"}}},
      {"info",
       {slam::RunInfoCommand,
        "describe a graph file: slam info FILE",
        {"info_command.cc"},
        {"repair_information", "skip_unknown_tags"}}},
      {"eval",
       {slam::RunEvalCommand,
        "ATE/RPE of a trajectory: slam eval --ref GT --est EST [--plot DIR]",
        {"eval_command.cc"},
        {"config", "dump_config", "report", "plot"}}},
      {"run",
       {kRun,
        "2D laser SLAM on a CARMEN log or stereo visual odometry on a KITTI "
        "folder: slam run --config configs/aces.yaml|kitti_stereo.yaml",
        {"run_command.cc", "stereo_run_command.cc"},
        // gt and report: the stereo pipeline's.
        {"config", "dump_config", "gt", "report"}}},
      {"inertial",
       {slam::RunInertialCommand,
        "IMU + position fixes: slam inertial -i EUROC_DIR|GTSAM.csv -o DIR",
        {"inertial_command.cc"},
        {"i", "o", "config", "dump_config", "report", "plot", "gt"}}},
      {"simulate",
       {slam::RunSimulateCommand,
        "write a synthetic dataset with ground truth: slam simulate -o DIR",
        {"simulate_command.cc"},
        {"o", "config", "dump_config"}}},
      {"vocabulary",
       {kVocabulary,
        "train a bag-of-words vocabulary: slam vocabulary --images DIR "
        "[DIR...] -o VOC [--k 10 --levels 5]",
        {"vocabulary_command.cc"},
        {"o"}}},
      {"loops",
       {kLoops,
        "visual loop detection scored against a loop matrix: slam loops "
        "--images DIR --gt GT.bmp [--plot DIR] [--report FILE.json]",
        {"loops_command.cc"},
        {"images", "voc", "orb_features", "config", "dump_config", "gt", "plot",
         "report"}}},
  };
  return *commands;
}

void PrintUsage() {
  std::fprintf(stderr, "usage: slam <command> [flags] [args]\n\ncommands:\n");
  for (const auto& [name, command] : Commands()) {
    std::fprintf(stderr, "  %-10s %s\n", name.c_str(), command.summary);
  }
  std::fprintf(stderr, "\n'slam <command> --help' lists its flags.\n");
}

std::string FileName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// The file (of command.flag_files) that makes `flag` the command's, "" for
// one listed in command.flags, nullptr when the command does not own it.
const std::string* Owner(const Command& command,
                         const gflags::CommandLineFlagInfo& flag) {
  static const std::string kListed;
  const std::string file = FileName(flag.filename);
  for (const std::string& f : command.flag_files) {
    if (f == file) return &f;
  }
  if (std::find(command.flags.begin(), command.flags.end(), flag.name) !=
      command.flags.end()) {
    return &kListed;
  }
  return nullptr;
}

bool IsHelpArgument(const char* arg) {
  return std::strcmp(arg, "-h") == 0 || std::strncmp(arg, "--help", 6) == 0 ||
         std::strncmp(arg, "-help", 5) == 0;
}

// `slam <name> --help`: the command's flags, grouped by defining file.
void PrintCommandHelp(const std::string& name, const Command& command) {
  std::printf("slam %s: %s\n", name.c_str(), command.summary);
  std::vector<gflags::CommandLineFlagInfo> all;
  gflags::GetAllFlags(&all);
  std::vector<std::string> groups = command.flag_files;
  groups.push_back("");  // The listed shared flags last.
  for (const std::string& group : groups) {
    bool header = false;
    for (const auto& flag : all) {
      const std::string* owner = Owner(command, flag);
      if (owner == nullptr || *owner != group) continue;
      if (!header) {
        std::printf("\n%s:\n", group.empty()
                                   ? "shared flags"
                                   : ("flags of slam " + name).c_str());
        header = true;
      }
      std::string text = flag.description;
      const std::string prefix = name + ": ";  // "eval: ..." in eval's help.
      if (text.rfind(prefix, 0) == 0) text = text.substr(prefix.size());
      std::string value = flag.default_value;
      if (flag.type == "string") value = "\"" + value + "\"";
      if (flag.type == "double") {  // Shortest form: 0.1, not 0.1000...01.
        char buf[32];
        const double v = std::strtod(value.c_str(), nullptr);
        value.assign(buf, std::to_chars(buf, buf + sizeof(buf), v).ptr);
      }
      std::printf("  --%s (%s, default %s)\n      %s\n", flag.name.c_str(),
                  flag.type.c_str(), value.c_str(), text.c_str());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Output piped into a reader that stops early (`| head -1`): the writes
  // fail with EPIPE and the command ends with an error (checked below)
  // instead of being killed by SIGPIPE half-way.
  std::signal(SIGPIPE, SIG_IGN);
  slam::ConfigureProcessHeap();  // See apps/process_heap.h.
  slam::FilterControlBytesOnStderr();
  slam::FilterControlBytesOnStderr();
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 ||
      std::strcmp(argv[1], "-h") == 0 || std::strcmp(argv[1], "help") == 0) {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  const std::string name = argv[1];
#ifndef SLAM_VISUAL_COMMANDS
  if (slam::IsVisualCommand(name))
    return slam::ForwardToVisualBinary(argc, argv);
#endif
  auto it = Commands().find(name);
  if (it == Commands().end()) {
    std::fprintf(stderr, "slam: unknown command '%s'\n\n", name.c_str());
    PrintUsage();
    return 2;
  }
  const Command& command = it->second;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--") == 0) break;
    if (IsHelpArgument(argv[i])) {
      PrintCommandHelp(name, command);
      return 0;
    }
  }
  // Drop the command name and let gflags parse the rest.
  std::vector<char*> rest = {argv[0]};
  for (int i = 2; i < argc; ++i) rest.push_back(argv[i]);
  int rest_argc = static_cast<int>(rest.size());
  char** rest_argv = rest.data();
  gflags::SetUsageMessage("slam " + name + ": " + command.summary);
  gflags::ParseCommandLineFlags(&rest_argc, &rest_argv, true);
  // Flags given but not the command's: refused, never silently ignored.
  std::vector<gflags::CommandLineFlagInfo> all;
  gflags::GetAllFlags(&all);
  for (const auto& flag : all) {
    if (!flag.is_default && Owner(command, flag) == nullptr) {
      std::fprintf(stderr,
                   "slam %s: --%s is not a flag of this command ('slam %s "
                   "--help' lists its flags)\n",
                   name.c_str(), flag.name.c_str(), name.c_str());
      return 2;
    }
  }
  std::vector<std::string> args(rest_argv + 1, rest_argv + rest_argc);
  // The outputs of a command are published only when it succeeds: a failed
  // command leaves none of them behind (datasets/atomic_file.h).
  slam::OutputStage outputs;
  int code = command.run(args);
  std::string error;
  std::cout.flush();
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
    // The report on stdout is incomplete: the command failed.
    std::fprintf(stderr,
                 "slam %s: cannot write to standard output (a closed pipe or "
                 "a full disk)\n",
                 name.c_str());
    if (code == 0) code = 1;
  }
  if (code == 0 && !outputs.Commit(&error)) {
    std::fprintf(stderr, "slam %s: %s\n", name.c_str(), error.c_str());
    return 1;
  }
  return code;
}
