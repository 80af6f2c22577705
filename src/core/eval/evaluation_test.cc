// Precision/recall, ATE and the ground-truth readers.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>

#include "rrr/eval/ground_truth.h"
#include "rrr/eval/loop_scores.h"
#include "rrr/eval/trajectory_error.h"
#include "rrr/io/input_error.h"

namespace rrr {
namespace {

using ::testing::HasSubstr;

// A temporary file holding `text`, removed at the end of the test.
class TempFile {
 public:
  explicit TempFile(const std::string& text)
      : path_(::testing::TempDir() + "rrr_eval_" +
              std::to_string(reinterpret_cast<std::uintptr_t>(this))) {
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

TEST(LoopScores, CountsPrecisionAndRecall) {
  const LoopScores s = ScoreLoops({true, true, false, false, true},
                                  {true, false, true, false, true});
  EXPECT_EQ(s.accepted, 3);
  EXPECT_EQ(s.correct_accepted, 2);
  EXPECT_EQ(s.correct_candidates, 3);
  EXPECT_DOUBLE_EQ(s.precision(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.recall(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(ScoreLoops({false}, {true}).precision(), 1.0);
  EXPECT_THROW(ScoreLoops({true}, {}), std::invalid_argument);
}

TEST(AbsoluteTrajectoryError, IgnoresARigidMotionButNotNoise) {
  Eigen::MatrixXd ref(2, 5);
  ref << 0, 1, 2, 3, 4, 0, 0, 1, 1, 3;
  const Eigen::Rotation2Dd r(0.7);
  const Eigen::MatrixXd moved =
      (r.toRotationMatrix() * ref).colwise() + Eigen::Vector2d(5, -2);
  EXPECT_NEAR(AbsoluteTrajectoryError(moved, ref), 0.0, 1e-12);
  Eigen::MatrixXd noisy = ref;
  noisy(0, 0) += 0.5;
  EXPECT_GT(AbsoluteTrajectoryError(noisy, ref), 0.1);
  EXPECT_THROW(AbsoluteTrajectoryError(ref.leftCols(2), ref.leftCols(2)),
               std::invalid_argument);
}

TEST(AssociateByTime, TakesTheNearestWithinTolerance) {
  const auto m =
      AssociateByTime({0.0, 1.04, 2.5, 10.0}, {0.1, 1.0, 1.1, 3.0}, 0.25);
  EXPECT_EQ(m, (std::vector<int>{0, 1, -1, -1}));
}

TEST(JudgeLoop, AppliesTopologicalAndMetricRules) {
  const Pose2 a(0, 0, 0), b(10, 0, 0);
  const LoopLabel exact = JudgeLoop(a.between(b), a, b);
  EXPECT_TRUE(exact.topological && exact.metric);
  const LoopLabel off = JudgeLoop(a.between(b) * Pose2(2, 0, 0), a, b);
  EXPECT_TRUE(off.topological);
  EXPECT_FALSE(off.metric);
  EXPECT_FALSE(JudgeLoop(a.between(b) * Pose2(6, 0, 0), a, b).topological);
  EXPECT_FALSE(JudgeLoop(a.between(b) * Pose2(0, 0, 1.0), a, b).topological);
}

TEST(GroundTruthFiles, ReadLabelsOfOneLevel) {
  const TempFile f(
      "# level i j label terr rerr gtdist grey maxdt\n"
      "0.150 751 655 1 0.2 1.0 3.7 0 0.1\n"
      "0.150 900 100 0 2.1 3.0 3.7 1 0.1\n"
      "0.150 950 120 0 9.1 3.0 3.7 0 0.1\n"
      "0.175 751 655 0 9.9 1.0 3.7 0 0.1\n");
  const auto labels = ReadLoopLabels(f.path(), "0.150");
  ASSERT_EQ(labels.size(), 3u);
  EXPECT_TRUE(labels.at({751, 655}).metric);
  EXPECT_TRUE(labels.at({900, 100}).topological);
  EXPECT_FALSE(labels.at({900, 100}).metric);
  EXPECT_FALSE(labels.at({950, 120}).topological);
  EXPECT_THROW(ReadLoopLabels(f.path(), "0.500"), InputError);
}

TEST(GroundTruthFiles, LoopListRoundTrips) {
  const TempFile f("");
  WriteLoopList({{5, 1}, {9, 3}}, "test", f.path());
  EXPECT_EQ(ReadLoopList(f.path()), (std::set<LoopKey>{{5, 1}, {9, 3}}));
}

TEST(GroundTruthFiles, ErrorsNameTheLine) {
  const TempFile csv("1.0, 0, 0, 0\n2.0, 1, zero, 0\n");
  try {
    ReadStampedPoses(csv.path());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(),
                HasSubstr(csv.path() + ":2: field 2 'zero' is not a number"));
  }
  const TempFile list("4 2\n7\n");
  EXPECT_THROW(ReadLoopList(list.path()), InputError);
  EXPECT_THROW(ReadTimestamps("/nonexistent"), InputError);
}

}  // namespace
}  // namespace rrr
