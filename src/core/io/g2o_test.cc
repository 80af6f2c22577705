#include "rrr/io/g2o.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
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

// Every pose, edge, measurement and information matrix of `h` equals `g`'s
// (to rounding: the writer keeps full precision, the reader normalizes
// quaternions again).
template <class Pose>
void ExpectSameGraph(const PoseGraph<Pose>& g, const PoseGraph<Pose>& h) {
  EXPECT_EQ(h.ids(), g.ids());
  ASSERT_EQ(h.num_poses(), g.num_poses());
  for (int k = 0; k < g.num_poses(); ++k) {
    EXPECT_LT((h.estimates()[k].Log() - g.estimates()[k].Log()).norm(), 1e-12)
        << "pose " << k;
  }
  EXPECT_EQ(h.fixed(), g.fixed());
  const auto same_edges = [](const std::vector<Constraint<Pose>>& a,
                             const std::vector<Constraint<Pose>>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
      EXPECT_EQ(a[k].from, b[k].from) << "edge " << k;
      EXPECT_EQ(a[k].to, b[k].to) << "edge " << k;
      EXPECT_LT((a[k].measurement.Log() - b[k].measurement.Log()).norm(), 1e-12)
          << "edge " << k;
      EXPECT_EQ(a[k].information, b[k].information) << "edge " << k;
    }
  };
  same_edges(h.odometry(), g.odometry());
  same_edges(h.loops(), g.loops());
}

TEST(G2o, WritesEachNumberInItsShortestExactForm) {
  PoseGraph2 g;
  g.AddPose(0, Pose2(0.1, 1.0 / 3.0, -2.5e-300));
  g.AddPose(1, Pose2(-7e17, 1234.5, 3.0));
  Constraint<Pose2> e;
  e.from = 0;
  e.to = 1;
  e.measurement = Pose2(0.1, 0.2, 0.3);
  e.information = Eigen::Matrix3d::Identity() * 1e-5;
  g.AddEdge(e);
  std::ostringstream out;
  WriteG2o(g, g.estimates(), {}, out);
  // The shortest text of each value, not 17 digits ("0.10000000000000001").
  EXPECT_NE(out.str().find("VERTEX_SE2 0 0.1 0.3333333333333333 -2.5e-300\n"),
            std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("EDGE_SE2 0 1 0.1 0.2 0.3 1e-05 0 0 1e-05 0 1e-05"),
            std::string::npos)
      << out.str();
  // Each reads back as the same double, bit for bit.
  const auto h = std::get<PoseGraph2>(Parse(out.str()).graph);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(h.estimates()[k].x(), g.estimates()[k].x()) << k;
    EXPECT_EQ(h.estimates()[k].y(), g.estimates()[k].y()) << k;
    EXPECT_EQ(h.estimates()[k].theta(), g.estimates()[k].theta()) << k;
  }
  EXPECT_EQ(h.odometry()[0].information, e.information);
}

TEST(G2o, WriteThenReadGivesTheSameGraph) {
  // Distinct values in every field, so that a swapped or dropped field shows.
  const auto g2 =
      std::get<PoseGraph2>(Parse("VERTEX_SE2 0 0.125 -0.25 0.5\n"
                                 "VERTEX_SE2 1 1.1 0.3 1.2\n"
                                 "VERTEX_SE2 2 0.9 1.7 -2.9\n"
                                 "FIX 1\n"
                                 "EDGE_SE2 0 1 1.01 0.02 1.03 11 1 2 12 3 13\n"
                                 "EDGE_SE2 1 2 0.97 -0.05 1.52 21 4 5 22 6 23\n"
                                 "EDGE_SE2 2 0 1.3 0.9 1.61 31 7 8 32 9 33\n")
                               .graph);
  std::ostringstream out2;
  WriteG2o(g2, g2.estimates(), AllLoops(g2), out2);
  ExpectSameGraph(g2, std::get<PoseGraph2>(Parse(out2.str()).graph));

  // The upper triangle row by row: a dominant diagonal, distinct entries.
  std::string info;
  for (int r = 0, k = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c, ++k) {
      info += " " + std::to_string(r == c ? 40.0 + k : 0.5 + 0.01 * k);
    }
  }
  const auto g3 = std::get<PoseGraph3>(
      Parse("VERTEX_SE3:QUAT 0 0.1 0.2 0.3 0 0 0 1\n"
            "VERTEX_SE3:QUAT 1 1.1 -0.2 0.35 0.1 0.2 0.3 0.927\n"
            "VERTEX_SE3:QUAT 2 2.1 0.4 -0.3 -0.2 0.1 0.05 0.97\n"
            "EDGE_SE3:QUAT 0 1 1 0.1 0.2 0.05 0.1 0.15 0.98" +
            info +
            "\n"
            "EDGE_SE3:QUAT 1 2 0.9 -0.1 0.3 0.1 -0.05 0.2 0.97" +
            info +
            "\n"
            "EDGE_SE3:QUAT 0 2 2 0.3 -0.1 -0.1 0.2 0.1 0.96" +
            info + "\n")
          .graph);
  std::ostringstream out3;
  WriteG2o(g3, g3.estimates(), AllLoops(g3), out3);
  ExpectSameGraph(g3, std::get<PoseGraph3>(Parse(out3.str()).graph));
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
              HasSubstr("test.g2o: no vertices and no edges"));
  EXPECT_THAT(ErrorOf("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"),
              HasSubstr("test.g2o: no vertices"));
}

G2oFile ParseLeniently(const std::string& text) {
  std::istringstream in(text);
  return ParseG2o(in, "test.g2o");
}

TEST(G2o, AFileOfEdgesOnlyTakesItsPosesFromItsOdometry) {
  const G2oFile file = ParseLeniently(
      "EDGE_SE2 0 1 1 0 1.5707963267948966 1 0 0 1 0 1\n"
      "EDGE_SE2 1 2 2 0 0 1 0 0 1 0 1\n"
      "EDGE_SE2 2 0 0 3 1.5707963267948966 1 0 0 1 0 1\n");
  EXPECT_TRUE(file.poses_from_odometry);
  const auto& g = std::get<PoseGraph2>(file.graph);
  EXPECT_EQ(g.ids(), (std::vector<PoseId>{0, 1, 2}));
  EXPECT_EQ(g.odometry().size(), 2u);
  EXPECT_EQ(g.loops().size(), 1u);
  // Pose 1 one metre ahead facing +y, pose 2 two metres further along +y.
  EXPECT_NEAR(g.estimates()[1].x(), 1.0, 1e-12);
  EXPECT_NEAR(g.estimates()[2].x(), 1.0, 1e-12);
  EXPECT_NEAR(g.estimates()[2].y(), 2.0, 1e-12);
  EXPECT_FALSE(Parse(kSquare2D).poses_from_odometry);
}

TEST(G2o, AnInformationMatrixThatIsNotPositiveDefiniteIsRepairedAndListed) {
  // Eigenvalues of the xy block: 3 ± 5, i.e. 8 and −2.
  const std::string text =
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
      "EDGE_SE2 0 1 1 0 0 3 5 0 3 0 4\n";
  const G2oFile file = ParseLeniently(text);
  ASSERT_EQ(file.repaired_information.size(), 1u);
  const RepairedInformation& r = file.repaired_information[0];
  EXPECT_EQ(r.line, 3);
  EXPECT_EQ(r.from, 0);
  EXPECT_EQ(r.to, 1);
  EXPECT_NEAR(r.smallest_eigenvalue, -2.0, 1e-12);
  const auto& info = std::get<PoseGraph2>(file.graph).odometry()[0].information;
  EXPECT_EQ(info, info.transpose());
  const Eigen::Vector3d eigen =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(info).eigenvalues();
  // The positive eigenvalues stay; the negative one is raised to the floor.
  EXPECT_NEAR(eigen(0), kLeastInformationRatio * 8.0, 1e-12);
  EXPECT_NEAR(eigen(1), 4.0, 1e-12);
  EXPECT_NEAR(eigen(2), 8.0, 1e-12);
  EXPECT_THAT(ErrorOf(text),
              HasSubstr("test.g2o:3: information matrix of edge 0 -> 1 is not "
                        "positive definite"));
  // Nothing to keep: refused even leniently.
  try {
    ParseLeniently(
        "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
        "EDGE_SE2 0 1 1 0 0 -1 0 0 -1 0 0\n");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("test.g2o:3: information matrix of edge "
                                    "0 -> 1 has no positive eigenvalue"));
  }
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
