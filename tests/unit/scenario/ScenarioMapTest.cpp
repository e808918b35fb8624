// The scenario key `map:` (an occupancy map, relative to the scenario file): it loads, a missing
// or broken map fails on the key with the map loader's message, and the start pose must be
// clear of the map's occupied cells.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "firmware/mapping/CostValues.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"
#include "loader/OccupancyMapFile.hpp"
#include "tests/unit/scenario/ScenarioTestUtil.hpp"

namespace carril::sim {
namespace {

namespace fs = std::filesystem;
namespace cost = fw::cost;
using test::kMinimalYaml;

// An empty directory for this test: <temp>/carril_scenario_map_<pid>/<test name>.
fs::path fresh_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("carril_scenario_map_" + std::to_string(::getpid())) / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir / "maps");
  return dir;
}

// A 40 x 30 map at 0.1 m centred on world (0, 0): a wall along its bottom row, free elsewhere.
loader::OccupancyMapData small_map() {
  loader::OccupancyMapData m;
  m.info = {40, 30, 0.1, -2.0, -1.5};
  m.cells.assign(40 * 30, cost::kFree);
  for (int i = 0; i < 40; ++i) m.cells[std::size_t(i)] = cost::kLethal;
  return m;
}

// Writes maps/room.{pgm,yaml} and `scenario` as scn.yaml in `dir`; loads the scenario.
LoadResult load_with_map(const fs::path& dir, const std::string& scenario) {
  EXPECT_EQ(loader::save_occupancy_map((dir / "maps" / "room").string(), small_map()),
            std::nullopt);
  const std::string path = (dir / "scn.yaml").string();
  std::ofstream(path) << scenario;
  return load_scenario(path, test::robots_dir());
}

TEST(ScenarioMap, MapLoadsRelativeToTheScenarioFile) {
  const fs::path dir = fresh_dir();
  const LoadResult r = load_with_map(dir, kMinimalYaml + "map: maps/room.yaml\n");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.scenario.map_path, (dir / "maps" / "room.yaml").string());
  ASSERT_NE(r.scenario.map, nullptr);
  EXPECT_EQ(r.scenario.map->info.nx, 40);
  EXPECT_EQ(r.scenario.map->info.ny, 30);
  EXPECT_EQ(r.scenario.map->info.origin_x_m, -2.0);
  EXPECT_EQ(r.scenario.map->cells, small_map().cells);
  // Without the key: no map.
  const LoadResult none = load_with_map(dir, kMinimalYaml);
  ASSERT_TRUE(none.ok) << none.error;
  EXPECT_EQ(none.scenario.map, nullptr);
  EXPECT_TRUE(none.scenario.map_path.empty());
}

TEST(ScenarioMap, ShippedMapFromTheScenariosFolder) {
  // As a scenario in scenarios/ names it (the text is never written there).
  const std::string path = std::string(CARRIL_SOURCE_DIR) + "/scenarios/house_test.yaml";
  const LoadResult r =
      load_scenario_text(kMinimalYaml + "map: maps/house.yaml\n", path, test::robots_dir());
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_NE(r.scenario.map, nullptr);
  EXPECT_EQ(r.scenario.map->info.nx, 210);
  EXPECT_EQ(r.scenario.map->info.ny, 170);
}

TEST(ScenarioMap, MissingMapFailsOnTheKey) {
  const fs::path dir = fresh_dir();
  const LoadResult r = load_with_map(dir, kMinimalYaml + "map: maps/gone.yaml\n");
  ASSERT_FALSE(r.ok);
  const std::string scn = (dir / "scn.yaml").string();
  EXPECT_EQ(r.error, scn + ":7: map: cannot load the map: " +
                         (dir / "maps" / "gone.yaml").string() + ": cannot open");
}

TEST(ScenarioMap, BrokenMapPassesOnTheMapLoadersMessage) {
  const fs::path dir = fresh_dir();
  std::ofstream((dir / "maps" / "bad.pgm").string()) << "GIF89a";
  std::ofstream((dir / "maps" / "bad.yaml").string())
      << "image: bad.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
         "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  const LoadResult r = load_with_map(dir, kMinimalYaml + "map: maps/bad.yaml\n");
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.error,
            (dir / "scn.yaml").string() +
                ":7: map: cannot load the map: " + (dir / "maps" / "bad.yaml").string() +
                ":1: image: " + (dir / "maps" / "bad.pgm").string() +
                ": not a PGM image (it looks like a GIF file, expected the magic P5 or P2)");
}

TEST(ScenarioMap, MapBiggerThanTheSimulatorsLimit) {
  // 1001 x 1000 cells: refused on the header, before any pixel is read.
  const fs::path dir = fresh_dir();
  std::ofstream((dir / "maps" / "big.pgm").string()) << "P5 1001 1000 255\n";
  std::ofstream((dir / "maps" / "big.yaml").string())
      << "image: big.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
         "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  const LoadResult r = load_with_map(dir, kMinimalYaml + "map: maps/big.yaml\n");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find(":7: map: cannot load the map: "), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("1001 x 1000 = 1001000 cells, more than the 1000000 cells the map "
                         "buffer holds"),
            std::string::npos)
      << r.error;
}

TEST(ScenarioMap, MapMustBeAFileName) {
  const fs::path dir = fresh_dir();
  LoadResult r = load_with_map(dir, kMinimalYaml + "map: [maps/room.yaml]\n");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find(":7: map: expected a string, got a list"), std::string::npos) << r.error;
  r = load_with_map(dir, kMinimalYaml + "map: \"\"\n");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find(":7: map: expected a map file (ROS map_server YAML), got an empty string"),
            std::string::npos)
      << r.error;
}

// Issue 46 item 8: where a kidnap puts the robot down is checked as its start is.
TEST(ScenarioMap, AKidnapPoseMustBeClearAsAStartIs) {
  const fs::path dir = fresh_dir();
  const std::string yaml =
      test::edit(kMinimalYaml, "robot: {preset: pioneer3at}",
                 "robot: {preset: pioneer3at, start: {x: 0.3, y: -0.5, yaw_deg: 0}}") +
      "map: maps/room.yaml\nlocalisation:\n  kidnap:\n    - {t_s: 5, x: 0.3, y: -1.1, yaw_deg: "
      "0}\n";
  const LoadResult ok = load_with_map(dir, yaml);
  EXPECT_TRUE(ok.ok) << ok.error;
  const LoadResult r = load_with_map(dir, test::edit(yaml, "y: -1.1", "y: -1.2"));
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find(":10: localisation.kidnap[0]: expected a kidnap pose whose pioneer3at "
                         "footprint (0.508 x 0.497 m) is clear of the map's occupied cells, got "
                         "x 0.3, y -1.2, yaw_deg 0"),
            std::string::npos)
      << r.error;
}

TEST(ScenarioMap, StartMustBeClearOfOccupiedCells) {
  // The wall is the bottom row, y -1.5..-1.4. A Pioneer 3-AT (0.508 x 0.497 m) at y -1.1 reaches
  // down to -1.3485: clear; at y -1.2 down to -1.4485: on the wall.
  const fs::path dir = fresh_dir();
  const std::string yaml =
      test::edit(kMinimalYaml, "robot: {preset: pioneer3at}",
                 "robot: {preset: pioneer3at, start: {x: 0.3, y: -1.1, yaw_deg: 0}}") +
      "map: maps/room.yaml\n";
  const LoadResult ok = load_with_map(dir, yaml);
  EXPECT_TRUE(ok.ok) << ok.error;
  const LoadResult r = load_with_map(dir, test::edit(yaml, "y: -1.1", "y: -1.2"));
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find(":3: robot.start: expected a start pose whose pioneer3at footprint "
                         "(0.508 x 0.497 m) is clear of the map's occupied cells, got x 0.3, "
                         "y -1.2, yaw_deg 0 (overlaps occupied cell ("),
            std::string::npos)
      << r.error;
  // The map was saved twice over the same name: its image alternates (docs/map-formats.md).
  EXPECT_NE(r.error.find(", y -1.45 of " + (dir / "maps" / "room.next.pgm").string()),
            std::string::npos)
      << r.error;
}

}  // namespace
}  // namespace carril::sim
