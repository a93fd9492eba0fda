#pragma once
// Short flights for the N-way merge and batch tests: flights A and B of session_sim_fixture.hpp
// (office layout 3) cut to their first kFleetFrames frames, a handheld walk through the same
// office (seed 6) and a flight through another office (layout 5). Runs of them are cached across
// test processes like the session tests' (session_runs.hpp), which also give run C.
#include <filesystem>
#include <map>
#include <string>

#include "s3m/sim/simulate.hpp"
#include "session_runs.hpp"
#include "session_sim_fixture.hpp"

namespace s3m::it {

inline constexpr long kFleetFrames = 100;

inline sim::SimConfig fleet_flight_config(const std::string& trajectory, std::uint64_t layout, int frames) {
  sim::SimConfig c;
  c.scene = "office";
  c.layout_seed = layout;
  c.seed = 6;
  c.trajectory.type = trajectory;
  c.trajectory.frames = frames;
  return c;
}
inline const std::string& flight_handheld_dir() {
  static const std::string d =
      flight_dir(fleet_flight_config("handheld", kSessionLayout, kFleetFrames), "office_l3_handheld_s6");
  return d;
}
// Another building: office layout 5, the figure-eight.
inline const std::string& flight_other_building_dir() {
  static const std::string d = flight_dir(fleet_flight_config("figure8", 5, 80), "office_l5_figure8_s6");
  return d;
}

inline const std::string& fleet_run(const std::string& name) {
  static std::map<std::string, std::string> runs;
  if (!runs.count(name)) {
    if (name == "a")
      runs[name] = cached_merge_run("fleet_a", flight_a_dir(), "", kFleetFrames);
    else if (name == "b")
      runs[name] = cached_merge_run("fleet_b", flight_b_dir(), "", kFleetFrames);
    else if (name == "handheld")
      runs[name] = cached_merge_run("fleet_handheld", flight_handheld_dir());
    else if (name == "c")
      runs[name] = run_c();  // the session tests' (240 frames)
    else
      runs[name] = cached_merge_run("fleet_other_building", flight_other_building_dir());
  }
  return runs.at(name);
}

}  // namespace s3m::it
