// The ROS layer's fuzz driver (test/fuzz/fuzz_ros_messages.cpp) for
// RISAS_ROS_FUZZ_SECONDS: a broken invariant, an undocumented exception or
// (in a sanitizer build) a sanitizer report ends it with a non-zero exit.
#include "tool_run.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

TEST(FuzzLoop, RosMessageChecksHoldTheirInvariants) {
  const risas::test::ToolRun run =
      risas::test::runTool("risas_ros_fuzz_loop --seconds " + std::to_string(RISAS_ROS_FUZZ_SECONDS) + " --seed 1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("no invariant broken"), std::string::npos) << run.output;
}

}  // namespace
