// Costmap export as a map_server PGM + YAML pair: grey levels, vertical flip, the YAML keys as
// map_server reads them, and how map_server's trinary mode reads every cost back.
#include "loader/CostmapExport.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <vector>

#include "firmware/mapping/CostValues.hpp"
#include "tests/unit/loader/MapFileTestUtil.hpp"

namespace carril::loader {
namespace {

namespace cost = fw::cost;
using test::fresh_dir;
using test::list_dir;
using test::read_bytes;

// map_server's (ROS 1 and Nav2) trinary reading of a grey, negate 0: occupancy 100, free 0,
// unknown -1.
int map_server_trinary(std::uint8_t grey, double occupied_thresh, double free_thresh) {
  const double occ = (255.0 - grey) / 255.0;
  if (occ > occupied_thresh) return 100;
  if (occ < free_thresh) return 0;
  return -1;
}

TEST(CostmapExport, GreyLevels) {
  EXPECT_EQ(costmap_pgm_grey(cost::kFree), 254);
  EXPECT_EQ(costmap_pgm_grey(1), 253);
  EXPECT_EQ(costmap_pgm_grey(cost::kMaxGraded), 206);
  EXPECT_EQ(costmap_pgm_grey(cost::kInscribed), 0);
  EXPECT_EQ(costmap_pgm_grey(cost::kLethal), 0);
  EXPECT_EQ(costmap_pgm_grey(cost::kUnknown), 205);
  // Costlier is never lighter.
  for (int c = 1; c <= cost::kMaxGraded; ++c) {
    EXPECT_LE(costmap_pgm_grey(static_cast<std::uint8_t>(c)),
              costmap_pgm_grey(static_cast<std::uint8_t>(c - 1)))
        << c;
  }
}

TEST(CostmapExport, MapServerReadsPassableAsFreeBlockedAsOccupiedUnknownAsUnknown) {
  for (int c = 0; c <= 255; ++c) {
    const auto cc = static_cast<std::uint8_t>(c);
    const int occ = map_server_trinary(costmap_pgm_grey(cc), 0.65, 0.196);
    if (cost::passable(cc)) {
      EXPECT_EQ(occ, 0) << "cost " << c;
    } else if (cc == cost::kUnknown) {
      EXPECT_EQ(occ, -1) << "cost " << c;
    } else {
      EXPECT_EQ(occ, 100) << "cost " << c;
    }
  }
}

TEST(CostmapExport, PgmIsFlippedVerticallyWithTheMapServerYaml) {
  const auto dir = fresh_dir();
  // 3 x 2 cells, row-major from the lower-left: row y=0 then row y=1.
  const std::array<std::uint8_t, 6> costs = {
      cost::kFree, cost::kUnknown, cost::kLethal, cost::kInscribed, 126, cost::kFree};
  const CostmapGeometry g{3, 2, 0.05, -1.5, 2.25};
  ASSERT_EQ(export_costmap_pgm((dir / "lab").string(), costs.data(), g), std::nullopt);
  EXPECT_EQ(list_dir(dir), (std::vector<std::string>{"lab.pgm", "lab.yaml"}));

  const std::string pgm = read_bytes(dir / "lab.pgm");
  const std::string header = "P5\n3 2\n255\n";
  ASSERT_EQ(pgm.size(), header.size() + 6);
  EXPECT_EQ(pgm.substr(0, header.size()), header);
  auto px = [&](std::size_t row, std::size_t col) {
    return static_cast<int>(static_cast<unsigned char>(pgm[header.size() + row * 3 + col]));
  };
  // Top image row = the map's highest y (row y=1).
  EXPECT_EQ(px(0, 0), 0);  // inscribed
  EXPECT_EQ(px(0, 1), costmap_pgm_grey(126));
  EXPECT_EQ(px(0, 2), 254);
  EXPECT_EQ(px(1, 0), 254);
  EXPECT_EQ(px(1, 1), 205);  // unknown
  EXPECT_EQ(px(1, 2), 0);    // lethal

  const YAML::Node y = YAML::LoadFile((dir / "lab.yaml").string());
  EXPECT_EQ(y["image"].as<std::string>(), "lab.pgm");  // relative to the YAML file
  EXPECT_EQ(y["mode"].as<std::string>(), "trinary");
  EXPECT_DOUBLE_EQ(y["resolution"].as<double>(), 0.05);
  ASSERT_TRUE(y["origin"].IsSequence());
  ASSERT_EQ(y["origin"].size(), 3U);
  EXPECT_DOUBLE_EQ(y["origin"][0].as<double>(), -1.5);
  EXPECT_DOUBLE_EQ(y["origin"][1].as<double>(), 2.25);
  EXPECT_DOUBLE_EQ(y["origin"][2].as<double>(), 0.0);
  EXPECT_EQ(y["negate"].as<int>(), 0);
  EXPECT_DOUBLE_EQ(y["occupied_thresh"].as<double>(), 0.65);
  EXPECT_DOUBLE_EQ(y["free_thresh"].as<double>(), 0.196);
}

// Issue 46 item 9: a kill between the image and the YAML must leave the old pair whole. The
// export is stopped there as a kill would stop it: the YAML still names an image of its own
// geometry; then the export completes and the new pair replaces it, one image left.
TEST(CostmapExport, AnExportStoppedBetweenImageAndYamlLeavesTheOldPairWhole) {
  const auto dir = fresh_dir();
  const std::string base = (dir / "lab").string();
  const std::vector<std::uint8_t> old_costs(3 * 2, cost::kLethal), new_costs(5 * 4, cost::kFree);
  const CostmapGeometry old_g{3, 2, 0.05, -1.5, 2.25}, new_g{5, 4, 0.1, 0.0, 0.0};
  for (int generation = 0; generation < 3; ++generation) {  // both image names, in turn
    ASSERT_EQ(export_costmap_pgm(base, old_costs.data(), old_g), std::nullopt);
    CostmapImageStep step;
    ASSERT_EQ(write_costmap_image(base, new_costs.data(), new_g, step), std::nullopt);
    // Killed here: the YAML and the image it names are the old pair.
    const YAML::Node y = YAML::LoadFile(base + ".yaml");
    EXPECT_DOUBLE_EQ(y["resolution"].as<double>(), 0.05);
    const std::string image = read_bytes(dir / y["image"].as<std::string>());
    EXPECT_EQ(image.substr(0, 11), "P5\n3 2\n255\n") << generation;
    EXPECT_NE(step.image_path, (dir / y["image"].as<std::string>()).string());
    ASSERT_EQ(commit_costmap_yaml(base, new_g, step), std::nullopt);
    const YAML::Node n = YAML::LoadFile(base + ".yaml");
    EXPECT_DOUBLE_EQ(n["resolution"].as<double>(), 0.1);
    EXPECT_EQ(read_bytes(dir / n["image"].as<std::string>()).substr(0, 11), "P5\n5 4\n255\n");
    EXPECT_EQ(list_dir(dir).size(), 2U);  // the YAML and its image: the old image is gone
  }
}

TEST(CostmapExport, BadInputIsNamed) {
  const auto dir = fresh_dir();
  const std::string base = (dir / "lab").string();
  const std::array<std::uint8_t, 1> one = {0};
  EXPECT_EQ(export_costmap_pgm(base, nullptr, {1, 1, 0.05, 0, 0}),
            base + ".pgm: nothing to export (no costs, or nx 1, ny 1)");
  EXPECT_EQ(export_costmap_pgm(base, one.data(), {0, 1, 0.05, 0, 0}),
            base + ".pgm: nothing to export (no costs, or nx 0, ny 1)");
  const auto nan_res = export_costmap_pgm(base, one.data(), {1, 1, std::nan(""), 0, 0});
  ASSERT_TRUE(nan_res.has_value());
  EXPECT_EQ(nan_res->rfind(base + ".yaml: resolution must be finite and > 0", 0), 0U) << *nan_res;
  EXPECT_TRUE(list_dir(dir).empty());
  const std::string missing = (dir / "no_dir" / "lab").string();
  const auto io = export_costmap_pgm(missing, one.data(), {1, 1, 0.05, 0, 0});
  ASSERT_TRUE(io.has_value());
  EXPECT_EQ(io->rfind(missing + ".pgm: ", 0), 0U) << *io;
}

}  // namespace
}  // namespace carril::loader
