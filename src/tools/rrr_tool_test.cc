// The rrr program as a user runs it: exit codes, messages and outputs.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

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
  const Result r = Rrr("optimize " + gap + " -o " + Tmp("o.g2o"));
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output, HasSubstr("pose 2 has no odometry edge to pose 1"));
}

TEST(RrrTool, BadOptionIsNamed) {
  const Result r = Rrr("simulate --poses 10 -o " + Tmp("w.g2o") + " -t " +
                       Tmp("f.txt") + " --ground-truth " + Tmp("t.g2o"));
  EXPECT_NE(r.status, 0);
  EXPECT_THAT(r.output, HasSubstr("poses must be at least 100"));
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
}

}  // namespace
