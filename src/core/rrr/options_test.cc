#include "rrr/rrr/options.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace rrr {
namespace {

TEST(OptionsText, ReadsBackEveryOptionExactly) {
  RrrOptions o;
  o.procedure = Procedure::kPublished;
  o.cluster_window = 50;
  o.steps = SolveSteps::kTrustRegion;
  o.alpha = 0.1 + 0.2;  // not exact in decimal
  o.span_gate = true;
  o.noise_scale = 1.0 / 3.0;
  o.map_radius = 9;
  o.convergence.relative_decrease = 1e-7;
  const RrrOptions back = ParseOptionsText(OptionsText(o));
  EXPECT_EQ(OptionsText(back), OptionsText(o));
  EXPECT_EQ(back.procedure, Procedure::kPublished);
  EXPECT_EQ(back.cluster_window, 50);
  EXPECT_EQ(back.steps, SolveSteps::kTrustRegion);
  EXPECT_EQ(back.alpha, o.alpha);
  EXPECT_TRUE(back.span_gate);
  EXPECT_EQ(back.noise_scale, o.noise_scale);
  EXPECT_EQ(back.convergence.relative_decrease, 1e-7);
  // A name it does not list keeps its default.
  EXPECT_EQ(ParseOptionsText("cluster_window=7").map_radius,
            RrrOptions().map_radius);
}

TEST(OptionsText, RefusesWhatIsNotAnOptionNamingIt) {
  const auto error = [](const std::string& text) {
    try {
      ParseOptionsText(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("cluster_window").find("'cluster_window' is not name=value"),
            std::string::npos);
  EXPECT_NE(error("windy=1").find("unknown option windy"), std::string::npos);
  EXPECT_NE(error("cluster_window=ten").find("cluster_window=ten"),
            std::string::npos);
  EXPECT_NE(error("procedure=best").find("procedure=best"), std::string::npos);
}

}  // namespace
}  // namespace rrr
