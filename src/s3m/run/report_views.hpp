#pragma once
// The report's pictures that come from the run itself rather than from metrics.json: the 3-D map
// viewer (s3m::viewer, into REPORT/viewer/) and the camera views (camera_views.hpp). Written
// before tools/plot_report.py lays out report.html around them.
#include <string>
#include <vector>

#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::run {

// Never throws: like make_report, a missing picture must not lose the run's outputs. Returns
// what could not be made ("" when everything was), for the run's warning.
std::string write_report_views(const pipeline::Pipeline& pipeline, const pipeline::FrameSource& source,
                               const pipeline::PipelineConfig& config, const pipeline::OutputPaths& paths,
                               const std::vector<pipeline::EvalFrame>& camera_frames);

}  // namespace s3m::run
