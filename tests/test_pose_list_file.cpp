// Pose-list files (io/pose_list_file.hpp): the wanted targets of `robcal compensate` and the
// task poses of `robcal plan --task-poses`.

#include "robcal/io/pose_list_file.hpp"

#include <gtest/gtest.h>

#include "robcal/core/error.hpp"

namespace robcal {
namespace {

TEST(PoseListFile, ReadsRowsAndNamesBadCells) {
  const std::string good =
      "# wanted poses\nname,x,y,z,qw,qx,qy,qz,config\n"
      "a,100,200,300,1,0,0,0,front-up-noflip\nb,1,2,3,0,1,0,0,5\nc,1,2,3,0,0,1,0,\n";
  const auto rows = parse_pose_list(good, "t.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].line, 3);
  EXPECT_EQ(rows[0].config->label(), "front-up-noflip");
  EXPECT_EQ(rows[1].config->label(), "back-up-flip");  // index 5 = back 4 + flip 1
  EXPECT_FALSE(rows[2].config.has_value());
  EXPECT_NEAR(rows[1].world_T_tcp.R(1, 1), -1.0, 1e-15);  // q = (0,1,0,0): half turn about x

  const auto error = [](const std::string& text) {
    try {
      parse_pose_list(text, "t.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("name,x,y,z,qw,qx,qy,qz\na,1,2,oops,1,0,0,0\n"),
            "t.csv:2:7 (z): expected a number, found 'oops'");
  EXPECT_EQ(error("name,x,y,z,qw,qx,qy,qz,config\na,1,2,3,1,0,0,0,sideways\n"),
            "t.csv:2:17 (config): expected a configuration such as front-up-noflip or its index "
            "0..7, found 'sideways'");
  EXPECT_NE(error("name,x,y,z,qw,qx,qy,qz\na,1,2,3,2,0,0,0\n").find("t.csv:2:9 (qw..qz)"),
            std::string::npos);
  EXPECT_NE(error("name,x,y,q\n").find("t.csv:1:10: expected the header"), std::string::npos);
  EXPECT_NE(error("name,x,y,z,qw,qx,qy,qz\n").find("no poses"), std::string::npos);
}

}  // namespace
}  // namespace robcal
