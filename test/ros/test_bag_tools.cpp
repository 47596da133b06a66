// The bag writers (risas_dataset_to_bag, risas_tum_to_bag) and what they
// share, BagWriter: a complete bag, or one line of error, never an abort.
#include "../src/ros/bag_frames.hpp"
#include "tool_run.hpp"

#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <string>

namespace risas_ros {
namespace {

namespace fs = std::filesystem;

using risas::test::ToolRun;

ToolRun run(const std::string& command_line, const std::string& shell = "") {
  return risas::test::runTool(command_line, shell);
}

class BagTools : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir);
    const ToolRun r = run("risas_render_synthetic --out " + (dir / "sequence").string() + " --frames 2");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string full(const std::string& name) const { return risas::test::fullDiskAt(dir / name); }
  const fs::path dir = fs::temp_directory_path() / ("risas_bag_tools_" + std::to_string(::getpid()));
};

TEST_F(BagTools, WriteEveryFrameOrFailInOneLine) {
  const std::string written = (dir / "written.bag").string();
  const ToolRun ok = run("risas_dataset_to_bag --data " + (dir / "sequence").string() + " --out " + written);
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  rosbag::Bag bag(written, rosbag::bagmode::Read);
  rosbag::View view(bag);
  EXPECT_EQ(view.size(), 6u);  // two frames, three topics each
  const std::vector<const rosbag::ConnectionInfo*> topics = view.getConnections();
  EXPECT_EQ(topics.size(), 3u);

  // A bag that cannot even take its header (/dev/full: every write fails).
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const ToolRun failed =
      run("risas_dataset_to_bag --data " + (dir / "sequence").string() + " --out " + full("full.bag"));
  EXPECT_EQ(failed.exit_code, 1) << failed.output;  // an abort was 134
  EXPECT_EQ(failed.output.rfind("risas_dataset_to_bag: error: cannot write bag " + (dir / "full.bag").string() + ": ", 0),
            0u)
      << failed.output;
  EXPECT_EQ(std::count(failed.output.begin(), failed.output.end(), '\n'), 1) << failed.output;
}

// --frame-id names every message's frame, and is a tf frame id or wrong
// usage, before any work.
TEST_F(BagTools, TheFrameIdIsTakenWhenTfWouldTakeIt) {
  const std::string written = (dir / "framed.bag").string();
  const ToolRun ok =
      run("risas_dataset_to_bag --data " + (dir / "sequence").string() + " --out " + written + " --frame-id cam2_optical");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  rosbag::Bag bag(written, rosbag::bagmode::Read);
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (const auto image = m.instantiate<sensor_msgs::Image>()) {
      EXPECT_EQ(image->header.frame_id, "cam2_optical");
    }
    if (const auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
      EXPECT_EQ(info->header.frame_id, "cam2_optical");
    }
  }
  for (const std::string& tool : {"risas_dataset_to_bag --data " + (dir / "sequence").string(),
                                 "risas_tum_to_bag --tum " + (dir / "sequence").string() + " --fx 500 --fy 500 --cx 320 --cy 240"}) {
    const ToolRun slash = run(tool + " --out " + (dir / "slash.bag").string() + " --frame-id /cam2_optical");
    EXPECT_EQ(slash.exit_code, 2) << slash.output;
    EXPECT_NE(slash.output.find("--frame-id must be a tf frame id: not empty, no leading '/' (got '/cam2_optical')"),
              std::string::npos)
        << slash.output;
    EXPECT_FALSE(fs::exists(dir / "slash.bag"));
  }
}

// While it lives, files this process writes stop at `bytes`: a write
// beyond fails with EFBIG (SIGXFSZ ignored), as a disk filling up part-way
// through a file fails. The limit and the signal's action are restored.
struct FileSizeLimit {
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved);
    rlimit limited = saved;
    limited.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limited);
    previous_action = std::signal(SIGXFSZ, SIG_IGN);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, previous_action);
  }
  rlimit saved{};
  void (*previous_action)(int) = SIG_DFL;
};

TEST_F(BagTools, AWriterThatFailsPartWayReportsItAndIsDestroyedWithoutAnAbort) {
  sensor_msgs::Image image;
  image.data.resize(1 << 20);  // beyond rosbag's chunk: written to the file at once
  const std::string path = (dir / "cut.bag").string();
  std::string said;
  {
    const FileSizeLimit limit(256 * 1024);
    {
      BagWriter bag(path);  // its header fits
      try {
        bag.write("image", ros::Time(1.0), image);
        bag.close();
      } catch (const risas::InputError& e) {
        said = e.what();
      }
      // A second use says the bag was given up; its destructor, after the
      // failure, does not close it again (rosbag's would throw, and abort).
      EXPECT_THROW(bag.close(), risas::InputError);
    }
  }
  EXPECT_EQ(said.rfind("cannot write bag " + path + ": ", 0), 0u) << said;
  EXPECT_LE(fs::file_size(path), 256u * 1024u);
}

TEST_F(BagTools, AFileThatFailsPartWayStopsTheToolInOneLine) {
  // The shell's limit (in 512-byte blocks) with SIGXFSZ ignored, for the
  // tool alone: its frames' first megabyte fails to be written.
  const std::string path = (dir / "cut.bag").string();
  const ToolRun r = run("risas_dataset_to_bag --data " + (dir / "sequence").string() + " --out " + path,
                        "trap '' XFSZ; ulimit -f 512; exec ");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("risas_dataset_to_bag: error: cannot write bag " + path + ": ", 0), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

}  // namespace
}  // namespace risas_ros
