// The rrr program as a user runs it: exit codes, messages and outputs.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace {

using ::testing::HasSubstr;

struct Result {
  int status;
  std::string output;  // stdout and stderr
};

Result Rrr(const std::string& args) {
  const std::string command = std::string(RRR_BINARY) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) {
    output.append(buffer.data(), n);
  }
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::string Tmp(const std::string& name) {
  return ::testing::TempDir() + "rrr_tool_test_" + name;
}

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(RrrTool, MalformedInputIsAClearErrorNotACrash) {
  const std::string bad = Tmp("bad.g2o");
  std::ofstream(bad) << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                        "EDGE_SE2 0 1 1 0 0 1 0 0 1 0\n";
  const Result r = Rrr("verify " + bad + " -w 10 -o " + Tmp("o.g2o") + " -r " +
                       Tmp("r.json"));
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output,
              HasSubstr(bad + ":3: EDGE_SE2 needs 12 fields, found 11"));
}

TEST(RrrTool, BrokenOdometryChainIsNamed) {
  const std::string gap = Tmp("gap.g2o");
  std::ofstream(gap)
      << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
         "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n";
  // Only the map procedure judges several chains.
  const Result r = Rrr("verify " + gap + " -w 10 --procedure published -o " +
                       Tmp("o.g2o") + " -r " + Tmp("r.json"));
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output, HasSubstr("pose 2 has no odometry edge to pose 1"));
  // It keeps chains that nothing joins apart, each a map of its own.
  const std::string report = Tmp("chains.json");
  const Result apart =
      Rrr("verify " + gap + " -w 10 -o " + Tmp("o.g2o") + " -r " + report);
  ASSERT_EQ(apart.status, 0) << apart.output;
  const nlohmann::json chains = ReadJson(report);
  ASSERT_EQ(chains["chains"].size(), 2u);
  EXPECT_EQ(chains["chains"][1]["first"], 2);
  EXPECT_EQ(chains["maps"].size(), 2u);
  // Optimization needs every pose reached.
  const Result unreached = Rrr("optimize " + gap + " -o " + Tmp("o.g2o"));
  EXPECT_EQ(unreached.status, 1);
  EXPECT_THAT(unreached.output,
              HasSubstr(gap + ": pose 2 is not reached from the first pose"));
}

TEST(RrrTool, RobotsKeyedAsSymbolsAreChainsNamedByTheirLetters) {
  // Two robots, 'a' and 'b', keyed as GTSAM symbols, and one loop between
  // them: two chains, named, left apart (one loop cannot join them), ids
  // written back as read.
  const std::string fleet = Tmp("fleet.g2o"), out = Tmp("fleet_out.g2o"),
                    report = Tmp("fleet.json");
  const long long a = static_cast<long long>('a') << 56;
  const long long b = static_cast<long long>('b') << 56;
  {
    std::ofstream f(fleet);
    for (const long long robot : {a, b}) {
      for (int k = 0; k < 5; ++k) {
        f << "VERTEX_SE2 " << robot + k << " " << k << " 0 0\n";
      }
      for (int k = 0; k < 4; ++k) {
        f << "EDGE_SE2 " << robot + k << " " << robot + k + 1
          << " 1 0 0 1 0 0 1 0 1\n";
      }
    }
    f << "EDGE_SE2 " << a + 1 << " " << b + 1 << " 0 3 0 1 0 0 1 0 1\n";
  }
  const Result r =
      Rrr("verify " + fleet + " -w 10 -o " + out + " -r " + report);
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json j = ReadJson(report);
  ASSERT_EQ(j["chains"].size(), 2u);
  EXPECT_EQ(j["chains"][0]["robot"], "a");
  EXPECT_EQ(j["chains"][1]["robot"], "b");
  EXPECT_EQ(j["chains"][1]["first_index"], 0);
  ASSERT_EQ(j["chain_pairs"].size(), 1u);
  EXPECT_FALSE(j["chain_pairs"][0]["joined"].get<bool>());
  EXPECT_EQ(j["decisions"][0]["test"], "apart");
  std::ifstream written(out);
  std::string first;
  written >> first >> first;
  EXPECT_EQ(first, std::to_string(a));
  // Evaluated per robot and per map, each aligned on its own.
  const std::string none = Tmp("fleet_false.txt"),
                    scores = Tmp("fleet_scores.json");
  std::ofstream(none) << "";
  ASSERT_EQ(Rrr("evaluate " + report + " --map " + out + " --gt-g2o " + fleet +
                " --false-loops " + none + " --json " + scores)
                .status,
            0);
  const nlohmann::json e = ReadJson(scores);
  ASSERT_EQ(e["chains"].size(), 2u);
  EXPECT_EQ(e["chains"][1]["ate_poses"], 5);
  ASSERT_EQ(e["maps"].size(), 2u);
  EXPECT_LT(e["maps"][1]["ate_rmse"].get<double>(), 1e-6);
  // PCM's inter-robot test has nothing to compare one loop with: its clique
  // of one joins the robots, placed by that loop.
  ASSERT_EQ(
      Rrr("verify " + fleet + " --method pcm -w 10 -o " + out + " -r " + report)
          .status,
      0);
  const nlohmann::json pcm = ReadJson(report);
  ASSERT_EQ(pcm["chain_pairs"].size(), 1u);
  EXPECT_TRUE(pcm["chain_pairs"][0]["joined"].get<bool>());
  const std::vector<double> relative = pcm["chain_pairs"][0]["relative_pose"];
  EXPECT_NEAR(relative[0], 0.0, 1e-9);
  EXPECT_NEAR(relative[1], 3.0, 1e-9);
  EXPECT_EQ(pcm["maps"].size(), 1u);
}

TEST(RrrTool, OptimizeJoinsTwoChainsByTheirLoops) {
  // Two sessions: poses 0-1 and 2-3 (the second's odometry restarted away
  // from the first), joined only by the loop 0 -> 2 (2 m ahead).
  const std::string two = Tmp("two_chains.g2o"), out = Tmp("two_out.g2o");
  std::ofstream(two) << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                        "VERTEX_SE2 2 5 5 0\nVERTEX_SE2 3 6 5 0\n"
                        "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
                        "EDGE_SE2 2 3 1 0 0 1 0 0 1 0 1\n"
                        "EDGE_SE2 0 2 2 0 0 1 0 0 1 0 1\n";
  for (const std::string init : {"odometry", "chordal"}) {
    const Result r = Rrr("optimize " + two + " -o " + out + " --init " + init);
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream in(out);
    std::string line;
    std::vector<std::string> vertices;
    while (std::getline(in, line) && line.rfind("VERTEX", 0) == 0) {
      vertices.push_back(line);
    }
    ASSERT_EQ(vertices.size(), 4u);
    double id, x, y, theta;
    std::istringstream(vertices[3].substr(11)) >> id >> x >> y >> theta;
    EXPECT_NEAR(x, 3.0, 1e-6) << init;
    EXPECT_NEAR(y, 0.0, 1e-6) << init;
  }
}

TEST(RrrTool, BadOptionIsNamed) {
  const Result r = Rrr("simulate --poses 10 -o " + Tmp("w.g2o") + " -t " +
                       Tmp("f.txt") + " --ground-truth " + Tmp("t.g2o"));
  EXPECT_NE(r.status, 0);
  EXPECT_THAT(r.output, HasSubstr("poses must be at least 100"));
  // The options are checked before the input is read.
  const std::string graph = Tmp("two_poses.g2o");
  std::ofstream(graph) << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                          "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n";
  const Result limit = Rrr("verify " + graph + " -w 10 --map-junctions 0 -o " +
                           Tmp("v.g2o") + " -r " + Tmp("v.json"));
  EXPECT_NE(limit.status, 0);
  EXPECT_THAT(limit.output, HasSubstr("map_junctions must be at least 1"));
}

TEST(RrrTool, UnknownTagsAreCountedInAWarning) {
  const std::string file = Tmp("tags.g2o");
  std::ofstream(file)
      << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_XY 5 1 1\n"
         "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n";
  const Result r = Rrr("optimize " + file + " -o " + Tmp("o.g2o"));
  EXPECT_EQ(r.status, 0);
  EXPECT_THAT(r.output,
              HasSubstr("skipped lines with unknown tags: VERTEX_XY x1"));
}

TEST(RrrTool, OptimizeSaysWhetherItConvergedAndFailsIfNot) {
  const std::string world = Tmp("opt_world.g2o"), out = Tmp("opt_out.g2o"),
                    report = Tmp("opt.json");
  ASSERT_EQ(Rrr("simulate --poses 300 --false-loops 0 -o " + world + " -t " +
                Tmp("opt_false.txt") + " --ground-truth " + Tmp("opt_gt.g2o"))
                .status,
            0);
  const Result limited =
      Rrr("optimize " + world + " -o " + out +
          " --init odometry --max-iterations 1 --report " + report);
  EXPECT_EQ(limited.status, 3) << limited.output;
  EXPECT_THAT(limited.output, HasSubstr("after 1 iterations, NOT converged"));
  EXPECT_THAT(limited.output,
              HasSubstr(world + ": not converged within 1 iterations"));
  nlohmann::json r = ReadJson(report);
  EXPECT_FALSE(r["optimization"]["converged"].get<bool>());
  EXPECT_EQ(r["optimization"]["stopped_by"], "iteration_limit");
  EXPECT_EQ(r["optimization"]["iterations"].get<int>(), 1);
  const double start = r["optimization"]["initial_chi2"].get<double>();

  const Result full = Rrr("optimize " + world + " -o " + out +
                          " --init odometry --report " + report);
  EXPECT_EQ(full.status, 0) << full.output;
  EXPECT_THAT(full.output, HasSubstr("converged"));
  r = ReadJson(report);
  EXPECT_TRUE(r["optimization"]["converged"].get<bool>());
  EXPECT_NE(r["optimization"]["stopped_by"], "iteration_limit");
  EXPECT_GT(r["optimization"]["iterations"].get<int>(), 1);
  EXPECT_DOUBLE_EQ(r["optimization"]["initial_chi2"].get<double>(), start);
  EXPECT_LT(r["optimization"]["final_chi2"].get<double>(), 0.01 * start);
}

TEST(RrrTool, OptimizeKeepsTheLowerMinimumOfItsStarts) {
  const std::string world = Tmp("starts_world.g2o"), out = Tmp("starts.g2o"),
                    report = Tmp("starts.json");
  ASSERT_EQ(
      Rrr("simulate --poses 600 --false-loops 0 -o " + world + " -t " +
          Tmp("starts_false.txt") + " --ground-truth " + Tmp("starts_gt.g2o"))
          .status,
      0);
  ASSERT_EQ(Rrr("optimize " + world + " -o " + out + " -r " + report).status,
            0);
  const nlohmann::json r = ReadJson(report);
  EXPECT_EQ(r["init"], "best");
  const nlohmann::json& starts = r["starts"];
  ASSERT_TRUE(starts.contains("odometry") && starts.contains("chordal"));
  // The chordal start is nearer the minimum than the composed odometry.
  EXPECT_LT(starts["chordal"]["initial_chi2"].get<double>(),
            starts["odometry"]["initial_chi2"].get<double>());
  const double kept = r["optimization"]["final_chi2"].get<double>();
  EXPECT_LE(kept, starts["odometry"]["final_chi2"].get<double>());
  EXPECT_LE(kept, starts["chordal"]["final_chi2"].get<double>());
  EXPECT_EQ(starts[r["start"].get<std::string>()]["final_chi2"].get<double>(),
            kept);
  EXPECT_NE(Rrr("optimize " + world + " -o " + out + " --init nowhere").status,
            0);
}

TEST(RrrTool, MendsARealFileAndRefusesItUnderStrict) {
  // Edges only (no VERTEX lines), and a loop whose information matrix has a
  // negative eigenvalue (3 ± 5 in its xy block).
  const std::string file = Tmp("edges_only.g2o"), out = Tmp("mended.g2o"),
                    report = Tmp("mended.json");
  std::ofstream(file) << "EDGE_SE2 0 1 1 0 0.5 1 0 0 1 0 1\n"
                         "EDGE_SE2 1 2 1 0 0.5 1 0 0 1 0 1\n"
                         "EDGE_SE2 2 3 1 0 0.5 1 0 0 1 0 1\n"
                         "EDGE_SE2 3 0 1 0 0.5 3 5 0 3 0 4\n";
  const Result mended =
      Rrr("optimize " + file + " -o " + out + " -r " + report);
  EXPECT_EQ(mended.status, 0) << mended.output;
  EXPECT_THAT(mended.output,
              HasSubstr(file + ":4: information matrix of edge 3 -> 0 is not "
                               "positive definite"));
  EXPECT_THAT(mended.output, HasSubstr(file + ": no vertices"));
  const nlohmann::json r = ReadJson(report);
  EXPECT_TRUE(r["poses_from_odometry"].get<bool>());
  ASSERT_EQ(r["repaired_information"].size(), 1u);
  EXPECT_EQ(r["repaired_information"][0][0].get<int>(), 4);
  EXPECT_NEAR(r["repaired_information"][0][3].get<double>(), -2.0, 1e-9);
  EXPECT_EQ(r["poses"].get<int>(), 4);
  // rrr verify reads it the same way and lists the same.
  const Result verified =
      Rrr("verify " + file + " -w 10 -o " + out + " -r " + report);
  EXPECT_EQ(verified.status, 0) << verified.output;
  EXPECT_EQ(ReadJson(report)["repaired_information"].size(), 1u);

  const Result strict = Rrr("optimize " + file + " -o " + out + " --strict");
  EXPECT_EQ(strict.status, 1);
  EXPECT_THAT(strict.output, HasSubstr(file + ": no vertices"));
  std::ofstream(file) << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                         "EDGE_SE2 0 1 1 0 0 3 5 0 3 0 4\n";
  const Result strict_information =
      Rrr("optimize " + file + " -o " + out + " --strict");
  EXPECT_EQ(strict_information.status, 1);
  EXPECT_THAT(strict_information.output,
              HasSubstr(file + ":3: information matrix of edge 0 -> 1 is not "
                               "positive definite"));
}

TEST(RrrTool, SimulateVerifyEvaluateRoundTrip) {
  const std::string world = Tmp("world.g2o"), truth = Tmp("false.txt"),
                    gt = Tmp("gt.g2o"), out = Tmp("out.g2o"),
                    report = Tmp("report.json"), eval = Tmp("eval.json");
  ASSERT_EQ(Rrr("simulate --poses 800 --false-loops 20 -o " + world + " -t " +
                truth + " --ground-truth " + gt)
                .status,
            0);
  const Result v =
      Rrr("verify " + world + " -w 10 -o " + out + " -r " + report);
  ASSERT_EQ(v.status, 0) << v.output;
  const nlohmann::json r = ReadJson(report);
  EXPECT_EQ(r["candidates"].get<size_t>(),
            r["accepted"].size() + r["rejected"].size());
  EXPECT_GT(r["clusters"].get<int>(), 0);
  EXPECT_TRUE(r["final_optimization"]["converged"].get<bool>());
  EXPECT_GE(r["seconds"].get<double>(), 0.0);
  const Result e =
      Rrr("evaluate " + report + " --map " + out + " --false-loops " + truth +
          " --gt-g2o " + gt + " --json " + eval);
  ASSERT_EQ(e.status, 0) << e.output;
  const nlohmann::json scores = ReadJson(eval);
  EXPECT_DOUBLE_EQ(scores["precision"].get<double>(), 1.0);
  EXPECT_GT(scores["recall"].get<double>(), 0.5);
  // Accepted loops correct the drift of odometry alone.
  ASSERT_EQ(Rrr("evaluate " + report + " --map " + world + " --false-loops " +
                truth + " --gt-g2o " + gt + " --json " + eval)
                .status,
            0);
  const double odometry_ate = ReadJson(eval)["ate_rmse"].get<double>();
  EXPECT_LT(scores["ate_rmse"].get<double>(), 0.5 * odometry_ate);
  // The output graph holds the odometry and only the accepted loops.
  std::ifstream in(out);
  std::string line;
  size_t edges = 0;
  while (std::getline(in, line)) edges += line.rfind("EDGE_SE2", 0) == 0;
  EXPECT_EQ(edges, 799 + r["accepted"].size());
}

TEST(RrrTool, VerifyNeedsOnlyItsInputAndPrintsItsCounts) {
  const std::string world = Tmp("alone_world.g2o"), truth = Tmp("alone.txt"),
                    gt = Tmp("alone_gt.g2o"), report = Tmp("alone_report.json");
  ASSERT_EQ(Rrr("simulate --poses 600 --false-loops 10 -o " + world + " -t " +
                truth + " --ground-truth " + gt)
                .status,
            0);
  const Result alone = Rrr("verify " + world);
  ASSERT_EQ(alone.status, 0) << alone.output;
  // The default window is 10, as the command below gives it.
  const Result full = Rrr("verify " + world + " -w 10 -r " + report);
  ASSERT_EQ(full.status, 0) << full.output;
  const nlohmann::json r = ReadJson(report);
  const std::string counts =
      "candidates " + std::to_string(r["candidates"].get<size_t>()) +
      ", clusters " + std::to_string(r["clusters"].get<size_t>()) +
      ", accepted " + std::to_string(r["accepted"].size()) + ", rejected " +
      std::to_string(r["rejected"].size());
  EXPECT_THAT(alone.output, HasSubstr(counts));
  EXPECT_THAT(full.output, HasSubstr(counts));
  // Another window clusters otherwise: the defaults are not the only ones.
  const Result other_window = Rrr("verify " + world + " -w 30");
  ASSERT_EQ(other_window.status, 0) << other_window.output;
  EXPECT_THAT(other_window.output, ::testing::Not(HasSubstr(counts)));
}

TEST(RrrTool, EvaluateJudgesListedLoopsByTheMetricRuleToo) {
  const std::string world = Tmp("judged.g2o"), truth = Tmp("judged.txt"),
                    gt = Tmp("judged_gt.g2o"), out = Tmp("judged_out.g2o"),
                    report = Tmp("judged.json"), listed = Tmp("listed.txt"),
                    eval = Tmp("judged_eval.json");
  ASSERT_EQ(Rrr("simulate --poses 600 --false-loops 10 -o " + world + " -t " +
                truth + " --ground-truth " + gt)
                .status,
            0);
  ASSERT_EQ(
      Rrr("verify " + world + " -w 10 -o " + out + " -r " + report).status, 0);
  // The list names one accepted (accurate) loop as false besides the real
  // false loops: the list's precision counts it, the metric rule does not.
  const auto first = ReadJson(report)["accepted"][0];
  std::ifstream real(truth);
  std::ofstream(listed) << real.rdbuf() << first[0] << " " << first[1] << "\n";
  const std::string scored = "evaluate " + report + " --graph " + world +
                             " --gt-g2o " + gt + " --json " + eval;
  ASSERT_EQ(Rrr(scored + " --false-loops " + listed).status, 0);
  const nlohmann::json with_list = ReadJson(eval);
  const double accepted = with_list["accepted"].get<double>();
  EXPECT_DOUBLE_EQ(with_list["precision"].get<double>(),
                   (accepted - 1) / accepted);
  EXPECT_DOUBLE_EQ(with_list["metric_precision"].get<double>(), 1.0);
  // Without a list, the ground truth decides both.
  ASSERT_EQ(Rrr(scored).status, 0);
  EXPECT_DOUBLE_EQ(ReadJson(eval)["precision"].get<double>(), 1.0);
  const Result flat = Rrr("evaluate " + report + " --graph " + world);
  EXPECT_NE(flat.status, 0);
  EXPECT_THAT(flat.output, HasSubstr("--graph needs --gt-g2o or --gt-csv"));
}

TEST(RrrTool, SpoilAddsAndListsFalseLoops) {
  const std::string world = Tmp("clean.g2o");
  ASSERT_EQ(Rrr("simulate --poses 300 --false-loops 0 -o " + world + " -t " +
                Tmp("none.txt") + " --ground-truth " + Tmp("gt2.g2o"))
                .status,
            0);
  const Result r = Rrr("spoil " + world + " -n 25 --group 5 -s 3 -o " +
                       Tmp("spoiled.g2o") + " -t " + Tmp("spoiled.txt"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("added 25 false loops"));
  std::ifstream list(Tmp("spoiled.txt"));
  std::string line;
  int loops = 0;
  while (std::getline(list, line)) loops += !line.empty() && line[0] != '#';
  EXPECT_EQ(loops, 25);
  // Against the simulated ground truth; one with a pose missing is named.
  const Result checked =
      Rrr("spoil " + world + " -n 25 -s 3 --reference " + Tmp("gt2.g2o") +
          " -o " + Tmp("spoiled2.g2o") + " -t " + Tmp("spoiled2.txt"));
  ASSERT_EQ(checked.status, 0) << checked.output;
  EXPECT_THAT(checked.output, HasSubstr("correct at the reference discarded"));
  const std::string short_truth = Tmp("short_gt.g2o");
  {
    std::ifstream in(Tmp("gt2.g2o"));
    std::ofstream out(short_truth);
    for (std::string l; std::getline(in, l);) {
      if (l.rfind("VERTEX_SE2 299 ", 0) != 0) out << l << "\n";
    }
  }
  const Result missing =
      Rrr("spoil " + world + " -n 25 -s 3 --reference " + short_truth + " -o " +
          Tmp("spoiled3.g2o") + " -t " + Tmp("spoiled3.txt"));
  EXPECT_NE(missing.status, 0);
  EXPECT_THAT(missing.output, HasSubstr(short_truth + ": has no pose 299"));
}

// A simulated world's file with degenerate candidates appended: 3 self
// loops, 2 exact duplicates of its first loop, 2 further edges between
// consecutive poses and 4 candidates naming poses the file does not have.
std::string WorldWithDegenerateCandidates() {
  const std::string world = Tmp("degenerate.g2o");
  Rrr("simulate --poses 400 --false-loops 0 -o " + world + " -t " +
      Tmp("degenerate_none.txt") + " --ground-truth " +
      Tmp("degenerate_gt.g2o"));
  std::ifstream in(world);
  std::string line, first_loop;
  std::stringstream text;
  while (std::getline(in, line)) {
    text << line << "\n";
    std::istringstream f(line);
    std::string tag;
    long a = 0, b = 0;
    f >> tag >> a >> b;
    if (tag == "EDGE_SE2" && std::labs(a - b) > 1 && first_loop.empty()) {
      first_loop = line;
    }
  }
  const std::string info = " 100 0 0 100 0 1000\n";
  for (const int p : {5, 50, 120}) {
    text << "EDGE_SE2 " << p << " " << p << " 0 0 0" << info;
  }
  text << first_loop << "\n" << first_loop << "\n";
  text << "EDGE_SE2 10 11 1 0 0" << info << "EDGE_SE2 31 30 -1 0 0" << info;
  for (const int p : {400, 401, 5000, -3}) {
    text << "EDGE_SE2 7 " << p << " 0 0 0" << info;
  }
  std::ofstream(world) << text.str();
  return world;
}

TEST(RrrTool, DegenerateCandidatesAreSkippedCountedAndReported) {
  const std::string world = WorldWithDegenerateCandidates();
  const std::string report = Tmp("degenerate.json");
  const Result r = Rrr("verify " + world + " -w 10 -o " +
                       Tmp("degenerate_out.g2o") + " -r " + report);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("skipped: self_loop"));
  EXPECT_THAT(r.output, HasSubstr("skipped candidates: consecutive_poses x2, "
                                  "duplicate x2, self_loop x3, "
                                  "unknown_pose x4"));
  const nlohmann::json skipped = ReadJson(report)["skipped_candidates"];
  EXPECT_EQ(skipped["self_loop"]["count"], 3);
  EXPECT_EQ(skipped["duplicate"]["count"], 2);
  EXPECT_EQ(skipped["consecutive_poses"]["count"], 2);
  EXPECT_EQ(skipped["unknown_pose"]["count"], 4);
  // Each is listed as [line, i, j].
  EXPECT_EQ(skipped["self_loop"]["candidates"][0][1], 5);
  EXPECT_EQ(skipped["self_loop"]["candidates"][0][2], 5);

  // --strict stops at the first, naming the file and line.
  const Result strict = Rrr("verify " + world + " -w 10 --strict -o " +
                            Tmp("degenerate_out.g2o") + " -r " + report);
  EXPECT_EQ(strict.status, 1);
  EXPECT_THAT(strict.output, HasSubstr(world + ":"));
  EXPECT_THAT(strict.output, HasSubstr("to itself"));
}

TEST(RrrTool, ToBagRunsItsOwnProgramWithEveryArgument) {
  const std::string world = Tmp("bag_world.g2o"), bag = Tmp("world.bag");
  ASSERT_EQ(Rrr("simulate --poses 200 --false-loops 5 -o " + world + " -t " +
                Tmp("bag_false.txt") + " --ground-truth " + Tmp("bag_gt.g2o"))
                .status,
            0);
  std::remove(bag.c_str());
  // Options before and after the input reach rrr_to_bag.
  const Result r = Rrr("to-bag --rate 20 " + world + " -o " + bag);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("wrote 200 odometry messages"));
  EXPECT_THAT(r.output, HasSubstr("(9.95 s)"));  // 199 steps at 20 Hz
  EXPECT_TRUE(std::ifstream(bag).good());
  EXPECT_THAT(Rrr("to-bag --help").output,
              HasSubstr("rrr_to_bag to-bag [OPTIONS] input"));
  const Result missing = Rrr("to-bag " + world);
  EXPECT_NE(missing.status, 0);
  EXPECT_THAT(missing.output, HasSubstr("--output is required"));
}

TEST(RrrTool, ToBagWritesSeveralChainsAsAFleetsTopics) {
  // Robot 'a' in two sessions (a gap in its ids after 4, then 6..9) and
  // robot 'b' in one, each step 1 m: a fleet's bag, or refused where the
  // node could not see a's restart.
  const std::string fleet = Tmp("bag_fleet.g2o"), bag = Tmp("fleet.bag");
  const long long a = static_cast<long long>('a') << 56;
  const long long b = static_cast<long long>('b') << 56;
  {
    std::ofstream f(fleet);
    for (const auto& [robot, ids] :
         {std::pair(a, std::vector<int>{0, 1, 2, 3, 4, 6, 7, 8, 9}),
          std::pair(b, std::vector<int>{0, 1, 2, 3})}) {
      for (size_t k = 0; k < ids.size(); ++k) {
        f << "VERTEX_SE2 " << robot + ids[k] << " " << k << " 0 0\n";
        if (k > 0 && ids[k] == ids[k - 1] + 1) {
          f << "EDGE_SE2 " << robot + ids[k - 1] << " " << robot + ids[k]
            << " 1 0 0 1 0 0 1 0 1\n";
        }
      }
    }
    f << "EDGE_SE2 " << a + 7 << " " << b + 2 << " 0 3 0 1 0 0 1 0 1\n";
  }
  std::remove(bag.c_str());
  const Result r = Rrr("to-bag " + fleet + " --rate 10 -o " + bag);
  ASSERT_EQ(r.status, 0) << r.output;
  // a's keyframes 0-8 (its second session from 5) and b's 0-3 side by side.
  EXPECT_THAT(r.output, HasSubstr("wrote 13 odometry messages of 2 robots "
                                  "(3 sessions) and 1 loop candidates "
                                  "(0.8 s)"));
  EXPECT_TRUE(std::ifstream(bag).good());
  // a's first session ends 4 m from where its odometry starts again.
  const Result hidden =
      Rrr("to-bag " + fleet + " --restart-jump 4 -o " + Tmp("hidden.bag"));
  EXPECT_EQ(hidden.status, 1);
  EXPECT_THAT(hidden.output,
              HasSubstr("robot a's session from pose " + std::to_string(a + 6) +
                        " starts again at zero within --restart-jump"));
  // Time stamps (line k: pose k) must not go back along a robot's poses,
  // whatever the other robots' do: b's start again at 1.
  const std::string stamps = Tmp("bag_fleet_stamps.txt");
  {
    std::ofstream f(stamps);
    for (int k = 0; k < 9; ++k) f << 10 + k << "\n";
    for (int k = 0; k < 4; ++k) f << 1 + k << "\n";
    f << "3.5\n";  // one more than the poses: not read
  }
  EXPECT_EQ(Rrr("to-bag " + fleet + " --timestamps " + stamps + " -o " +
                Tmp("stamped.bag"))
                .status,
            0);
  {
    std::ofstream f(stamps);
    for (int k = 0; k < 13; ++k) f << (k == 11 ? 5 : 10 + k) << "\n";
  }
  const Result back = Rrr("to-bag " + fleet + " --timestamps " + stamps +
                          " -o " + Tmp("stamped.bag"));
  EXPECT_EQ(back.status, 1);
  EXPECT_THAT(back.output,
              HasSubstr(stamps + ":12: time stamps must not "
                                 "decrease along a robot's poses"));
  // A bag holds nothing at time 0.
  {
    std::ofstream f(stamps);
    for (int k = 0; k < 13; ++k) f << k << "\n";
  }
  EXPECT_THAT(Rrr("to-bag " + fleet + " --timestamps " + stamps + " -o " +
                  Tmp("stamped.bag"))
                  .output,
              HasSubstr(stamps + ":1: time stamps must be after 0"));
  // Chains whose ids are not GTSAM symbols are sessions of one robot.
  const std::string sessions = Tmp("bag_sessions.g2o");
  std::ofstream(sessions) << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                             "VERTEX_SE2 2 2 0 0\nVERTEX_SE2 4 0 0 0\n"
                             "VERTEX_SE2 5 1 0 0\n"
                             "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
                             "EDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n"
                             "EDGE_SE2 4 5 1 0 0 1 0 0 1 0 1\n";
  const Result one =
      Rrr("to-bag " + sessions + " --robot r -o " + Tmp("sessions.bag"));
  ASSERT_EQ(one.status, 0) << one.output;
  EXPECT_THAT(one.output, HasSubstr("of 1 robot (2 sessions)"));
}

TEST(RrrTool, NeverWritesOverItsInputOrOneOutputWithAnother) {
  const std::string input = Tmp("precious.g2o");
  Rrr("simulate --poses 200 --false-loops 5 -o " + input + " -t " +
      Tmp("precious_false.txt") + " --ground-truth " + Tmp("precious_gt.g2o"));
  std::stringstream before;
  before << std::ifstream(input).rdbuf();
  ASSERT_FALSE(before.str().empty());
  for (const std::string& outputs :
       {" -o " + input + " -r " + input,
        " -o " + input + " -r " + Tmp("r.json"),
        " -o " + Tmp("same") + " -r " + Tmp("same"),
        " -o " + Tmp("x.g2o") + " -r " + Tmp("no/such/folder/r.json")}) {
    const Result r = Rrr("verify " + input + " -w 10" + outputs);
    EXPECT_EQ(r.status, 1) << outputs;
    EXPECT_THAT(r.output, ::testing::AnyOf(HasSubstr("is also an input"),
                                           HasSubstr("two outputs"),
                                           HasSubstr("does not exist")))
        << r.output;
  }
  std::stringstream after;
  after << std::ifstream(input).rdbuf();
  EXPECT_EQ(after.str(), before.str());
  // The same file by another name is refused too.
  const std::string alias = Tmp("alias.g2o");
  std::remove(alias.c_str());
  ASSERT_EQ(symlink(input.c_str(), alias.c_str()), 0);
  EXPECT_EQ(Rrr("optimize " + input + " -o " + alias).status, 1);
}

}  // namespace
