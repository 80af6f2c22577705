#include "rrr/solver/pose_graph_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <numeric>
#include <random>
#include <tuple>

#include "../testing/chain_worlds.h"
#include "../testing/dataset_dir.h"
#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/io/g2o.h"
#include "rrr/solver/edge_error.h"
#include "rrr/solver/solve_in_parallel.h"

namespace rrr {
namespace {

// Poses 0..n on the x axis, odometry measuring 1 m each, and one loop from
// pose 0 to pose n measuring `loop_length`; all with information `w`·I.
PoseGraph<Pose2> StraightLine(int n, double loop_length, double w) {
  PoseGraph<Pose2> g;
  for (int k = 0; k <= n; ++k) g.AddPose(k, Pose2(k, 0, 0));
  Constraint<Pose2> e;
  e.information *= w;
  for (int k = 0; k < n; ++k) {
    e.from = k;
    e.to = k + 1;
    e.measurement = Pose2(1, 0, 0);
    g.AddEdge(e);
  }
  e.from = 0;
  e.to = n;
  e.measurement = Pose2(loop_length, 0, 0);
  g.AddEdge(e);
  return g;
}

TEST(PoseGraphSolver, StraightLoopHasTheLeastSquaresAnswer) {
  const int n = 10;
  const double loop_length = 8.0, w = 4.0;
  const auto g = StraightLine(n, loop_length, w);
  PoseGraphSolver<Pose2> solver(g, 4);
  // Minimising n (s-1)² + (n s - L)² gives a uniform step s = (1 + L)/(1 + n).
  const double s = (1 + loop_length) / (1 + n);
  MinimizeResult result;
  const auto x = solver.Optimize({0}, ConvergenceOptions(), &result);
  for (int k = 0; k <= n; ++k) {
    EXPECT_NEAR(x[k].x(), k * s, 1e-9);
    EXPECT_NEAR(x[k].y(), 0, 1e-12);
  }
  EXPECT_LE(result.iterations, 3);
  EXPECT_TRUE(result.converged);
  const SubsetErrors errors = solver.Solve({0});
  const double expected_total =
      w *
      (n * (s - 1) * (s - 1) + (n * s - loop_length) * (n * s - loop_length));
  EXPECT_NEAR(errors.total_chi2, expected_total, 1e-9);
  EXPECT_EQ(errors.num_edges, n + 1);
  ASSERT_EQ(errors.loop_chi2.size(), 1u);
  EXPECT_NEAR(errors.loop_chi2[0],
              w * (n * s - loop_length) * (n * s - loop_length), 1e-9);
}

TEST(PoseGraphSolver, SolveStartsFromOdometryEveryTime) {
  const auto g = StraightLine(6, 3.0, 1.0);
  PoseGraphSolver<Pose2> solver(g, 4);
  const SubsetErrors none = solver.Solve({});
  EXPECT_NEAR(none.total_chi2, 0.0, 1e-12);
  EXPECT_TRUE(none.loop_chi2.empty());
  const SubsetErrors with_loop = solver.Solve({0});
  EXPECT_GT(with_loop.total_chi2, 1.0);
  const SubsetErrors again = solver.Solve({0});
  EXPECT_DOUBLE_EQ(again.total_chi2, with_loop.total_chi2);
  EXPECT_NEAR(solver.Solve({}).total_chi2, 0.0, 1e-12);
}

// A circle of poses in 3D with noisy odometry and exact loops back to the
// start: the optimum is a stationary point of the total error.
TEST(PoseGraphSolver, ConvergesToAStationaryPointIn3D) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  const int n = 40;
  std::vector<Pose3> truth;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    Pose3::Tangent xi;
    xi << 0, 0, 0.1 * std::sin(a), 0, 0, a;
    truth.push_back(Pose3::Exp(xi) * Pose3(Eigen::Quaterniond::Identity(),
                                           Eigen::Vector3d(5, 0, 0)));
  }
  PoseGraph<Pose3> g;
  for (int k = 0; k < n; ++k) g.AddPose(k, truth[k]);
  Constraint<Pose3> e;
  for (int k = 0; k + 1 < n; ++k) {
    Pose3::Tangent xi;
    for (int d = 0; d < 6; ++d) xi[d] = noise(rng);
    e.from = k;
    e.to = k + 1;
    e.measurement = truth[k].between(truth[k + 1]) * Pose3::Exp(xi);
    g.AddEdge(e);
  }
  for (const int j : {n - 1, n - 2}) {
    e.from = j;
    e.to = 0;
    e.measurement = truth[j].between(truth[0]);
    g.AddEdge(e);
  }
  PoseGraphSolver<Pose3> solver(g, 4);
  const auto x = solver.Optimize({0, 1}, ConvergenceOptions());
  const double best = solver.Evaluate({0, 1}, x).total_chi2;
  EXPECT_LT(best, solver.Evaluate({0, 1}, solver.initial()).total_chi2);
  for (int trial = 0; trial < 20; ++trial) {
    auto y = x;
    const int k = 1 + trial % (n - 1);
    Pose3::Tangent xi;
    for (int d = 0; d < 6; ++d) xi[d] = 1e-3 * noise(rng);
    y[k] = y[k] * Pose3::Exp(xi);
    EXPECT_GE(solver.Evaluate({0, 1}, y).total_chi2, best - 1e-12);
  }
  // The first pose stays where odometry put it.
  EXPECT_LT(x[0].between(truth[0]).Log().norm(), 1e-12);
}

// A ring of 100 poses, radius 10 m, whose odometry turns with `turn` rad of
// noise per step, closed by loops across the ring: with 0.5, far from
// odometry, the linear model of the first step is poor.
PoseGraph<Pose2> NoisyRing(std::vector<int>* loops, double turn = 0.5) {
  std::mt19937 rng(2);
  std::normal_distribution<double> noise(0.0, turn);
  const int n = 100;
  std::vector<Pose2> truth;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    truth.emplace_back(10 * std::cos(a), 10 * std::sin(a), a + M_PI / 2);
  }
  PoseGraph<Pose2> g;
  for (int k = 0; k < n; ++k) g.AddPose(k, truth[k]);
  Constraint<Pose2> e;
  e.information = 100 * Eigen::Matrix3d::Identity();
  for (int k = 0; k + 1 < n; ++k) {
    e.from = k;
    e.to = k + 1;
    e.measurement = truth[k].between(truth[k + 1]) * Pose2(0, 0, noise(rng));
    g.AddEdge(e);
  }
  for (int k = 0; k + n / 2 < n; k += 3) {
    e.from = k + n / 2;
    e.to = k;
    e.measurement = truth[k + n / 2].between(truth[k]);
    g.AddEdge(e);
    loops->push_back(static_cast<int>(loops->size()));
  }
  return g;
}

TEST(PoseGraphSolver, ConvergesWhereTheFirstGaussNewtonStepRaisesTheError) {
  std::vector<int> loops;
  const PoseGraph<Pose2> g = NoisyRing(&loops);
  const double start = PoseGraphSolver<Pose2>(g, 1)
                           .Evaluate(loops, g.ComposeOdometry())
                           .total_chi2;
  // The premise: one plain step from odometry overshoots.
  ASSERT_GT(PoseGraphSolver<Pose2>(g, 1).Solve(loops).total_chi2, start);
  // One damped step does not.
  EXPECT_LT(PoseGraphSolver<Pose2>(g, 1, SolveSteps::kTrustRegion)
                .Solve(loops)
                .total_chi2,
            start);

  PoseGraphSolver<Pose2> solver(g, 1);
  MinimizeResult result;
  const std::vector<Pose2> x =
      solver.Optimize(loops, ConvergenceOptions(), &result);
  EXPECT_TRUE(result.converged);
  EXPECT_DOUBLE_EQ(result.initial_chi2, start);
  const double best = solver.Evaluate(loops, x).total_chi2;
  EXPECT_DOUBLE_EQ(result.final_chi2, best);
  EXPECT_LT(best, 0.01 * start);
  // A minimum: no small move of any pose lowers the error.
  std::mt19937 rng(7);
  std::normal_distribution<double> small(0.0, 1e-4);
  for (int k = 1; k < g.num_poses(); k += 7) {
    std::vector<Pose2> y = x;
    y[k] = y[k] * Pose2(small(rng), small(rng), small(rng));
    EXPECT_GE(solver.Evaluate(loops, y).total_chi2, best - 1e-9) << k;
  }
}

// Undamped steps to a minimum, which is then told by the last step's factor
// (no factorization at the point reached): judged afresh there, with its own
// factor, it must still be one.
TEST(PoseGraphSolver, AMinimumToldByTheLastFactorIsOneByItsOwn) {
  std::vector<int> loops;
  const PoseGraph<Pose2> g = NoisyRing(&loops, 0.05);
  PoseGraphSolver<Pose2> solver(g, 1);
  MinimizeResult first, again;
  const std::vector<Pose2> x =
      solver.Optimize(loops, ConvergenceOptions(), &first);
  ASSERT_EQ(first.stop, StopReason::kStationary);
  ASSERT_GT(first.iterations, 2);
  solver.Optimize(loops, ConvergenceOptions(), &again, &x);
  EXPECT_EQ(again.stop, StopReason::kStationary);
  EXPECT_EQ(again.iterations, 0);
  EXPECT_NEAR(again.final_chi2, first.final_chi2, 1e-12 * first.final_chi2);
}

TEST(PoseGraphSolver, ReportsWhenItStopsAtTheIterationLimit) {
  std::vector<int> loops;
  const PoseGraph<Pose2> g = NoisyRing(&loops);
  PoseGraphSolver<Pose2> solver(g, 1);
  MinimizeResult result;
  ConvergenceOptions two;
  two.max_iterations = 2;
  solver.Optimize(loops, two, &result);
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(result.iterations, 2);
  EXPECT_LT(result.final_chi2, result.initial_chi2);
}

// The plain method, independently: dense Gauss–Newton over every pose but
// the first, from odometry, for k iterations; returns the total error.
template <class Pose>
double DenseSolve(const PoseGraph<Pose>& g, const std::vector<int>& loops,
                  int k) {
  constexpr int D = Pose::kDof;
  std::vector<const Constraint<Pose>*> edges;
  for (const auto& e : g.odometry()) edges.push_back(&e);
  for (const int l : loops) edges.push_back(&g.loops()[l]);
  std::vector<Pose> x = g.ComposeOdometry();
  const int n = (g.num_poses() - 1) * D;
  for (int it = 0; it < k; ++it) {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (const auto* e : edges) {
      typename Pose::Jacobian ji, jj;
      const auto r = EdgeResidualAndJacobians(e->measurement, x[e->from],
                                              x[e->to], &ji, &jj);
      Eigen::MatrixXd j = Eigen::MatrixXd::Zero(D, n + D);  // pose 0 first
      j.block(0, e->from * D, D, D) = ji;
      j.block(0, e->to * D, D, D) = jj;
      const Eigen::MatrixXd jf = j.rightCols(n);
      h += jf.transpose() * e->information * jf;
      b -= jf.transpose() * e->information * r;
    }
    const Eigen::VectorXd delta = h.ldlt().solve(b);
    for (int p = 1; p < g.num_poses(); ++p) {
      x[p] = x[p] * Pose::Exp(delta.template segment<D>((p - 1) * D));
    }
  }
  double total = 0;
  for (const auto* e : edges) total += EdgeChi2(*e, x);
  return total;
}

TEST(PoseGraphSolver, ReducedSolveEqualsDenseSolveOfTheWholeGraph) {
  // A wiggly 2D path with noisy odometry and loops in its middle only, so
  // both ends of the chain lie outside the stretch that the loops span.
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.05);
  const int n = 40;
  PoseGraph<Pose2> g;
  std::vector<Pose2> truth;
  for (int k = 0; k < n; ++k) {
    truth.push_back(
        Pose2(std::cos(0.3 * k) * 5, std::sin(0.3 * k) * 5, 0.3 * k));
    g.AddPose(k, truth.back());
  }
  Constraint<Pose2> e;
  e.information = Eigen::Vector3d(20, 30, 200).asDiagonal();
  for (int k = 0; k + 1 < n; ++k) {
    e.from = k;
    e.to = k + 1;
    e.measurement = truth[k].between(truth[k + 1]) *
                    Pose2(noise(rng), noise(rng), noise(rng));
    g.AddEdge(e);
  }
  for (const auto& [a, b, wrong] :
       {std::tuple{10, 25, 0.0}, {12, 30, 0.0}, {15, 22, 2.0}}) {
    e.from = b;
    e.to = a;
    e.measurement = truth[b].between(truth[a]) * Pose2(wrong, 0, wrong / 4);
    g.AddEdge(e);
  }
  PoseGraphSolver<Pose2> solver(g, 4);
  for (const std::vector<int>& loops :
       {std::vector<int>{0}, {1}, {0, 1}, {2}, {0, 1, 2}}) {
    EXPECT_NEAR(solver.Solve(loops).total_chi2, DenseSolve(g, loops, 4),
                1e-6 * (1 + DenseSolve(g, loops, 4)));
  }
}

TEST(PoseGraphSolver, CountsTheEdgesTheActiveLoopsSpan) {
  auto g = StraightLine(10, 8.0, 1.0);  // loop 0: poses 0 -> 10
  Constraint<Pose2> e;
  e.from = 6;
  e.to = 3;
  e.measurement = Pose2(-3, 0, 0);
  g.AddEdge(e);  // loop 1: poses 3..6, three odometry edges
  PoseGraphSolver<Pose2> solver(g, 4);
  EXPECT_EQ(solver.Solve({}).num_spanned_edges, 0);
  EXPECT_EQ(solver.Solve({1}).num_spanned_edges, 3 + 1);
  EXPECT_EQ(solver.Solve({0}).num_spanned_edges, 10 + 1);
  EXPECT_EQ(solver.Solve({0, 1}).num_spanned_edges, 10 + 2);
  EXPECT_EQ(solver.Solve({0, 1}).num_edges, 10 + 2);
}

// Adds to `g` (of `world`) a false revisit of 5 links, poses 300–304 to
// 500–504, each measuring the true relative pose times `off`; returns their
// loop indices.
std::vector<int> AddFalseRevisit(const SimulatedWorld& world, const Pose2& off,
                                 PoseGraph<Pose2>* g) {
  std::vector<int> revisit;
  for (int k = 0; k < 5; ++k) {
    Constraint<Pose2> e = g->loops().front();
    e.from = 300 + k;
    e.to = 500 + k;
    e.measurement = world.truth[e.from].between(world.truth[e.to]) * off;
    revisit.push_back(static_cast<int>(g->loops().size()));
    g->AddEdge(e);
  }
  return revisit;
}

TEST(PoseGraphSolver, ChangesOfMinimumAreWhatMinimizingWithAndWithoutGives) {
  // A simulated city whose loops are true, and a false revisit of 5 links
  // that the odometry's drift could explain (1 m and 0.03 rad off).
  const SimulatedWorld world = SimulateWorld(testing::Grid(600, 2));
  PoseGraph<Pose2> g = world.graph;
  const int true_loops = static_cast<int>(g.loops().size());
  ASSERT_GT(true_loops, 10);
  const std::vector<int> revisit =
      AddFalseRevisit(world, Pose2(1.0, 0.0, 0.03), &g);
  std::vector<int> true_ones(true_loops);
  std::iota(true_ones.begin(), true_ones.end(), 0);
  std::vector<int> all = true_ones;
  all.insert(all.end(), revisit.begin(), revisit.end());
  const std::vector<int> some_true = {0, 1, 2};
  const PoseGraphSolver<Pose2> solver(g, 1);
  const auto minimum = [&](const std::vector<int>& loops,
                           const std::vector<Pose2>* start = nullptr) {
    MinimizeResult result;
    const std::vector<Pose2> x =
        solver.Optimize(loops, ConvergenceOptions(), &result, start);
    return std::pair(x, result.final_chi2);
  };
  const auto without = [](std::vector<int> loops, const std::vector<int>& out) {
    for (const int k : out)
      loops.erase(std::find(loops.begin(), loops.end(), k));
    return loops;
  };
  const auto [with_all, chi2_all] = minimum(all);
  const auto [with_true, chi2_true] = minimum(true_ones);
  // Taken out of the map with every loop: the revisit and three true loops.
  std::vector<double> changes;
  ASSERT_TRUE(
      solver.ChangesOfMinimum(all, {revisit, some_true}, with_all, &changes));
  ASSERT_EQ(changes.size(), 2u);
  const double revisit_out = chi2_all - minimum(true_ones, &with_all).second;
  const double true_out =
      chi2_all - minimum(without(all, some_true), &with_all).second;
  EXPECT_NEAR(changes[0], revisit_out, 0.05 * revisit_out);
  EXPECT_NEAR(changes[1], true_out, 0.05 * true_out + 0.1);
  // The revisit costs far more than three true loops do.
  EXPECT_GT(changes[0], 10.0 * changes[1]);
  // Put into the map of the true loops: what it would bring.
  ASSERT_TRUE(
      solver.ChangesOfMinimum(true_ones, {revisit}, with_true, &changes));
  EXPECT_NEAR(changes[0], chi2_all - chi2_true, 0.05 * (chi2_all - chi2_true));
}

TEST(PoseGraphSolver, ChangesWithoutAGroupAreWhatMinimizingWithoutItGives) {
  // The city above with a false revisit 3 m and 0.1 rad off, three true
  // loops left out: what they would bring to the minimum without the revisit,
  // from the minimum with it (one step that takes the revisit out), is what
  // minimizing gives.
  const SimulatedWorld world = SimulateWorld(testing::Grid(600, 2));
  PoseGraph<Pose2> g = world.graph;
  const int true_loops = static_cast<int>(g.loops().size());
  const std::vector<int> revisit =
      AddFalseRevisit(world, Pose2(3.0, 0.0, 0.1), &g);
  // Three true loops within the stretch the revisit spans: it strains them.
  std::vector<int> left_out, others;
  for (int k = 0; k < true_loops; ++k) {
    const auto& e = g.loops()[k];
    const bool within = std::min(e.from, e.to) >= 300 &&
                        std::max(e.from, e.to) <= 505 &&
                        std::abs(e.from - e.to) > 50;
    (within && left_out.size() < 3 ? left_out : others).push_back(k);
  }
  ASSERT_EQ(left_out.size(), 3u);
  std::vector<int> in = others;
  in.insert(in.end(), revisit.begin(), revisit.end());
  const PoseGraphSolver<Pose2> solver(g, 1);
  const auto minimum = [&](const std::vector<int>& loops) {
    MinimizeResult result;
    const std::vector<Pose2> x =
        solver.Optimize(loops, ConvergenceOptions(), &result);
    return std::pair(x, result.final_chi2);
  };
  const std::vector<Pose2> x = minimum(in).first;
  std::vector<double> changes;
  std::vector<std::vector<double>> without;
  ASSERT_TRUE(
      solver.ChangesOfMinimum(in, {revisit, left_out}, x, &changes, &without));
  ASSERT_EQ(without.size(), 2u);
  ASSERT_EQ(without[0].size(), 2u);
  EXPECT_TRUE(without[1].empty());  // a group out has nothing to take out
  EXPECT_EQ(without[0][0], std::numeric_limits<double>::infinity());
  std::vector<int> all = others;
  all.insert(all.end(), left_out.begin(), left_out.end());
  const double exact = minimum(all).second - minimum(others).second;
  EXPECT_NEAR(without[0][1], exact, 0.05 * exact);
  // With the revisit in, the three bring more than they would without it.
  EXPECT_GT(changes[1], without[0][1]);
}

TEST(PoseGraphSolver, ChangesOfMinimumIn3DAreWhatMinimizingGives) {
  // Three laps of a tilted 3D circle of 40 poses, noisy odometry, true loops
  // between the laps and a false revisit of 4 links 0.5 m off.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  const int lap = 40;
  std::vector<Pose3> truth;
  for (int k = 0; k < 3 * lap; ++k) {
    const double a = 2 * M_PI * k / lap;
    Pose3::Tangent xi;
    xi << 0, 0, 0.02 * k, 0.1 * std::sin(a), 0, a;
    truth.push_back(Pose3::Exp(xi) * Pose3(Eigen::Quaterniond::Identity(),
                                           Eigen::Vector3d(5, 0, 0)));
  }
  PoseGraph<Pose3> g;
  for (size_t k = 0; k < truth.size(); ++k) g.AddPose(k, truth[k]);
  Constraint<Pose3> e;
  e.information *= 100.0;
  for (size_t k = 0; k + 1 < truth.size(); ++k) {
    Pose3::Tangent xi;
    for (int d = 0; d < 6; ++d) xi[d] = noise(rng);
    e.from = static_cast<int>(k);
    e.to = e.from + 1;
    e.measurement = truth[k].between(truth[k + 1]) * Pose3::Exp(xi);
    g.AddEdge(e);
  }
  std::vector<int> true_ones, revisit;
  for (int k = 0; k + lap < 3 * lap; k += 3) {
    e.from = k + lap;
    e.to = k;
    e.measurement = truth[e.from].between(truth[e.to]);
    true_ones.push_back(static_cast<int>(g.loops().size()));
    g.AddEdge(e);
  }
  Pose3::Tangent off;
  off << 0.5, 0, 0, 0, 0, 0.02;
  for (int k = 0; k < 4; ++k) {
    e.from = 90 + k;
    e.to = 10 + k;
    e.measurement = truth[e.from].between(truth[e.to]) * Pose3::Exp(off);
    revisit.push_back(static_cast<int>(g.loops().size()));
    g.AddEdge(e);
  }
  std::vector<int> all = true_ones;
  all.insert(all.end(), revisit.begin(), revisit.end());
  const PoseGraphSolver<Pose3> solver(g, 1);
  MinimizeResult with, without;
  const std::vector<Pose3> x =
      solver.Optimize(all, ConvergenceOptions(), &with);
  const std::vector<Pose3> y =
      solver.Optimize(true_ones, ConvergenceOptions(), &without, &x);
  const double exact = with.final_chi2 - without.final_chi2;
  ASSERT_GT(exact, 10.0);
  std::vector<double> changes;
  ASSERT_TRUE(solver.ChangesOfMinimum(all, {revisit}, x, &changes));
  EXPECT_NEAR(changes[0], exact, 0.05 * exact);
  ASSERT_TRUE(solver.ChangesOfMinimum(true_ones, {revisit}, y, &changes));
  EXPECT_NEAR(changes[0], exact, 0.05 * exact);
}

TEST(PoseGraphSolver, HoldsFixedPoses) {
  auto g = StraightLine(4, 2.0, 1.0);
  g.Fix(4);
  PoseGraphSolver<Pose2> solver(g, 4);
  const auto x = solver.Optimize({0}, ConvergenceOptions());
  EXPECT_DOUBLE_EQ(x[4].x(), 4.0);
  EXPECT_DOUBLE_EQ(x[0].x(), 0.0);
}

TEST(PoseGraphSolver, ConcurrentSolvesOfSphere2500AgreeWithOneAtATime) {
  // sphere2500's factor takes CHOLMOD's supernodal (BLAS) path, whose calls
  // must not run concurrently with Debian's serial OpenBLAS.
  const std::string path = testing::DatasetDir() + "/synthetic/sphere2500.g2o";
  if (!std::ifstream(path)) GTEST_SKIP() << "sphere2500 not found at " << path;
  const auto graph = std::get<PoseGraph<Pose3>>(ReadG2o(path).graph);
  PoseGraphSolver<Pose3> solver(graph, 4);
  std::vector<int> loops(graph.loops().size());
  std::iota(loops.begin(), loops.end(), 0);
  std::vector<std::vector<int>> subsets(4);
  for (size_t k = 0; k < subsets.size(); ++k) {
    subsets[k].assign(loops.begin(), loops.end() - 50 * k);
  }
  std::vector<SubsetErrors> expected(subsets.size());
  for (size_t k = 0; k < subsets.size(); ++k) {
    expected[k] = solver.Solve(subsets[k]);
  }
  const std::vector<SubsetErrors> concurrent =
      SolveInParallel(solver, subsets, 2);
  for (size_t k = 0; k < subsets.size(); ++k) {
    EXPECT_EQ(concurrent[k].total_chi2, expected[k].total_chi2) << k;
    EXPECT_EQ(concurrent[k].loop_chi2, expected[k].loop_chi2) << k;
  }
}

}  // namespace
}  // namespace rrr
