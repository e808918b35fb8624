// The campaign report: Wilson intervals against published values; failure modes grouped; the
// perturbation whose values fail runs ranked first; the worst runs ordered crash, failure, pass,
// each with a replay command.
#include "host_sim/campaign/Report.hpp"

#include <gtest/gtest.h>

#include <string>

namespace carril::sim::campaign {
namespace {

TEST(ReportTest, WilsonIntervalsMatchPublishedValues) {
  // Wilson 1927 / Newcombe 1998 (method 3): 81/263 -> [0.2553, 0.3662]; 0/10 -> [0, 0.2775].
  Interval ci = wilson95(81, 263);
  EXPECT_NEAR(ci.lo, 0.2553, 5e-4);
  EXPECT_NEAR(ci.hi, 0.3662, 5e-4);
  ci = wilson95(0, 10);
  EXPECT_NEAR(ci.lo, 0.0, 1e-9);
  EXPECT_NEAR(ci.hi, 0.2775, 5e-4);
  ci = wilson95(10, 10);
  EXPECT_NEAR(ci.lo, 0.7225, 5e-4);
  EXPECT_NEAR(ci.hi, 1.0, 1e-9);
  ci = wilson95(0, 0);
  EXPECT_EQ(ci.lo, 0.0);
  EXPECT_EQ(ci.hi, 0.0);
}

RunRow row(std::uint64_t i, const std::string& status, double slip, double noise, double rms,
           const std::string& result = "end_reached", const std::string& unmet = "") {
  RunRow r;
  r.index = i;
  r.base_name = "corners";
  r.preset = "pioneer3at";
  r.strategy = "pid";
  r.status = status;
  r.values = {slip, noise};
  if (status != "signal 11") {
    r.fields = {{"result", result},
                {"final_state", "END"},
                {"fault", ""},
                {"cross_track_rms_m", std::to_string(rms)},
                {"unmet_expectations", unmet}};
  }
  return r;
}

TEST(ReportTest, FailuresAreGroupedRankedAndReplayable) {
  CampaignSpec spec;
  spec.name = "t";
  spec.path = "t.yaml";
  spec.variants = 20;
  spec.scenarios = {"corners.yaml"};
  spec.perturbations = {{"wheel_slip", {}}, {"camera_noise", {}}};
  ResultsTable t;
  t.ok = true;
  // Slip above 0.04 fails (missing the stop); camera noise does not matter.
  for (std::uint64_t i = 0; i < 20; ++i) {
    const double slip = 0.0025 * double(i);
    const double noise = double((i * 7) % 10);
    if (slip > 0.04) {
      t.rows.push_back(row(i, "exit 1", slip, noise, 0.02 + slip, "time_limit",
                           "end_reached: expected true, got false"));
    } else {
      t.rows.push_back(row(i, "exit 0", slip, noise, 0.01));
    }
  }
  t.rows.push_back(row(20, "signal 11", 0.0, 1.0, 0.0));
  const std::string md = report_markdown(spec, t, "/out", "carril_sim");
  // 17 of 21 passed.
  EXPECT_NE(md.find("**Pass rate: 81.0 %"), std::string::npos) << md;
  // Failure modes: 3 that timed out missing the end, 1 crash.
  EXPECT_NE(md.find("| time_limit, final state END | `end_reached` | 3 | 17 |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| crashed (signal 11) | - | 1 | 20 |"), std::string::npos) << md;
  // wheel_slip ranks above camera_noise.
  const std::size_t slip = md.find("| `wheel_slip` |"), noise = md.find("| `camera_noise` |");
  ASSERT_NE(slip, std::string::npos) << md;
  ASSERT_NE(noise, std::string::npos) << md;
  EXPECT_LT(slip, noise);
  // Worst runs: the crash, then the failures by cross-track RMS (19 worst), each replayable.
  const std::size_t worst = md.find("## The worst runs");
  const std::size_t crash = md.find("| 20 | corners", worst),
                    fail19 = md.find("| 19 | corners", worst),
                    fail17 = md.find("| 17 | corners", worst);
  ASSERT_NE(crash, std::string::npos);
  EXPECT_LT(crash, fail19);
  EXPECT_LT(fail19, fail17);
  EXPECT_NE(md.find("`carril_sim --scenario /out/runs/000019/scenario.yaml --view`"),
            std::string::npos)
      << md;
}

TEST(ReportTest, APartialCampaignSaysSo) {
  CampaignSpec spec;
  spec.name = "t";
  spec.path = "t.yaml";
  spec.variants = 4;
  spec.scenarios = {"corners.yaml"};
  ResultsTable t;
  t.ok = true;
  t.missing = 3;
  t.rows.push_back(row(0, "exit 0", 0.0, 0.0, 0.01));
  t.rows[0].values.clear();
  const std::string md = report_markdown(spec, t, "/out", "carril_sim");
  EXPECT_NE(md.find("3 not yet: this report is partial"), std::string::npos) << md;
  EXPECT_NE(md.find("The campaign perturbs nothing."), std::string::npos) << md;
}

}  // namespace
}  // namespace carril::sim::campaign
