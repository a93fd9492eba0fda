#pragma once
// The interactive 3-D view of a semantic map: a folder that opens from file:// with no server and
// no network, so it can be zipped and mailed. It holds
//   index.html       the viewer alone (`s3m view`); report.html embeds the same scripts
//   map_data.js      the scene (viewer_data.hpp) as `window.S3M_VIEWER_DATA = {...};` (a script,
//                    not fetched JSON: Chromium refuses fetch() of file:// URLs)
//   viewer_voxels.js, viewer.js, viewer_pick.js, viewer.css: the viewer's own code, copied from the
//                    repository's tools/viewer/
//   three.min.js, OrbitControls.js   three.js r111 copied from Debian's libjs-three (and its
//                    licence notice, three.js-LICENSE.txt)
// When three.js is not installed the data and our files are still written, and the page says that
// the 3-D view needs libjs-three.
#include <string>

#include "s3m/mapping/semantic_octree.hpp"
#include "s3m/viewer/viewer_data.hpp"

namespace s3m::viewer {

struct ViewerFolder {
  std::string dir;
  std::string index_html;   // path of the standalone page
  bool have_three = false;  // three.js was found and copied
  std::string note;         // what is missing, when something is
};

// $S3M_THREE_DIR, else Debian's /usr/share/javascript/three; empty when three.min.js is not there.
std::string find_three_dir();
// $S3M_TOOLS_DIR/viewer, else the shipped tools/viewer (s3m/core/shipped_files.hpp); throws s3m::Error when not found.
std::string find_viewer_assets();

// Writes (atomically, file by file) the folder described above. Throws s3m::Error naming the file
// when something cannot be written or the viewer's own files are missing.
ViewerFolder write_viewer(const mapping::SemanticOcTree& map, const SceneExtras& extras, const std::string& dir);

// A saved map and its trajectories, for `s3m view` and the run report.
struct ViewInputs {
  std::string map;         // .ot written by s3m (any version the loader accepts, or the ROS node)
  std::string trajectory;  // camera trajectory, TUM or KITTI; empty = none
  std::string keyframes;   // keyframe poses, TUM; empty = none
  std::optional<PinholeCamera> camera;
  std::string out_dir;     // the viewer folder
};
// Loads with mapping::load_semantic_map (the same loader and errors as `s3m query`) and the
// trajectory readers, then write_viewer(). Throws s3m::Error / ParseError naming the bad file.
ViewerFolder view_map_file(const ViewInputs& in);

}  // namespace s3m::viewer
