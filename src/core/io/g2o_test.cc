#include "rrr/io/g2o.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <sstream>

#include "rrr/io/input_error.h"

namespace rrr {
namespace {

using ::testing::HasSubstr;

G2oFile Parse(const std::string& text) {
  std::istringstream in(text);
  return ParseG2o(in, "test.g2o", /*strict=*/true);
}

// The InputError message of parsing `text`, or "" if it parses.
std::string ErrorOf(const std::string& text) {
  try {
    Parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* const kSquare2D =
    "VERTEX_SE2 0 0 0 0\n"
    "VERTEX_SE2 1 1 0 1.5707963\n"
    "VERTEX_SE2 2 1 1 3.1415926\n"
    "EDGE_SE2 0 1 1 0 1.5707963 100 0 0 100 0 1000\n"
    "EDGE_SE2 1 2 1 0 1.5707963 100 0 0 100 0 1000\n"
    "EDGE_SE2 2 0 1 1 1.5707963 10 0 0 10 0 100\n";

TEST(G2o, ReadsVerticesOdometryAndLoops2D) {
  const G2oFile file = Parse(kSquare2D);
  const auto& g = std::get<PoseGraph2>(file.graph);
  EXPECT_EQ(g.num_poses(), 3);
  EXPECT_EQ(g.odometry().size(), 2u);
  ASSERT_EQ(g.loops().size(), 1u);
  EXPECT_EQ(g.ids()[g.loops()[0].from], 2);
  EXPECT_EQ(g.ids()[g.loops()[0].to], 0);
  EXPECT_DOUBLE_EQ(g.loops()[0].information(2, 2), 100);
  EXPECT_DOUBLE_EQ(g.estimates()[2].y(), 1);
  EXPECT_TRUE(file.skipped_tags.empty());
}

TEST(G2o, ReadsSE3WithQuaternionOrderXyzw) {
  std::string info = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 2 0 0 2 0 2";
  const G2oFile file = Parse(
      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
      "VERTEX_SE3:QUAT 1 1 2 3 0 0 0.7071068 0.7071068\n"
      "EDGE_SE3:QUAT 0 1 1 2 3 0 0 0.7071068 0.7071068" +
      info + "\n");
  const auto& g = std::get<PoseGraph3>(file.graph);
  ASSERT_EQ(g.odometry().size(), 1u);
  EXPECT_NEAR(g.estimates()[1].angle(), M_PI / 2, 1e-6);
  EXPECT_NEAR(g.estimates()[1].translation().z(), 3, 1e-12);
  EXPECT_DOUBLE_EQ(g.odometry()[0].information(5, 5), 2);
  EXPECT_DOUBLE_EQ(g.odometry()[0].information(0, 0), 1);
}

TEST(G2o, AQuaternionWithHugeComponentsIsADirection) {
  // Found by fuzzing: normalizing (0, 0, 1e205, 0) overflowed to a
  // quaternion of NaNs.
  std::string info = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 2 0 0 2 0 2";
  const G2oFile file = Parse(
      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
      "VERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 1e205 0" +
      info + "\n");
  const auto& e = std::get<PoseGraph3>(file.graph).odometry()[0];
  EXPECT_TRUE(e.measurement.Log().allFinite());
  EXPECT_NEAR(e.measurement.angle(), M_PI, 1e-9);
}

TEST(G2o, WriteThenReadGivesTheSameGraph) {
  const auto g = std::get<PoseGraph2>(Parse(kSquare2D).graph);
  std::ostringstream out;
  WriteG2o(g, g.estimates(), AllLoops(g), out);
  const auto h = std::get<PoseGraph2>(Parse(out.str()).graph);
  ASSERT_EQ(h.num_poses(), g.num_poses());
  ASSERT_EQ(h.loops().size(), 1u);
  for (int k = 0; k < g.num_poses(); ++k) {
    EXPECT_DOUBLE_EQ(h.estimates()[k].theta(), g.estimates()[k].theta());
  }
  EXPECT_EQ(h.loops()[0].information, g.loops()[0].information);
}

TEST(G2o, WritesOnlyTheChosenLoops) {
  const auto g = std::get<PoseGraph2>(Parse(kSquare2D).graph);
  std::ostringstream out;
  WriteG2o(g, g.estimates(), {}, out);
  EXPECT_TRUE(std::get<PoseGraph2>(Parse(out.str()).graph).loops().empty());
}

TEST(G2o, CountsUnknownTags) {
  const G2oFile file = Parse(std::string(kSquare2D) +
                             "VERTEX_XY 7 1 2\nVERTEX_XY 8 1 2\nPARAMS 1\n");
  EXPECT_EQ(file.skipped_tags.at("VERTEX_XY"), 2);
  EXPECT_EQ(DescribeSkipped(file.skipped_tags), "PARAMS x1, VERTEX_XY x2");
}

TEST(G2o, ReadsFix) {
  const auto g =
      std::get<PoseGraph2>(Parse(std::string(kSquare2D) + "FIX 1\n").graph);
  EXPECT_EQ(g.fixed(), std::vector<int>{1});
}

TEST(G2o, DegenerateCandidatesAreSkippedAndListed) {
  std::istringstream in(std::string(kSquare2D) +
                        "EDGE_SE2 2 2 0 0 0 1 0 0 1 0 1\n"    // self loop
                        "EDGE_SE2 0 9 0 0 0 1 0 0 1 0 1\n"    // unknown pose
                        "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"    // odometry again
                        "EDGE_SE2 0 2 2 0 0 1 0 0 1 0 1\n"    // a candidate
                        "EDGE_SE2 0 2 2 0 0 1 0 0 1 0 1\n"    // the same again
                        "EDGE_SE2 0 2 2.1 0 0 1 0 0 1 0 1\n"  // same pair, kept
                        "EDGE_SE2 1 0 -1 0 0 1 0 0 1 0 1\n");  // consecutive
  const G2oFile file = ParseG2o(in, "test.g2o");
  const auto& g = std::get<PoseGraph2>(file.graph);
  const G2oFile square = Parse(kSquare2D);
  const auto& plain = std::get<PoseGraph2>(square.graph);
  EXPECT_EQ(g.odometry().size(), plain.odometry().size());
  EXPECT_EQ(g.loops().size(), plain.loops().size() + 2);
  std::vector<std::pair<int, std::string>> skipped;
  for (const auto& s : file.skipped_candidates) {
    skipped.emplace_back(s.line, ToString(s.defect));
  }
  const int first = static_cast<int>(std::count(
                        kSquare2D, kSquare2D + std::strlen(kSquare2D), '\n')) +
                    1;
  EXPECT_EQ(skipped, (std::vector<std::pair<int, std::string>>{
                         {first, "self_loop"},
                         {first + 1, "unknown_pose"},
                         {first + 2, "consecutive_poses"},
                         {first + 4, "duplicate"},
                         {first + 6, "consecutive_poses"}}));
}

TEST(G2o, ErrorsNameFileLineAndProblem) {
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0 0 0\n"),
              HasSubstr("test.g2o:1: VERTEX_SE2 needs 5 fields, found 4"));
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 x 0 0\n"),
              HasSubstr("test.g2o:2: field 2 'x' is not a number"));
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0 0 nan 0\n"),
              HasSubstr("test.g2o:1: field 3 'nan' is not finite"));
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0.5 0 0 0\n"),
              HasSubstr("test.g2o:1: field 1 '0.5' is not an integer id"));
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 0 0 0 0\n"),
              HasSubstr("test.g2o:2: vertex 0 is defined twice"));
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 5 1 0 0 1 0 0 1 0 1\n"),
              HasSubstr("test.g2o:2: edge refers to unknown vertex 5"));
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\n"
                      "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n"),
              HasSubstr("test.g2o:3: information matrix of edge 0 -> 1 is not "
                        "positive definite"));
  EXPECT_THAT(ErrorOf("VERTEX_SE2 0 0 0 0\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n"),
              HasSubstr("test.g2o:2: mixes 2D and 3D elements"));
  EXPECT_THAT(ErrorOf("VERTEX_SE3:QUAT 1 0 0 0 0 0 0 0\n"),
              HasSubstr("test.g2o:1: the quaternion has zero norm"));
  EXPECT_THAT(ErrorOf("FIX 3\nVERTEX_SE2 0 0 0 0\n"),
              HasSubstr("test.g2o:1: FIX refers to unknown vertex 3"));
  EXPECT_THAT(ErrorOf("# only a comment\n"),
              HasSubstr("test.g2o: no vertices"));
}

TEST(G2o, MissingFileIsAnError) {
  try {
    ReadG2o("/nonexistent/graph.g2o");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/graph.g2o: cannot open"));
  }
}

}  // namespace
}  // namespace rrr
