// summary.html of a batch (summary.hpp): one table of the recordings, one of the merge.
#include <fmt/format.h>

#include "s3m/batch/summary.hpp"

namespace s3m::batch {
using nlohmann::json;

namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string text(const json& j, const char* key) {
  if (!j.contains(key)) return "";
  const json& v = j[key];
  if (v.is_string()) return escape(v.get<std::string>());
  if (v.is_number_float()) return fmt::format("{:.4f}", v.get<double>());
  return escape(v.dump());
}

std::string runs_table(const json& runs) {
  std::string s =
      "<table><tr><th>recording</th><th>status</th><th>frames</th><th>ATE RMSE [m]</th><th>map voxels</th>"
      "<th>map mIoU</th><th>merged map's mIoU there</th><th>mIoU on all runs' "
      "voxels</th><th>error</th></tr>\n";
  for (const json& r : runs) {
    const json map = r.value("map", json::object());
    s += fmt::format(
        "<tr "
        "class=\"{}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</"
        "td>"
        "<td>{}</td></tr>\n",
        r["status"] == "done" ? "ok" : "bad", text(r, "name"), text(r, "status"), text(r, "frames"),
        text(r, "ate_rmse_m"), text(map, "voxels"), text(map, "miou_on_own"), text(map, "merged_miou_on_own"),
        text(map, "miou_on_union"), text(r, "error"));
  }
  return s + "</table>\n";
}

std::string merge_table(const json& merged) {
  std::string s = fmt::format("<p>status: {} {}</p>\n", text(merged, "status"), text(merged, "error"));
  if (!merged.contains("runs")) return s;
  const json map = merged.value("map", json::object());
  s += fmt::format(
      "<p>world: {}; order: {}; map: {} voxels; on the {} ground-truth voxels the runs observed: mIoU {}, "
      "coverage {} (within one voxel); mIoU on its own observed space {}</p>\n",
      text(merged, "world"), text(merged, "order"), text(map, "voxels"),
      text(map, "union_observed_gt_voxels"), text(map, "miou"), text(map, "coverage_of_union"),
      text(map, "miou_own_observed"));
  s += "<table><tr><th>run</th><th>merge</th><th>joined to</th><th>verified "
       "pairs</th><th>agreeing</th></tr>\n";
  for (const json& r : merged["runs"])
    s += fmt::format("<tr class=\"{}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                     r["status"] == "not placed" ? "bad" : "ok", text(r, "name"), text(r, "status"),
                     text(r, "joined_to"), text(r, "verified_pairs"), text(r, "agreeing_pairs"));
  return s + "</table>\n";
}

}  // namespace

std::string summary_html(const json& summary) {
  return fmt::format(
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>s3m batch</title>\n"
      "<style>body{{font-family:sans-serif}} td,th{{padding:2px 8px;border-bottom:1px solid #ccc}} "
      "tr.bad td{{color:#a00}}</style></head><body>\n"
      "<h1>s3m batch: {} recordings, {} not done</h1>\n<p>manifest {}, folder {}</p>\n"
      "<h2>Recordings</h2>\n{}<h2>Merged map</h2>\n{}</body></html>\n",
      text(summary, "recordings"), text(summary, "failed"), text(summary, "manifest"), text(summary, "dir"),
      runs_table(summary["runs"]), merge_table(summary["merged"]));
}

}  // namespace s3m::batch
