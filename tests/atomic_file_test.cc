// The atomic writer (datasets/atomic_file.h): what it replaces and what it
// never replaces, temporaries on signals and after SIGKILL, output stages.
#include "datasets/atomic_file.h"

#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <thread>

#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

namespace fs = std::filesystem;
using ::slam::testing::Contains;
using ::slam::testing::ReadText;
using ::slam::testing::TempDir;
using ::slam::testing::WriteText;

// Files in `dir` whose name contains ".slam-tmp-".
int CountTemps(const std::string& dir) {
  int n = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    n += Contains(entry.path().filename().string(), ".slam-tmp-");
  }
  return n;
}

TEST(AtomicFileTest, ReplacesARegularFileAndKeepsItsMode) {
  const std::string dir = TempDir();
  const std::string path = dir + "/out.txt";
  WriteText(path, "old");
  ASSERT_EQ(::chmod(path.c_str(), 0640), 0);
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, "new", &error)) << error;
  EXPECT_EQ(ReadText(path), "new");
  struct stat st;
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0640u);
  EXPECT_EQ(CountTemps(dir), 0);
}

TEST(AtomicFileTest, FollowsSymlinksAndReplacesTheirTarget) {
  const std::string dir = TempDir();
  const std::string target = dir + "/target.txt";
  WriteText(target, "old");
  fs::create_symlink("target.txt", dir + "/link1");
  fs::create_symlink(dir + "/link1", dir + "/link2");  // A chain.
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(dir + "/link2", "new", &error)) << error;
  EXPECT_TRUE(fs::is_symlink(dir + "/link2"));
  EXPECT_TRUE(fs::is_symlink(dir + "/link1"));
  EXPECT_EQ(ReadText(target), "new");
  // A dangling link: its target is created.
  fs::create_symlink("missing.txt", dir + "/dangling");
  ASSERT_TRUE(WriteFileAtomically(dir + "/dangling", "made", &error)) << error;
  EXPECT_TRUE(fs::is_symlink(dir + "/dangling"));
  EXPECT_EQ(ReadText(dir + "/missing.txt"), "made");
  // A loop is an error.
  fs::create_symlink("loop_b", dir + "/loop_a");
  fs::create_symlink("loop_a", dir + "/loop_b");
  EXPECT_FALSE(WriteFileAtomically(dir + "/loop_a", "x", &error));
  EXPECT_TRUE(Contains(error, "loop_a")) << error;
  EXPECT_EQ(CountTemps(dir), 0);
}

TEST(AtomicFileTest, WritesDevicesAndFifosDirectlyNeverReplacingThem) {
  std::string error;
  ASSERT_TRUE(WriteFileAtomically("/dev/null", "discarded", &error)) << error;
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // /dev/full: the write fails and the device stays.
  EXPECT_FALSE(WriteFileAtomically("/dev/full", "x", &error));
  EXPECT_TRUE(Contains(error, "/dev/full: cannot write")) << error;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));

  const std::string dir = TempDir();
  const std::string fifo = dir + "/fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = ReadText(fifo); });
  EXPECT_TRUE(WriteFileAtomically(fifo, "through the pipe", &error)) << error;
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(CountTemps(dir), 0);

  // A directory is never replaced.
  fs::create_directories(dir + "/sub");
  EXPECT_FALSE(WriteFileAtomically(dir + "/sub", "x", &error));
  EXPECT_TRUE(Contains(error, "is a directory")) << error;
  EXPECT_TRUE(fs::is_directory(dir + "/sub"));
}

TEST(AtomicFileTest, LeftoverOfAKilledProcessIsRemovedByTheNextWrite) {
  const std::string dir = TempDir();
  // A process that is gone: its pid names the leftover.
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  const std::string leftover =
      dir + "/out.txt.slam-tmp-" + std::to_string(child) + "-AbCdEf";
  WriteText(leftover, "partial");
  // The leftover of a live process (ours) is left alone.
  const std::string live =
      dir + "/out.txt.slam-tmp-" + std::to_string(::getppid()) + "-AbCdEf";
  WriteText(live, "in progress");
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(dir + "/out.txt", "ok", &error)) << error;
  EXPECT_FALSE(fs::exists(leftover));
  EXPECT_TRUE(fs::exists(live));
}

// A signal while outputs are being written removes the temporaries and the
// process still dies of the signal.
TEST(AtomicFileTest, SignalsRemoveTemporaries) {
  for (int sig : {SIGTERM, SIGINT}) {
    const std::string dir = TempDir();
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      OutputStage stage;  // Keeps the temporary alive until the signal.
      std::string error;
      if (!WriteFileAtomically(dir + "/out.txt", "data", &error)) ::_exit(3);
      if (CountTemps(dir) != 1) ::_exit(4);
      ::raise(sig);
      ::_exit(5);  // Not reached.
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_EQ(CountTemps(dir), 0);
    EXPECT_FALSE(fs::exists(dir + "/out.txt"));
  }
}

TEST(AtomicFileTest, OutputStagePublishesOnlyOnCommit) {
  const std::string dir = TempDir();
  WriteText(dir + "/a.txt", "old a");
  std::string error;
  {
    OutputStage stage;
    ASSERT_TRUE(WriteFileAtomically(dir + "/a.txt", "new a", &error));
    ASSERT_TRUE(WriteFileAtomically(dir + "/b.txt", "new b", &error));
    EXPECT_EQ(ReadText(dir + "/a.txt"), "old a");
    EXPECT_FALSE(fs::exists(dir + "/b.txt"));
    // Destroyed without Commit: a failed command.
  }
  EXPECT_EQ(ReadText(dir + "/a.txt"), "old a");
  EXPECT_FALSE(fs::exists(dir + "/b.txt"));
  EXPECT_EQ(CountTemps(dir), 0);
  {
    OutputStage stage;
    ASSERT_TRUE(WriteFileAtomically(dir + "/b.txt", "first", &error));
    ASSERT_TRUE(WriteFileAtomically(dir + "/b.txt", "second", &error));
    ASSERT_TRUE(stage.Commit(&error)) << error;
  }
  EXPECT_EQ(ReadText(dir + "/b.txt"), "second");
  EXPECT_EQ(CountTemps(dir), 0);
  EXPECT_EQ(OutputStage::Current(), nullptr);
}

}  // namespace
}  // namespace slam
