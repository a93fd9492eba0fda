// The simulator's config is a field table too: the shipped defaults file reads as the built-in
// defaults, and what the table writes reads back as the same values.
#include <string>

#include <gtest/gtest.h>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m::sim {
namespace {

TEST(SimConfigTable, TheShippedDefaultsAreTheBuiltInOnes) {
  const SimConfig file = load_sim_config(std::string(S3M_TEST_DATA_DIR) + "/../../config/sim_default.yaml");
  EXPECT_EQ(config::values(file), config::values(SimConfig{}));
}

TEST(SimConfigTable, WhatIsWrittenReadsBack) {
  SimConfig c;
  c.layout_seed = 11;
  c.trajectory.mount.position_r_m = Vec3(0.2, -0.01, 0.05);
  c.sensor.camera.fx = 382.6;
  c.sensor.noise = false;
  SimConfig back;
  load_sim_config(YAML::Load(config::to_text(config::write(c))), back, "written.yaml");
  EXPECT_EQ(config::values(back), config::values(c));
  EXPECT_EQ(back.layout(), 11u);
  SimConfig d;  // no layout_seed: written as ~, read back as absent
  load_sim_config(YAML::Load(config::to_text(config::write(SimConfig{}))), d, "written.yaml");
  EXPECT_EQ(config::values(d), config::values(SimConfig{}));
  EXPECT_FALSE(d.layout_seed.has_value());
  EXPECT_THROW(load_sim_config(YAML::Load("trajectory: {camera_position_r_m: [1, 2]}"), back, "t.yaml"),
               ParseError);
}

}  // namespace
}  // namespace s3m::sim
