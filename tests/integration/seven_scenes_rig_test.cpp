// A folder as Microsoft 7-Scenes gives one: the depth images are a Kinect v1's depth camera's
// (585 px), 2.5 cm beside a 529 px colour camera, and camera.yaml holds only the dataset's one set
// of intrinsics (585 px). `s3m run` without a preset finds the depth unregistered, recognises the
// intrinsics and draws the depth into the colour camera with the rig (camera preset
// 7scenes_kinect_v1); the same folder read as one camera (dataset.depth_registration: unregistered)
// tracks far worse. Rendered with the rig's exact cameras, so the truth is exact.
#include <nlohmann/json.hpp>

#include "pipeline_fixture.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/depth_to_colour.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/tum_dataset.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

constexpr int kRigFrames = 40;

// The fixture's flight (office, hand-held, seed 7) seen by the rig's colour camera.
const std::string& colour_flight_dir() {
  static const std::string dir =
      cached_folder(fs::temp_directory_path() /
                        ("s3m_it_sequence_office_handheld_seed7_kinect529_" + std::to_string(kRigFrames)),
                    "gt_voxels.txt", [](const fs::path& tmp) {
                      sim::SimConfig c = sequence_config();
                      c.trajectory.frames = kRigFrames;
                      c.sensor.camera = io::load_camera_file("7scenes_kinect_v1").camera;
                      sim::simulate_sequence(c, tmp.string());
                    });
  return dir;
}

// The flight with its depth images redrawn in the depth camera and 7-Scenes' camera.yaml.
std::string seven_scenes_folder() {
  // Without sim.yaml: a folder of a camera, not of the simulator.
  const fs::path dir = linked_copy(
      "seven_scenes_rig",
      [](const fs::path& rel) {
        return rel.parent_path() == "depth" || rel == "camera.yaml" || rel == "sim.yaml";
      },
      colour_flight_dir());
  const io::TumDataset flight = io::TumDataset::open(colour_flight_dir());
  const io::CameraFile rig = io::load_camera_file("7scenes_kinect_v1");
  const io::DepthToColour to_depth_camera(flight.camera(), rig.depth->camera, rig.depth->T_c_d.inverse());
  for (std::size_t i = 0; i < flight.size(); ++i)
    io::write_depth_png((dir / flight.entries()[i].depth).string(), to_depth_camera(flight.load(i).depth_m),
                        rig.depth->camera.depth_factor);
  io::write_camera_yaml((dir / "camera.yaml").string(), *camera_preset("7scenes"));
  return dir.string();
}

run::RunOptions slam_run(const std::string& name, const std::string& dir) {
  run::RunOptions o = options(name, true);
  o.dataset_dir = dir;
  o.slam_only = true;
  // As `s3m run DIR` without a preset: no camera written (sim.yaml's "", the folder's own camera,
  // is a camera the config writes, which the rig would not replace).
  o.config.dataset.camera = "";
  o.config.written.erase("dataset.camera");
  o.config.dataset.depth_registration = "auto";
  return o;
}

double ate_m(const run::RunResult& r) { return r.metrics["trajectory"]["ate_rmse_m"].get<double>(); }

TEST(SevenScenesRig, UnregisteredKinectDepthIsDrawnInWithTheRigAndTracksAsRegisteredDepth) {
  const std::string dir = seven_scenes_folder();
  const run::RunResult registered = run::run_dataset(slam_run("rig_registered", colour_flight_dir()));
  const run::RunResult found = run::run_dataset(slam_run("rig_found", dir));
  run::RunOptions one = slam_run("rig_one_camera", dir);
  one.config.dataset.depth_registration = "unregistered";
  const run::RunResult one_camera = run::run_dataset(one);

  const std::string why = found.metrics["inputs"]["depth_registration"].get<std::string>();
  EXPECT_EQ(why.rfind("not registered", 0), 0u) << why;
  EXPECT_NE(why.find("camera preset 7scenes_kinect_v1"), std::string::npos) << why;
  for (const auto* r : {&registered, &found}) {
    EXPECT_EQ(r->metrics["tracked"].get<int>(), kRigFrames);
    EXPECT_EQ(r->metrics["tracking"]["states"].value("LOST", 0), 0) << r->metrics["tracking"].dump();
  }
  std::cout << "ATE registered " << ate_m(registered) * 100 << " cm, drawn in with the rig "
            << ate_m(found) * 100 << " cm, read as one 585 px camera " << ate_m(one_camera) * 100 << " cm\n";
  // Drawn into the depth camera by the test and back by s3m: the depth moves by up to a pixel.
  EXPECT_LT(ate_m(found), ate_m(registered) + 0.001);
  // As one camera the colour pixels are read at a 10 % wrong focal length, with depth ~8 px off.
  EXPECT_GT(ate_m(one_camera), 3 * ate_m(found));
}

}  // namespace
}  // namespace s3m::it
