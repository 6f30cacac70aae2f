// `calibench render` and `calibench detect`: rendered frames on disk with their ground truth, and
// the detector's accuracy against it.
//
// render CONFIG --frames DIR writes, for one trial of one scenario with detections: rendered,
//   DIR/frame_000000.png ...   8-bit gray frames at the scenario's frame rate (noise drawn from
//                              (seed, trial, frame) exactly as the rendered source draws it);
//   DIR/corners.csv            frame,time_s,point_id,tag_id,corner,u_px,v_px,in_view: the exact
//                              projection of every tag corner (calibench pixel convention: pixel
//                              centres at integers; corner order of target.h), in_view = 1 when
//                              the whole tag is at least 2 px inside the image and faces the
//                              camera (the tags a detector should find).
// detect CONFIG [--frames DIR] reports the detection rate and the per-corner error against the
//   truth (RMS, mean bias in x and y, p95): on frames rendered in memory, or on DIR's PNGs and
//   corners.csv (e.g. after post-processing them with another tool).
#pragma once

#include <string>

#include "bench/config/scenario.h"
#include "detect/rendered_source.h"

namespace calibench {

struct FramesOptions {
  int trial = 0;
  int max_frames = 0;  // 0: every frame of the scenario's duration.
  // detect --frames: also write every matched corner's error here (CSV: frame, point, u_px, v_px
  // exact, du_px, dv_px, radial_px, tangent_px along the tag's diagonal); empty: none.
  std::string errors_path;
};

// Returns false with *why (file and reason) when the scenario cannot be rendered or DIR written.
bool WriteRenderedFrames(const ScenarioConfig& scenario, const FramesOptions& options,
                         const std::string& dir, int* frames_written, std::string* why);

// frames_dir empty: render in memory. False with *why on unreadable input.
bool DetectFrames(const ScenarioConfig& scenario, const FramesOptions& options,
                  const std::string& frames_dir, DetectionStats* stats, std::string* why);

std::string FormatDetectionStats(const DetectionStats& stats);

}  // namespace calibench
